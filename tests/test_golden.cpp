// Golden streams (spec/FORMAT.md §6): streams of format 7.0 (layers that
// send points beside the coarser level's candidates: ellipsoid_793, a TetGen
// mesh; the torus's layers send none; the paper preset's, without
// corrections, are 5.0), the torus's with the input's TetGen markers as a
// field, and of 6.0 (carving corrections with 6.0's contexts), 5.0, 4.0
// (carving corrections, and the paper's alpha carving), 3.0 and 2.0
// (golden/v6/ to v2/, which this decoder still reads), that every later
// decoder must decode to the same levels and values, and whose every damaged
// variant it must refuse.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <iterator>
#include <map>
#include <nlohmann/json.hpp>

#include "codec/decode.h"
#include "codec/stream/format.h"
#include "test_support.h"
#include "tools/decoded_mesh.h"
#include "tools/formats/input.h"
#include "tools/formats/tetgen.h"

namespace dtm {
namespace {

std::vector<uint8_t> read_bytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), {}};
}

std::string golden(const std::string& name) { return std::string(DTM_TEST_SOURCE_DIR) + "/golden/" + name; }

std::string hex(uint64_t v) {
  char buf[17];
  std::snprintf(buf, sizeof buf, "%016llx", static_cast<unsigned long long>(v));
  return buf;
}

// The sum over k of (k + 1) x the k-th value's bits in its own type's width
// (a negative integer's are sign-extended in FieldValues), modulo 2^64.
uint64_t bits_checksum(const FieldValues& f) {
  constexpr int kBytes[] = {1, 1, 2, 2, 4, 4, 8, 8, 4, 8};
  const int bytes = kBytes[static_cast<int>(f.description.type)];
  const uint64_t mask = bytes == 8 ? ~uint64_t{0} : (uint64_t{1} << (8 * bytes)) - 1;
  uint64_t sum = 0;
  for (size_t k = 0; k < f.bits.size(); ++k) sum += (k + 1) * (f.bits[k] & mask);
  return sum;
}

class GoldenStream : public ::testing::TestWithParam<std::string> {};

TEST_P(GoldenStream, DecodesToTheRecordedLevels) {
  const auto bytes = read_bytes(golden(GetParam() + ".dtm"));
  ASSERT_FALSE(bytes.empty());
  std::ifstream expected_file(golden(GetParam() + ".expected.json"));
  const auto expected = nlohmann::json::parse(expected_file);
  size_t index = 0;
  ProgressiveDecoder dec;
  ASSERT_TRUE(
      dec.feed(bytes,
               [&](const ProgressiveDecoder& d, const DecodedLevel& l) {
                 ASSERT_LT(index, expected["levels"].size());
                 const auto& want = expected["levels"][index++];
                 EXPECT_EQ(l.level, want["level"].get<int>());
                 EXPECT_EQ(l.vertices, want["vertices"].get<uint32_t>());
                 if (want.contains("new_vertices")) {
                   const size_t coarser =
                       d.levels().size() >= 2 ? d.levels()[d.levels().size() - 2].vertices : 0;
                   EXPECT_EQ(l.vertices - coarser, want["new_vertices"].get<uint32_t>());
                 }
                 EXPECT_EQ(hex(level_cell_hash(d.header().flags, d.points(), d.carved_cells())),
                           want["cell_hash"].get<std::string>())
                     << GetParam() << " level " << l.level;
                 // 10.0: level 0's cell arrays, each as its count and
                 // the sum of (k + 1) x its k-th value's bits (tests/golden/make.sh).
                 if (want.contains("cell_data")) {
                   const ProgressiveDecoder::LevelCells level = d.level_cells();
                   const std::vector<FieldValues> values = d.cell_data(level.mesh, level.kept, level.order);
                   ASSERT_EQ(values.size(), want["cell_data"].size());
                   for (const FieldValues& f : values) {
                     ASSERT_TRUE(want["cell_data"].contains(f.description.name)) << f.description.name;
                     const auto& w = want["cell_data"][f.description.name];
                     EXPECT_EQ(f.bits.size(), w["values"].get<size_t>());
                     EXPECT_EQ(hex(bits_checksum(f)), w["checksum"].get<std::string>()) << f.description.name;
                   }
                 }
                 // 18.0: level 0's edge nodes, their count, the moved ones'
                 // and a checksum of their places in the section's order
                 // (tests/golden/make.sh).
                 if (want.contains("edge_nodes")) {
                   const ProgressiveDecoder::LevelCells level = d.level_cells();
                   const ProgressiveDecoder::EdgeNodes nodes = d.edge_nodes(level);
                   ASSERT_TRUE(d.mesh_status().ok()) << d.mesh_status().message();
                   const auto& w = want["edge_nodes"];
                   uint64_t count = 0, moved = 0, sum = 0;
                   for (size_t e = 0; e < nodes.present.size(); ++e) {
                     if (!nodes.present[e]) continue;
                     const GridPoint &a = d.points()[nodes.edges.corners[e][0]],
                                     &b = d.points()[nodes.edges.corners[e][1]];
                     const auto& x = nodes.points[e];
                     moved += 2 * x[0] != a.x + b.x || 2 * x[1] != a.y + b.y || 2 * x[2] != a.z + b.z;
                     const auto twice = [](double v) { return static_cast<uint64_t>(std::llround(2 * v)); };
                     sum += ++count * (twice(x[0]) + 3 * twice(x[1]) + 5 * twice(x[2]));
                   }
                   EXPECT_EQ(count, w["nodes"].get<uint64_t>());
                   EXPECT_EQ(moved, w["moved"].get<uint64_t>());
                   EXPECT_EQ(hex(sum), w["checksum"].get<std::string>());
                 }
                 // 19.0: each field's values at level 0's edge nodes, their
                 // count and checksum as cell_data's (tests/golden/make.sh).
                 if (want.contains("edge_values")) {
                   const ProgressiveDecoder::LevelCells level = d.level_cells();
                   const ProgressiveDecoder::EdgeNodes nodes = d.edge_nodes(level);
                   ASSERT_TRUE(d.mesh_status().ok()) << d.mesh_status().message();
                   ASSERT_EQ(nodes.values.size(), want["edge_values"].size());
                   for (const FieldValues& f : nodes.values) {
                     ASSERT_TRUE(want["edge_values"].contains(f.description.name)) << f.description.name;
                     const auto& w = want["edge_values"][f.description.name];
                     EXPECT_EQ(f.bits.size(), w["values"].get<size_t>());
                     EXPECT_EQ(hex(bits_checksum(f)), w["checksum"].get<std::string>()) << f.description.name;
                   }
                 }
                 // 21.0: level 0's vertices and edge nodes in the input's
                 // numbering, their count and a checksum of their places in
                 // that order (tests/golden/make.sh).
                 if (want.contains("numbered_nodes")) {
                   const OutputMesh mesh = decoded_mesh(d, GetParam(), true);
                   uint64_t sum = 0;
                   for (size_t k = 0; k < mesh.points.size(); ++k) {
                     const GridPoint& p = mesh.points[k];
                     sum +=
                         (k + 1) * static_cast<uint64_t>(int64_t{p.x} + 3 * int64_t{p.y} + 5 * int64_t{p.z});
                   }
                   EXPECT_EQ(mesh.points.size(), want["numbered_nodes"]["nodes"].get<uint64_t>());
                   EXPECT_EQ(hex(sum), want["numbered_nodes"]["checksum"].get<std::string>());
                 }
                 // 22.0: the input's node ids in its numbering, their count
                 // and the sum of (k + 1) x the k-th (tests/golden/make.sh).
                 if (want.contains("node_labels")) {
                   const OutputMesh mesh = decoded_mesh(d, GetParam(), true);
                   uint64_t sum = 0;
                   for (size_t k = 0; k < mesh.node_labels.size(); ++k)
                     sum += (k + 1) * static_cast<uint64_t>(mesh.node_labels[k]);
                   EXPECT_EQ(mesh.node_labels.size(), want["node_labels"]["nodes"].get<uint64_t>());
                   EXPECT_EQ(hex(sum), want["node_labels"]["checksum"].get<std::string>());
                 }
                 // 9.0: the level's cells per region label.
                 if (!want.contains("region_cells")) return;
                 // (An exact level 0's cells are more than DT's: level_cells().)
                 const ProgressiveDecoder::LevelCells level = d.level_cells();
                 std::map<std::string, uint64_t> cells;
                 for (uint8_t r : level.kept)
                   if (r) ++cells[std::to_string(d.regions()[r - 1u].label)];
                 for (const auto& [label, count] : want["region_cells"].items())
                   EXPECT_EQ(cells[label], count.get<uint64_t>()) << GetParam() << " level " << l.level;
                 EXPECT_EQ(cells.size(), want["region_cells"].size());
                 if (!want.contains("tagged_faces")) return;
                 SurfaceFaces surface;
                 std::map<std::string, uint64_t> faces;
                 for (uint8_t t : d.face_tags(level.mesh, level.kept, surface))
                   if (t >= 2) ++faces[std::to_string(d.face_tag_table()[t - 2u].label)];
                 for (const auto& [tag, count] : want["tagged_faces"].items())
                   EXPECT_EQ(faces[tag], count.get<uint64_t>()) << GetParam() << " level " << l.level;
                 EXPECT_EQ(faces.size(), want["tagged_faces"].size());
               })
          .ok());
  EXPECT_TRUE(dec.finish().ok());
  EXPECT_EQ(index, expected["levels"].size());
  EXPECT_EQ(dec.header().grid.qbits, expected["qbits"].get<int>());
  EXPECT_EQ(dec.header().vertex_count, expected["vertices"].get<uint32_t>());
  ASSERT_TRUE(expected.contains("format"));
  EXPECT_EQ(
      "dtm " + std::to_string(dec.header().version_major) + "." + std::to_string(dec.header().version_minor),
      expected["format"].get<std::string>());
}

// Every byte is under a checksum, so any single flipped bit must be refused;
// a decoder may stop early but must never return a wrong level as valid.
TEST_P(GoldenStream, EverySingleBitFlipIsRefused) {
  const auto bytes = read_bytes(golden(GetParam() + ".dtm"));
  for (size_t i = 0; i < bytes.size(); ++i)
    for (int b = 0; b < 8; ++b) {
      auto damaged = bytes;
      damaged[i] ^= static_cast<uint8_t>(1 << b);
      ProgressiveDecoder dec;
      const Status s = dec.feed(damaged);
      ASSERT_FALSE(s.ok() && dec.finish().ok()) << "flip of bit " << b << " of byte " << i;
      EXPECT_FALSE(scan_stream(damaged).status.ok());
    }
}

// The torus's 8.0 (bricked), 7.0, 6.0 and 5.0 streams carry the input's boundary markers: every vertex
// of every level has the marker of the input point it quantizes (found by
// position, the stream's grid mapped onto the input's bounding box).
TEST(GoldenValues, EveryVertexCarriesItsInputPointsMarker) {
  for (const std::string name :
       {"torus_288_bricks", "torus_288", "torus_288_paper", "torus_288_grid_q10_hull", "torus_288_q24",
        "v6/torus_288", "v6/torus_288_paper", "v6/torus_288_grid_q10_hull", "v6/torus_288_q24",
        "v5/torus_288", "v5/torus_288_paper", "v5/torus_288_grid_q10_hull", "v5/torus_288_q24"}) {
    const InputMesh in = read_input(
        test::data_path(name.find("grid") != std::string::npos ? "torus_288_grid.node" : "torus_288.node"));
    const VertexField& markers = in.fields.at(0);
    ASSERT_EQ(markers.name, "boundary_marker");
    ProgressiveDecoder dec;
    ASSERT_TRUE(decode_stream(read_bytes(golden(name + ".dtm")), dec).ok()) << name;
    ASSERT_EQ(dec.fields().size(), 1u) << name;
    const FieldValues& f = dec.fields()[0];
    EXPECT_EQ(f.description.name, "boundary_marker");
    EXPECT_EQ(f.description.type, ValueType::kI32);
    EXPECT_FALSE(f.description.lossy);
    // The affine map from input units to the decoded ones: per axis, the boxes' corners.
    std::array<double, 3> in_lo{1e300, 1e300, 1e300}, in_hi{-1e300, -1e300, -1e300}, lo = in_lo, hi = in_hi;
    auto grow = [](std::array<double, 3>& l, std::array<double, 3>& h, const InputPoint& p) {
      const double c[3] = {p.x, p.y, p.z};
      for (int a = 0; a < 3; ++a) l[a] = std::min(l[a], c[a]), h[a] = std::max(h[a], c[a]);
    };
    for (const InputPoint& p : in.points) grow(in_lo, in_hi, p);
    std::vector<InputPoint> decoded;
    for (const GridPoint& g : dec.points()) decoded.push_back(dec.header().grid.to_input(g));
    for (const InputPoint& p : decoded) grow(lo, hi, p);
    for (size_t v = 0; v < decoded.size(); ++v) {
      const double c[3] = {decoded[v].x, decoded[v].y, decoded[v].z};
      size_t best = 0;
      double best_d = 1e300;
      for (size_t i = 0; i < in.points.size(); ++i) {
        const double ic[3] = {in.points[i].x, in.points[i].y, in.points[i].z};
        double d = 0;
        for (int a = 0; a < 3; ++a) {
          const double t = in_lo[a] + (c[a] - lo[a]) / (hi[a] - lo[a]) * (in_hi[a] - in_lo[a]);
          d += (t - ic[a]) * (t - ic[a]);
        }
        if (d < best_d) best_d = d, best = i;
      }
      EXPECT_EQ(f.value(v, 0), markers.values[best]) << name << " vertex " << v;
    }
  }
}

INSTANTIATE_TEST_SUITE_P(Format9_0, GoldenStream, ::testing::Values("two_materials"));
INSTANTIATE_TEST_SUITE_P(Format10_0, GoldenStream, ::testing::Values("torus_288_cells"));
// 15.0: the gmsh part's regions in bricked layers, a region section a chunk.
INSTANTIATE_TEST_SUITE_P(Format15_0, GoldenStream, ::testing::Values("two_materials_bricks"));
// 16.0: the torus's cell data in bricked layers, a cell value section in
// each of level 0's chunks.
INSTANTIATE_TEST_SUITE_P(Format16_0, GoldenStream, ::testing::Values("torus_288_cells_bricks"));
// 17.0: the gmsh part's tagged faces in bricked layers, a face section in
// each chunk.
INSTANTIATE_TEST_SUITE_P(Format17_0, GoldenStream, ::testing::Values("two_materials_bricks_faces"));
// 18.0: a second-order gmsh ball's own 10-node tetrahedra, their edge nodes
// in an edge node section.
INSTANTIATE_TEST_SUITE_P(Format18_0, GoldenStream, ::testing::Values("v18/ball_order2_exact"));
// 19.0: the same ball, its nodes coded from the surface's prediction, and
// with a float64 and an int32 field at every node, the nodes' values in an
// edge value section.
INSTANTIATE_TEST_SUITE_P(Format19_0, GoldenStream,
                         ::testing::Values("v19/ball_order2_exact", "v19/ball_order2_fields_exact"));
// 20.0: the two, and a two-region block with a pin through it, its nodes
// along the pin's ends predicted on the creases' curves (every kind of
// crease edge's tangent).
INSTANTIATE_TEST_SUITE_P(Format20_0, GoldenStream,
                         ::testing::Values("v20/ball_order2_exact", "v20/ball_order2_fields_exact",
                                           "v20/pin_order2_exact"));
// 21.0: the ball in gmsh's numbering of its vertices and edge nodes
// together, a node order section after its edge node section.
INSTANTIATE_TEST_SUITE_P(Format21_0, GoldenStream, ::testing::Values("v21/ball_order2_numbered_exact"));
// 22.0: the ball with its node tags made to skip, a node label section
// after its node order section.
INSTANTIATE_TEST_SUITE_P(Format22_0, GoldenStream, ::testing::Values("v22/ball_order2_labelled_exact"));
// 23.0: every exact stream above, its layer headers holding the section
// lengths its flags call for, its exact cell section with the filled bits
// in the context of the boundary's edges and the apexes ranked closing
// faces first.
INSTANTIATE_TEST_SUITE_P(Format23_0, GoldenStream,
                         ::testing::Values("two_materials_exact", "ball_order2_exact",
                                           "ball_order2_fields_exact", "pin_order2_exact",
                                           "ball_order2_numbered_exact", "ball_order2_labelled_exact"));
// 14.0 to 11.0: level 0 is the gmsh part's own tetrahedra (its recorded
// cell hash is theirs, as the encoder hashed the input's cells), its apexes
// ranked among the candidates that fit (12.0), with the filled bits in the
// context of the Delaunay cell across and a second ring (13.0), after a
// flag per 3-2 flip of the kept cells (14.0), or among them all (11.0).
INSTANTIATE_TEST_SUITE_P(Format14_0, GoldenStream, ::testing::Values("v14/two_materials_exact"));
INSTANTIATE_TEST_SUITE_P(Format13_0, GoldenStream, ::testing::Values("v13/two_materials_exact"));
INSTANTIATE_TEST_SUITE_P(Format12_0, GoldenStream, ::testing::Values("v12/two_materials_exact"));
INSTANTIATE_TEST_SUITE_P(Format11_0, GoldenStream, ::testing::Values("v11/two_materials_exact"));

// 10.0's vertex order: the torus's level 0 decodes in its .node's numbering
// (each point where the stream's grid puts the input's, scaled by 25).
TEST(GoldenOrder, TheTorusDecodesInItsInputsNumbering) {
  const auto bytes = read_bytes(golden("torus_288_cells.dtm"));
  ProgressiveDecoder d;
  ASSERT_TRUE(decode_stream(bytes, d).ok());
  ASSERT_TRUE(d.header().flags & kFlagVertexOrder);
  const OutputMesh m = decoded_mesh(d, "torus_288_cells");
  const NodeFile node = read_tetgen_node(test::data_path("torus_288.node"));
  ASSERT_EQ(m.points.size(), node.points.size());
  const Grid& g = d.header().grid;
  for (size_t k = 0; k < node.points.size(); ++k) {
    const InputPoint& p = node.points[k];
    const GridPoint expected{static_cast<int32_t>(std::lround((25 * p.x - g.origin[0]) / g.step)),
                             static_cast<int32_t>(std::lround((25 * p.y - g.origin[1]) / g.step)),
                             static_cast<int32_t>(std::lround((25 * p.z - g.origin[2]) / g.step))};
    EXPECT_EQ(m.points[k], expected) << k;
  }
}
INSTANTIATE_TEST_SUITE_P(Format8_0, GoldenStream,
                         ::testing::Values("ellipsoid_793_bricks", "torus_288_bricks"));
INSTANTIATE_TEST_SUITE_P(Format7_0, GoldenStream,
                         ::testing::Values("ellipsoid_793", "torus_288", "torus_288_paper",
                                           "torus_288_grid_q10_hull", "torus_288_q24"));
INSTANTIATE_TEST_SUITE_P(Format6_0, GoldenStream,
                         ::testing::Values("v6/torus_288", "v6/torus_288_paper", "v6/torus_288_grid_q10_hull",
                                           "v6/torus_288_q24"));
INSTANTIATE_TEST_SUITE_P(Format5_0, GoldenStream,
                         ::testing::Values("v5/torus_288", "v5/torus_288_paper", "v5/torus_288_grid_q10_hull",
                                           "v5/torus_288_q24"));
INSTANTIATE_TEST_SUITE_P(Format4_0, GoldenStream,
                         ::testing::Values("v4/torus_288", "v4/torus_288_paper", "v4/torus_288_grid_q10_hull",
                                           "v4/torus_288_q24"));
INSTANTIATE_TEST_SUITE_P(Format3_0, GoldenStream,
                         ::testing::Values("v3/torus_288", "v3/torus_288_grid_q10_hull", "v3/torus_288_q24"));
INSTANTIATE_TEST_SUITE_P(Format2_0, GoldenStream,
                         ::testing::Values("v2/torus_288", "v2/torus_288_grid_q10_hull", "v2/torus_288_q24"));

}  // namespace
}  // namespace dtm
