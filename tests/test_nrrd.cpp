// Voxel volumes: a CT-like torus generated here in every NRRD flavour we read
// (uint8, uint16 big-endian, float32; attached, detached .nhdr + .raw, gzip),
// its solid taken on the voxel grid, and the most degenerate Delaunay input
// there is (every point on a lattice) through the hierarchy, the stream and
// the decoder, checked level by level.
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <filesystem>
#include <nlohmann/json.hpp>

#include "codec/decode.h"
#include "codec/encode.h"
#include "core/voxel_solid.h"
#include "format_test_support.h"
#include "test_support.h"
#include "tools/formats/input.h"
#include "tools/formats/render_util.h"

namespace dtm {
namespace {

constexpr int kSize = 32;
constexpr double kSpacing = 0.5;  // exact in binary: positions stay exact
constexpr std::array<double, 3> kOrigin{10, 20, -30};

// Signed depth inside a torus (core radius 9, tube radius 4, voxel units),
// centred in the volume: > 0 inside.
double depth(int i, int j, int k) {
  const double x = i - 15.5, y = j - 15.5, z = k - 15.2;
  return 4.0 - std::hypot(std::hypot(x, y) - 9.0, z);
}

enum class Flavour { kUint8, kUint16Big, kFloat32 };

// The volume's bytes, x fastest; CT-like values: 1000 + 100 * depth, clamped.
std::string voxels(Flavour f) {
  std::string out;
  for (int k = 0; k < kSize; ++k)
    for (int j = 0; j < kSize; ++j)
      for (int i = 0; i < kSize; ++i) {
        const double d = depth(i, j, k);
        switch (f) {
          case Flavour::kUint8:
            append_binary(out, static_cast<uint8_t>(d >= 0 ? 200 : 10));
            break;
          case Flavour::kUint16Big:
            append_binary(out, static_cast<uint16_t>(std::clamp(1000 + 100 * d, 0.0, 4000.0)), true);
            break;
          case Flavour::kFloat32:
            append_binary(out, static_cast<float>(d));
            break;
        }
      }
  return out;
}

std::string header(const char* type, const char* encoding, const char* endian,
                   const std::string& extra = "") {
  return std::string("NRRD0004\n# a CT-like torus\ntype: ") + type + "\ndimension: 3\nsizes: 32 32 32\n" +
         "space dimension: 3\nspace directions: (0.5,0,0) (0,0.5,0) (0,0,0.5)\nspace origin: (10,20,-30)\n" +
         "kinds: domain domain domain\nencoding: " + encoding + "\n" +
         (endian ? std::string("endian: ") + endian + "\n" : "") + extra;
}

class Volumes : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = ::testing::TempDir() + "/volumes";
    std::filesystem::create_directories(dir_);
    std::ofstream(dir_ + "/torus_u8.nrrd", std::ios::binary) << header("uchar", "raw", nullptr) << "\n"
                                                             << voxels(Flavour::kUint8);
    std::ofstream(dir_ + "/torus_u16.raw", std::ios::binary) << voxels(Flavour::kUint16Big);
    std::ofstream(dir_ + "/torus_u16.nhdr")
        << header("unsigned short", "raw", "big", "data file: torus_u16.raw\n");
    std::ofstream(dir_ + "/torus_f32.nrrd", std::ios::binary) << header("float", "raw", "little") << "\n"
                                                              << voxels(Flavour::kFloat32);
    // gzip, as 3D Slicer saves by default.
    std::ofstream(dir_ + "/torus_f32.raw", std::ios::binary) << voxels(Flavour::kFloat32);
    const auto r = test::run_command("gzip -c " + dir_ + "/torus_f32.raw > " + dir_ + "/torus_f32.raw.gz");
    ASSERT_EQ(r.status, 0) << r.output;
    std::ofstream(dir_ + "/torus_gz.nrrd", std::ios::binary) << header("float", "gzip", "little") << "\n"
                                                             << test::slurp(dir_ + "/torus_f32.raw.gz");
  }
  static std::string path(const std::string& name) { return dir_ + "/" + name; }
  static VolumeOptions threshold(double t, int step = 1) {
    VolumeOptions o;
    o.threshold = t;
    o.interior_step = step;
    return o;
  }
  static std::string dir_;
};
std::string Volumes::dir_;

TEST_F(Volumes, EveryFlavourSelectsTheSameSolidOnTheVoxelLattice) {
  const InputMesh u8 = read_input(path("torus_u8.nrrd"), {}, threshold(100));
  ASSERT_TRUE(u8.on_grid.has_value());
  const QuantizedPoints& q = *u8.on_grid;
  // Points: the voxels at depth >= 0, indices shifted so that the smallest is 0.
  size_t solid = 0;
  for (int k = 0; k < kSize; ++k)
    for (int j = 0; j < kSize; ++j)
      for (int i = 0; i < kSize; ++i) solid += depth(i, j, k) >= 0;
  EXPECT_EQ(q.points.size(), solid);  // interior step 1: every solid voxel
  EXPECT_TRUE(std::is_sorted(q.points.begin(), q.points.end()));
  EXPECT_EQ(std::adjacent_find(q.points.begin(), q.points.end()), q.points.end());
  EXPECT_EQ(q.grid.step, kSpacing);
  GridPoint lo = q.points[0], hi = q.points[0];
  for (const GridPoint& g : q.points) {
    lo = {std::min(lo.x, g.x), std::min(lo.y, g.y), std::min(lo.z, g.z)};
    hi = {std::max(hi.x, g.x), std::max(hi.y, g.y), std::max(hi.z, g.z)};
  }
  EXPECT_EQ(lo, (GridPoint{0, 0, 0}));
  EXPECT_EQ(q.grid.qbits, 5);  // the torus spans 27 voxels: 2^5 - 1 >= 26
  // Lossless: each point's position is its voxel centre, exactly.
  for (size_t n = 0; n < q.points.size(); ++n) {
    const InputPoint p = u8.points[n];
    const double i = (p.x - kOrigin[0]) / kSpacing, j = (p.y - kOrigin[1]) / kSpacing,
                 k = (p.z - kOrigin[2]) / kSpacing;
    ASSERT_EQ(i, std::floor(i));
    ASSERT_GE(depth(static_cast<int>(i), static_cast<int>(j), static_cast<int>(k)), 0);
    const InputPoint g = q.grid.to_input(q.points[n]);
    ASSERT_TRUE(test::same_double(g.x, p.x) && test::same_double(g.y, p.y) && test::same_double(g.z, p.z));
  }
  // The same points from uint16 (detached, big-endian), float32 and gzip,
  // and the values' type as the file stores them.
  for (const auto& [name, t, type] : {std::tuple{"torus_u16.nhdr", 1000.0, ScalarType::kUInt16},
                                      std::tuple{"torus_f32.nrrd", 0.0, ScalarType::kFloat32},
                                      std::tuple{"torus_gz.nrrd", 0.0, ScalarType::kFloat32}}) {
    const InputMesh m = read_input(path(name), {}, threshold(t));
    ASSERT_TRUE(m.on_grid.has_value()) << name;
    EXPECT_EQ(m.on_grid->points, q.points) << name;
    EXPECT_EQ(m.on_grid->grid.origin, q.grid.origin) << name;
    ASSERT_EQ(m.fields.size(), 1u);
    EXPECT_EQ(m.fields[0].name, "value");
    EXPECT_EQ(m.fields[0].type, type) << name;
  }
}

// A header may claim a volume far larger than its data: the reader must
// find out from the data, without allocating what the header claims
// (2048^3 bytes here, 8 GiB).
TEST_F(Volumes, AHugeClaimedVolumeWithLittleDataFailsWithoutAllocatingIt) {
  const std::string claim = "NRRD0004\ntype: uchar\ndimension: 3\nsizes: 2048 2048 2048\nspacings: 1 1 1\n";
  std::ofstream(path("small.raw"), std::ios::binary) << std::string(1000, '\0');
  const auto r = test::run_command("gzip -c " + path("small.raw") + " > " + path("small.raw.gz"));
  ASSERT_EQ(r.status, 0) << r.output;
  std::ofstream(path("huge_gz.nrrd"), std::ios::binary) << claim << "encoding: gzip\n\n"
                                                        << test::slurp(path("small.raw.gz"));
  std::ofstream(path("huge_ascii.nrrd"), std::ios::binary) << claim << "encoding: ascii\n\n1 2 3 4\n";
  for (const char* name : {"huge_gz.nrrd", "huge_ascii.nrrd"}) {
    const auto start = std::chrono::steady_clock::now();
    try {
      read_input(path(name), {}, threshold(1));
      ADD_FAILURE() << name << " was accepted";
    } catch (const FormatError& e) {
      EXPECT_NE(std::string(e.what()).find(name), std::string::npos) << e.what();
    }
    EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(), 2.0) << name;
  }
}

TEST_F(Volumes, InteriorSubsamplingKeepsEveryBoundaryVoxel) {
  const InputMesh all = read_input(path("torus_u8.nrrd"), {}, threshold(100, 1));
  const InputMesh sub = read_input(path("torus_u8.nrrd"), {}, threshold(100, 3));
  const auto& a = all.on_grid->points;
  const auto& s = sub.on_grid->points;
  EXPECT_LT(s.size(), a.size());
  ASSERT_TRUE(std::includes(a.begin(), a.end(), s.begin(), s.end()));
  // A voxel of `a` with all 6 neighbours in `a` is interior; every other one is kept.
  const std::set<GridPoint> in_a(a.begin(), a.end()), in_s(s.begin(), s.end());
  size_t boundary = 0;
  for (const GridPoint& g : a) {
    bool interior = true;
    for (const GridPoint d : {GridPoint{1, 0, 0}, GridPoint{-1, 0, 0}, GridPoint{0, 1, 0},
                              GridPoint{0, -1, 0}, GridPoint{0, 0, 1}, GridPoint{0, 0, -1}})
      interior = interior && in_a.count({g.x + d.x, g.y + d.y, g.z + d.z});
    if (!interior) {
      ++boundary;
      EXPECT_TRUE(in_s.count(g));
    }
  }
  EXPECT_GT(boundary, 0u);
  EXPECT_GT(s.size(), boundary);  // and some interior voxels
}

TEST_F(Volumes, LatticeRoundTripsThroughTheCodecLevelByLevel) {
  // Every level of the hierarchy of a lattice point set is rebuilt by the
  // decoder, cell for cell (cell-set hashes, meshdec --verify), and the
  // finest level holds exactly the voxel centres.
  const std::string stream = path("torus.dtm"), report = path("torus.json"),
                    node = path("torus_decoded.node");
  auto r = test::run_command(std::string(DTM_MESHENC) + " " + path("torus_u16.nhdr") +
                             " --threshold 1000 --voxel-interior-step 2 --dmax 0.5 --hash-cells -o " +
                             stream + " --report " + report);
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_NE(r.output.find("the voxel lattice: lossless"), std::string::npos) << r.output;
  const auto j = nlohmann::json::parse(test::slurp(report));
  EXPECT_EQ(j["qbits"], 5);
  EXPECT_EQ(j["step"], kSpacing);
  EXPECT_EQ(j["duplicates_merged"], 0);
  ASSERT_GE(j["levels"].size(), 3u) << r.output;
  r = test::run_command(std::string(DTM_MESHDEC) + " " + stream + " --verify -o " + node);
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_NE(r.output.find("verified " + std::to_string(j["levels"].size()) + " levels"), std::string::npos)
      << r.output;
  VolumeOptions o = threshold(1000, 2);
  const InputMesh want = read_input(path("torus_u16.nhdr"), {}, o);
  const NodeFile got = read_tetgen_node(node);
  ASSERT_EQ(got.points.size(), want.points.size());
  std::vector<std::array<double, 3>> a, b;
  for (const auto& p : got.points) a.push_back({p.x, p.y, p.z});
  for (const auto& p : want.points) b.push_back({p.x, p.y, p.z});
  std::sort(a.begin(), a.end());
  std::sort(b.begin(), b.end());
  EXPECT_EQ(a, b);  // bit-identical positions
  // --box sets the units the encoder measures in; the stream keeps the
  // lattice's own, bit for bit.
  r = test::run_command(std::string(DTM_MESHENC) + " " + path("torus_u16.nhdr") +
                        " --threshold 1000 --voxel-interior-step 2 --box 256 --dmax 8 -q -o " + stream);
  ASSERT_EQ(r.status, 0) << r.output;
  r = test::run_command(std::string(DTM_MESHDEC) + " " + stream + " -q -o " + node);
  ASSERT_EQ(r.status, 0) << r.output;
  a.clear();
  for (const auto& p : read_tetgen_node(node).points) a.push_back({p.x, p.y, p.z});
  std::sort(a.begin(), a.end());
  EXPECT_EQ(a, b);
}

// The voxels are the solid (spec/HIERARCHY.md §2.1): at every level the
// decoder's mesh is exactly the Delaunay cells whose centroid lies in a
// solid voxel, worked out here from the volume itself: the voxel whose centre
// is nearest the centroid in input units (at half-way, the higher index).
// On the lattice (the grid is the voxels) and through the directions of an
// anisotropic volume.
TEST_F(Volumes, EveryLevelKeepsTheCellsWhoseCentroidIsInASolidVoxel) {
  const std::string anisotropic = path("anisotropic_solid.nrrd");
  std::ofstream(anisotropic, std::ios::binary)
      << "NRRD0004\ntype: uchar\ndimension: 3\nsizes: 32 32 32\nspacings: 1 1 2.5\nencoding: raw\n\n"
      << voxels(Flavour::kUint8);
  for (const auto& [file, spacing] : {std::pair{path("torus_u8.nrrd"), std::array<double, 3>{0.5, 0.5, 0.5}},
                                      std::pair{anisotropic, std::array<double, 3>{1, 1, 2.5}}}) {
    const InputMesh in = read_input(file, {}, threshold(100, 2));
    ASSERT_TRUE(in.voxels.has_value());
    EncodeInput input;
    input.points = in.points;
    if (in.on_grid) input.lattice = &*in.on_grid;
    input.voxels = &*in.voxels;
    EncodeOptions options;
    options.dmax = 1.0;
    const EncodedMesh encoded = encode(input, options).value();
    EXPECT_GT(encoded.report.reference_voxels, 0u);
    const Grid& grid = encoded.report.grid;
    const std::array<double, 3> origin = file == anisotropic ? std::array<double, 3>{0, 0, 0} : kOrigin;
    auto solid_at = [&](const std::array<double, 3>& x) {
      int64_t v[3];
      for (int a = 0; a < 3; ++a)
        v[a] = static_cast<int64_t>(std::floor((x[a] - origin[a]) / spacing[a] + 0.5));
      for (int a = 0; a < 3; ++a)
        if (v[a] < 0 || v[a] >= kSize) return false;
      return depth(static_cast<int>(v[0]), static_cast<int>(v[1]), static_cast<int>(v[2])) >= 0;
    };
    size_t levels = 0, kept = 0;
    ProgressiveDecoder decoder;
    ASSERT_TRUE(decoder
                    .feed(encoded.bytes,
                          [&](const ProgressiveDecoder& d, const DecodedLevel& l) {
                            const TetMesh dt = d.delaunay();
                            const std::vector<uint8_t> carving = d.carving(dt);
                            for (size_t c = 0; c < dt.cells.size(); ++c) {
                              std::array<double, 3> centroid{0, 0, 0};
                              for (uint32_t v : dt.cells[c]) {
                                const InputPoint p = grid.to_input(d.points()[v]);
                                centroid[0] += p.x / 4, centroid[1] += p.y / 4, centroid[2] += p.z / 4;
                              }
                              ASSERT_EQ(carving[c] != 0, solid_at(centroid)) << file << " level " << l.level;
                              kept += carving[c];
                            }
                            ++levels;
                          })
                    .ok());
    EXPECT_GE(levels, 3u) << file;
    EXPECT_GT(kept, 1000u);
  }
}

TEST(VoxelSolid, TheCentroidsVoxelIsTheNearestCentreHalfWayUp) {
  // Voxels 0..3 along x, 1 along y and z; only voxel 2 solid. The lattice is
  // the grid, offset by one voxel (grid point 0 is voxel 1).
  VoxelMask mask;
  mask.sizes = {4, 1, 1};
  mask.inside = {0, 0, 1, 0};
  mask.lattice_offset = std::array<int64_t, 3>{1, 0, 0};
  const VoxelSolid solid(mask, Grid{}, 1.0);
  // Grid x in quarters: voxel 2 is grid 1, from 0.5 (included) to 1.5 (excluded).
  EXPECT_FALSE(solid.contains_point4({1, 0, 0}));  // 0.25
  EXPECT_TRUE(solid.contains_point4({2, 0, 0}));   // 0.5: half-way goes up
  EXPECT_TRUE(solid.contains_point4({5, 0, 0}));   // 1.25
  EXPECT_FALSE(solid.contains_point4({6, 0, 0}));  // 1.5: voxel 3
  EXPECT_FALSE(solid.contains_point4({4, 4, 0}));  // y = 1: outside the volume
  EXPECT_FALSE(solid.contains_point4({-9, 0, 0}));
  // The same through directions (no lattice): voxel centres at x = 10 + 2 i.
  mask.lattice_offset.reset();
  mask.origin = {10, 0, 0};
  mask.directions = {{{2, 0, 0}, {0, 1, 0}, {0, 0, 1}}};
  Grid grid;
  grid.origin = {10, 0, 0};
  grid.step = 0.5;  // grid x g is input 10 + g / 2
  const VoxelSolid through(mask, grid, 1.0);
  EXPECT_FALSE(through.contains_point4({4 * 5, 0, 0}));   // input 12.5: voxel 1
  EXPECT_TRUE(through.contains_point4({4 * 6, 0, 0}));    // 13: half-way, voxel 2
  EXPECT_TRUE(through.contains_point4({4 * 9, 0, 0}));    // 14.5
  EXPECT_FALSE(through.contains_point4({4 * 10, 0, 0}));  // 15: voxel 3
}

TEST_F(Volumes, QbitsMayGrowButNotShrink) {
  auto r = test::run_command(std::string(DTM_MESHENC) + " " + path("torus_u8.nrrd") +
                             " --threshold 100 --qbits 4 -q");
  EXPECT_NE(r.status, 0);
  EXPECT_NE(r.output.find("qbits must be at least 5"), std::string::npos) << r.output;
  const std::string report = path("q12.json");
  r = test::run_command(std::string(DTM_MESHENC) + " " + path("torus_u8.nrrd") +
                        " --threshold 100 --qbits 12 --levels 2 -q --report " + report);
  ASSERT_EQ(r.status, 0) << r.output;
  const auto j = nlohmann::json::parse(test::slurp(report));
  EXPECT_EQ(j["qbits"], 12);
  EXPECT_EQ(j["step"], kSpacing);
  // The default D_max is 0.5% of the solid's largest extent, whatever the
  // grid's (it was the grid's: 4095 steps here, 13 times the torus's).
  std::array<int, 3> lo{kSize, kSize, kSize}, hi{-1, -1, -1};
  for (int k = 0; k < kSize; ++k)
    for (int jj = 0; jj < kSize; ++jj)
      for (int i = 0; i < kSize; ++i)
        if (depth(i, jj, k) >= 0) {
          const std::array<int, 3> at{i, jj, k};
          for (size_t a = 0; a < 3; ++a) lo[a] = std::min(lo[a], at[a]), hi[a] = std::max(hi[a], at[a]);
        }
  const int extent = std::max({hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]});
  const double expected = 0.005 * extent * kSpacing;
  EXPECT_NEAR(j["dmax"].get<double>(), expected, 1e-12);
  const std::string default_q = path("q_default.json");
  r = test::run_command(std::string(DTM_MESHENC) + " " + path("torus_u8.nrrd") +
                        " --threshold 100 --levels 2 -q --report " + default_q);
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_NEAR(nlohmann::json::parse(test::slurp(default_q))["dmax"].get<double>(), expected, 1e-12);
}

TEST_F(Volumes, LabelSelectsOneValue) {
  VolumeOptions o;
  o.label = 200;
  const InputMesh m = read_input(path("torus_u8.nrrd"), {}, o);
  EXPECT_EQ(m.points.size(), read_input(path("torus_u8.nrrd"), {}, threshold(100)).points.size());
  o.label = 201;
  EXPECT_THROW(read_input(path("torus_u8.nrrd"), {}, o), FormatError);
}

TEST_F(Volumes, AnisotropicSpacingPlacesVoxelsAtTheirPositionsAndQuantizesThem) {
  const std::string p = path("anisotropic.nrrd");
  std::ofstream(p, std::ios::binary)
      << "NRRD0004\ntype: uchar\ndimension: 3\nsizes: 32 32 32\nspacings: 1 1 2.5\n"
         "encoding: raw\n\n"
      << voxels(Flavour::kUint8);
  const InputMesh m = read_input(p, {}, threshold(100));
  EXPECT_FALSE(m.on_grid.has_value());
  for (const InputPoint& q : m.points) ASSERT_EQ(std::fmod(q.z, 2.5), 0.0);
  const auto r = test::run_command(std::string(DTM_MESHENC) + " " + p + " --threshold 100 --levels 2");
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_EQ(r.output.find("the voxel lattice"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("q=14"), std::string::npos) << r.output;
}

TEST_F(Volumes, VolumeOptionsNeedAVolumeAndAVolumeNeedsThem) {
  auto r = test::run_command(std::string(DTM_MESHENC) + " " + test::data_path("torus_288.node") +
                             " --threshold 3 -q");
  EXPECT_NE(r.status, 0);
  EXPECT_NE(r.output.find("apply to voxel volumes only"), std::string::npos) << r.output;
  r = test::run_command(std::string(DTM_MESHENC) + " " + path("torus_u8.nrrd") + " -q");
  EXPECT_NE(r.status, 0);
  EXPECT_NE(r.output.find("not a 0/1 mask needs --threshold"), std::string::npos) << r.output;
}

// A 0/1 mask needs no selection: its solid is the 1s, and its values say
// nothing more, so the stream carries no field. A scan's values do travel.
TEST_F(Volumes, AMaskNeedsNoThresholdAndCarriesNoField) {
  const std::string p = path("mask.nrrd");
  std::string voxels;
  for (int k = 0; k < 16; ++k)
    for (int j = 0; j < 16; ++j)
      for (int i = 0; i < 16; ++i)
        voxels +=
            static_cast<char>((i - 7.5) * (i - 7.5) + (j - 7.5) * (j - 7.5) + (k - 7.5) * (k - 7.5) < 36);
  std::ofstream(p, std::ios::binary)
      << "NRRD0004\ntype: uchar\ndimension: 3\nsizes: 16 16 16\nencoding: raw\n\n"
      << voxels;
  const InputMesh m = read_input(p, {}, {});
  EXPECT_TRUE(m.fields.empty());
  EXPECT_GT(m.points.size(), 100u);
  const auto with_label = read_input(p, {}, {std::nullopt, 1.0, 1});
  ASSERT_EQ(with_label.fields.size(), 1u);
  EXPECT_EQ(with_label.points.size(), m.points.size());
  const auto r = test::run_command(std::string(DTM_MESHENC) + " " + p + " -o " + path("mask.dtm"));
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_EQ(r.output.find("fields"), std::string::npos) << r.output;
  // A mask of 0s only is said as such, not as a --label the user never gave.
  const std::string empty = path("empty_mask.nrrd");
  std::ofstream(empty, std::ios::binary)
      << "NRRD0004\ntype: uchar\ndimension: 3\nsizes: 4 4 4\nencoding: raw\n\n"
      << std::string(64, '\0');
  try {
    read_input(empty, {}, {});
    ADD_FAILURE() << "an empty mask was accepted";
  } catch (const FormatError& e) {
    EXPECT_NE(std::string(e.what()).find("the volume has no solid voxel"), std::string::npos) << e.what();
  }
}

// A float32 volume: --label and --threshold compare as float32 holds them
// (2.3 is 2.29999995f: --label 2.3 found no voxel); a NaN voxel is outside
// the solid, and said.
TEST_F(Volumes, AFloatVolumesOptionsCompareAsItsValuesAndNaNIsSaid) {
  const std::string p = path("floats.nrrd");
  std::string bytes;
  for (int k = 0; k < 8; ++k)
    for (int j = 0; j < 8; ++j)
      for (int i = 0; i < 8; ++i) {
        const bool inside = i > 0 && i < 7 && j > 0 && j < 7 && k > 0 && k < 7;
        append_binary(bytes, i == 3 && j == 3 && k == 3 ? NAN : inside ? 2.3f : 0.0f);
      }
  std::ofstream(p, std::ios::binary) << "NRRD0004\ntype: float\ndimension: 3\nsizes: 8 8 8\n"
                                        "encoding: raw\nendian: little\n\n"
                                     << bytes;
  VolumeOptions label;
  label.label = 2.3;
  const InputMesh by_label = read_input(p, {}, label);
  EXPECT_EQ(by_label.points.size(), 6u * 6 * 6 - 1);
  const InputMesh by_threshold = read_input(p, {}, threshold(2.3));
  EXPECT_EQ(by_threshold.points.size(), by_label.points.size());
  ASSERT_EQ(by_threshold.left_out.size(), 1u);
  EXPECT_EQ(by_threshold.left_out[0],
            "1 voxels whose value is NaN (outside the solid: no threshold selects them)");
}

}  // namespace
}  // namespace dtm
