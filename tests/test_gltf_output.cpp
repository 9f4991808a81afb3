// meshdec's surfaces for web and AR tools: glTF 2.0 (.glb; .gltf + .bin),
// Draco-compressed or plain, and Draco's .drc. Checked against independent
// readers where this machine has them (Draco's own draco_decoder for the
// .drc; the glTF validator and three.js's loaders run in web/test/) and by
// reading the files' own structure: the GLB chunks, the declared extension,
// the plain buffers' positions, normals and indices against the same level's
// surface as meshdec writes it in OFF.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <set>
#include <span>
#include <sstream>

#include "codec/decode.h"
#include "format_test_support.h"
#include "mesh/topology.h"
#include "test_support.h"
#include "tools/formats/input.h"

namespace dtm {
namespace {

using nlohmann::json;

struct Off {
  std::vector<std::array<double, 3>> points;
  std::vector<std::array<uint32_t, 3>> triangles;
};

Off read_off(const std::string& path) {
  std::istringstream in(test::slurp(path));
  std::string magic;
  size_t v = 0, f = 0, e = 0;
  in >> magic >> v >> f >> e;
  Off off;
  off.points.resize(v);
  for (auto& p : off.points) in >> p[0] >> p[1] >> p[2];
  off.triangles.resize(f);
  for (auto& t : off.triangles) {
    int n = 0;
    in >> n >> t[0] >> t[1] >> t[2];
  }
  return off;
}

struct Glb {
  json gltf;
  std::string bin;
};

Glb read_glb(const std::string& path) {
  const std::string b = test::slurp(path);
  EXPECT_GE(b.size(), 20u);
  EXPECT_EQ(b.substr(0, 4), "glTF");
  uint32_t version = 0, length = 0, json_length = 0, json_type = 0;
  std::memcpy(&version, b.data() + 4, 4);
  std::memcpy(&length, b.data() + 8, 4);
  std::memcpy(&json_length, b.data() + 12, 4);
  std::memcpy(&json_type, b.data() + 16, 4);
  EXPECT_EQ(version, 2u);
  EXPECT_EQ(length, b.size());
  EXPECT_EQ(json_type, 0x4E4F534Au);
  EXPECT_EQ(json_length % 4, 0u);
  Glb glb;
  glb.gltf = json::parse(b.substr(20, json_length));
  if (b.size() > 20 + json_length) {
    uint32_t bin_length = 0, bin_type = 0;
    std::memcpy(&bin_length, b.data() + 20 + json_length, 4);
    std::memcpy(&bin_type, b.data() + 24 + json_length, 4);
    EXPECT_EQ(bin_type, 0x004E4942u);
    glb.bin = b.substr(28 + json_length, bin_length);
  }
  return glb;
}

// The floats of a plain accessor.
std::vector<float> floats(const Glb& glb, int accessor) {
  const json& a = glb.gltf["accessors"][accessor];
  const json& view = glb.gltf["bufferViews"][a["bufferView"].get<int>()];
  EXPECT_EQ(a["componentType"], 5126);
  const size_t n = a["count"].get<size_t>() * 3;
  std::vector<float> out(n);
  std::memcpy(out.data(), glb.bin.data() + view.value("byteOffset", 0) + a.value("byteOffset", 0), 4 * n);
  return out;
}

std::vector<uint32_t> indices(const Glb& glb, int accessor) {
  const json& a = glb.gltf["accessors"][accessor];
  const json& view = glb.gltf["bufferViews"][a["bufferView"].get<int>()];
  const size_t n = a["count"].get<size_t>(), at = view.value("byteOffset", 0) + a.value("byteOffset", 0);
  std::vector<uint32_t> out(n);
  for (size_t i = 0; i < n; ++i) {
    if (a["componentType"] == 5125) {
      std::memcpy(&out[i], glb.bin.data() + at + 4 * i, 4);
    } else if (a["componentType"] == 5121) {  // (a primitive of under 256 vertices)
      out[i] = static_cast<uint8_t>(glb.bin[at + i]);
    } else {
      uint16_t v;
      std::memcpy(&v, glb.bin.data() + at + 2 * i, 2);
      out[i] = v;
    }
  }
  return out;
}

class GltfOutput : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = ::testing::TempDir() + "/gltf_output";
    std::filesystem::create_directories(dir_);
    stream_ = dir_ + "/bunny.dtm";
    const auto r = test::run_command(std::string(DTM_MESHENC) + " " + test::data_path("bunny_10k.node") +
                                     " --box 256 --dmax 2 -q -o " + stream_);
    ASSERT_EQ(r.status, 0) << r.output;
  }
  static test::CommandRun meshdec(const std::string& args) {
    return test::run_command(std::string(DTM_MESHDEC) + " " + stream_ + " " + args);
  }
  static inline std::string dir_, stream_;
};

TEST_F(GltfOutput, DracoDecoderReadsTheDrcToTheSameSurfaceWithinTheStatedStep) {
  for (const char* level : {"0", "3"}) {
    const std::string drc = dir_ + "/level" + level + ".drc", off = dir_ + "/level" + level + ".off";
    auto r = meshdec(std::string("--level ") + level + " -o " + drc);
    ASSERT_EQ(r.status, 0) << r.output;
    // "Draco: positions B bits (step S, ...)"
    const size_t at = r.output.find("Draco: positions ");
    ASSERT_NE(at, std::string::npos) << r.output;
    const double step = std::stod(r.output.substr(r.output.find("(step ", at) + 6));
    ASSERT_EQ(meshdec(std::string("--level ") + level + " -o " + off).status, 0);
    const Off surface = read_off(off);

    r = test::run_command("draco_decoder -i " + drc + " -o " + dir_ + "/decoded.obj");
    ASSERT_EQ(r.status, 0) << r.output;
    std::istringstream obj(test::slurp(dir_ + "/decoded.obj"));
    std::vector<std::array<double, 3>> decoded;
    size_t faces = 0;
    for (std::string line; std::getline(obj, line);) {
      if (line.rfind("v ", 0) == 0) {
        std::istringstream in(line.substr(2));
        std::array<double, 3> p;
        in >> p[0] >> p[1] >> p[2];
        decoded.push_back(p);
      } else if (line.rfind("f ", 0) == 0) {
        ++faces;
      }
    }
    EXPECT_EQ(faces, surface.triangles.size()) << "level " << level;
    // Every decoded vertex is within half Draco's step (and float rounding)
    // of one of the level's surface vertices, per axis.
    std::map<std::array<long, 3>, std::vector<std::array<double, 3>>> cells;
    auto cell = [&](const std::array<double, 3>& p) {
      return std::array<long, 3>{std::lround(p[0] / step), std::lround(p[1] / step),
                                 std::lround(p[2] / step)};
    };
    for (const auto& p : surface.points) cells[cell(p)].push_back(p);
    for (const auto& q : decoded) {
      bool found = false;
      const auto c = cell(q);
      for (long dx = -1; dx <= 1 && !found; ++dx)
        for (long dy = -1; dy <= 1 && !found; ++dy)
          for (long dz = -1; dz <= 1 && !found; ++dz) {
            const auto it = cells.find({c[0] + dx, c[1] + dy, c[2] + dz});
            if (it == cells.end()) continue;
            for (const auto& p : it->second)
              found = found || (std::abs(p[0] - q[0]) <= 0.5001 * step + 1e-4 &&
                                std::abs(p[1] - q[1]) <= 0.5001 * step + 1e-4 &&
                                std::abs(p[2] - q[2]) <= 0.5001 * step + 1e-4);
          }
      ASSERT_TRUE(found) << "a decoded vertex is farther than half a step from the surface's";
    }
  }
}

TEST_F(GltfOutput, GlbDeclaresDracoAndHoldsTheSurfaceWithNormalsAndColours) {
  auto r = meshdec("--level 1 -o " + dir_ + "/draco.glb");
  ASSERT_EQ(r.status, 0) << r.output;
  ASSERT_EQ(meshdec("--level 1 -o " + dir_ + "/level1.off").status, 0);
  const Off surface = read_off(dir_ + "/level1.off");
  const Glb glb = read_glb(dir_ + "/draco.glb");
  for (const char* list : {"extensionsUsed", "extensionsRequired"})
    EXPECT_EQ(glb.gltf[list], json::array({"KHR_draco_mesh_compression"})) << list;
  const json& primitive = glb.gltf["meshes"][0]["primitives"][0];
  EXPECT_EQ(primitive.value("mode", 4), 4);  // triangles
  for (const char* attribute : {"POSITION", "NORMAL", "COLOR_0"}) {
    EXPECT_TRUE(primitive["attributes"].contains(attribute)) << attribute;
    EXPECT_TRUE(primitive["extensions"]["KHR_draco_mesh_compression"]["attributes"].contains(attribute));
  }
  EXPECT_EQ(glb.gltf["accessors"][primitive["indices"].get<int>()]["count"], 3 * surface.triangles.size());
  EXPECT_EQ(glb.gltf["asset"]["version"], "2.0");
  EXPECT_EQ(glb.gltf["asset"]["generator"].get<std::string>().rfind("dtmesh meshdec", 0), 0u);
  EXPECT_FALSE(glb.bin.empty());
}

TEST_F(GltfOutput, PlainGlbHoldsTheSurfaceExactlyWithOutwardUnitNormals) {
  auto r = meshdec("--level 2 --no-draco -o " + dir_ + "/plain.glb");
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_EQ(r.output.find("Draco:"), std::string::npos);
  ASSERT_EQ(meshdec("--level 2 -o " + dir_ + "/level2.off").status, 0);
  const Off surface = read_off(dir_ + "/level2.off");
  const Glb glb = read_glb(dir_ + "/plain.glb");
  EXPECT_FALSE(glb.gltf.contains("extensionsRequired"));
  const json& primitive = glb.gltf["meshes"][0]["primitives"][0];
  EXPECT_FALSE(primitive.contains("extensions"));
  const std::vector<float> positions = floats(glb, primitive["attributes"]["POSITION"].get<int>());
  const std::vector<float> normals = floats(glb, primitive["attributes"]["NORMAL"].get<int>());
  const std::vector<uint32_t> index = indices(glb, primitive["indices"].get<int>());
  ASSERT_EQ(positions.size(), 3 * surface.points.size());
  ASSERT_EQ(index.size(), 3 * surface.triangles.size());
  // The same points, in the same order, as float32 of the decoded doubles
  // less the node's translation (the surface's least corner).
  const json& node = glb.gltf["nodes"][0];
  ASSERT_TRUE(node.contains("translation"));
  const std::array<double, 3> anchor = node["translation"].get<std::array<double, 3>>();
  for (size_t v = 0; v < surface.points.size(); ++v)
    for (int k = 0; k < 3; ++k)
      ASSERT_EQ(positions[3 * v + k], static_cast<float>(surface.points[v][k] - anchor[k]));
  // Unit normals; each triangle's own normal agrees with its corners' (the
  // surface is oriented outward: BoundarySurfaceIsClosedAndOrientedOutward).
  size_t agreeing = 0;
  for (size_t t = 0; t < index.size(); t += 3) {
    const float* a = &positions[3 * index[t]];
    const float* b = &positions[3 * index[t + 1]];
    const float* c = &positions[3 * index[t + 2]];
    const double u[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]},
                 w[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
    const double n[3] = {u[1] * w[2] - u[2] * w[1], u[2] * w[0] - u[0] * w[2], u[0] * w[1] - u[1] * w[0]};
    double dot = 0;
    for (int k = 0; k < 3; ++k) dot += n[k] * normals[3 * index[t] + k];
    agreeing += dot > 0;
  }
  for (size_t v = 0; v < surface.points.size(); ++v)
    EXPECT_NEAR(std::hypot(normals[3 * v], normals[3 * v + 1], normals[3 * v + 2]), 1.0, 1e-5);
  EXPECT_GT(agreeing, 0.97 * surface.triangles.size());
}

// Far from the origin float32 cannot hold a position to the grid's step
// (the bunny moved by 2.5e6: float32 steps 0.25 there). A glTF file holds
// offsets from its node's translation, within half a grid step; a .drc
// holds positions whole, and meshdec's stated bound says what float32 adds.
TEST_F(GltfOutput, FarFromTheOriginGlbKeepsTheStepAndDrcSaysWhatItLoses) {
  const std::string node = dir_ + "/far.node", far = dir_ + "/far.dtm";
  {
    const InputMesh in = read_input(test::data_path("bunny_10k.node"));
    std::ofstream f(node);
    f.precision(17);
    f << in.points.size() << " 3 0 0\n";
    for (size_t i = 0; i < in.points.size(); ++i)
      f << i << " " << in.points[i].x + 1e6 << " " << in.points[i].y - 2.5e6 << " " << in.points[i].z + 37
        << "\n";
  }
  auto r = test::run_command(std::string(DTM_MESHENC) + " " + node + " --box 256 --dmax 2 -q -o " + far);
  ASSERT_EQ(r.status, 0) << r.output;
  const std::string base = std::string(DTM_MESHDEC) + " " + far + " --level 1 ";
  ASSERT_EQ(test::run_command(base + "-o " + dir_ + "/far.off").status, 0);
  ASSERT_EQ(test::run_command(base + "--no-draco -o " + dir_ + "/far.glb").status, 0);
  const Off surface = read_off(dir_ + "/far.off");
  const Glb glb = read_glb(dir_ + "/far.glb");
  const std::vector<float> positions =
      floats(glb, glb.gltf["meshes"][0]["primitives"][0]["attributes"]["POSITION"].get<int>());
  const std::array<double, 3> anchor = glb.gltf["nodes"][0]["translation"].get<std::array<double, 3>>();
  ASSERT_EQ(positions.size(), 3 * surface.points.size());
  double worst = 0;
  for (size_t v = 0; v < surface.points.size(); ++v)
    for (int k = 0; k < 3; ++k)
      worst = std::max(worst, std::abs(positions[3 * v + k] + anchor[k] - surface.points[v][k]));
  const double step = 9.92 / 16383;  // the bunny's extent over the grid
  EXPECT_LT(worst, step / 100);
  r = test::run_command(base + "-o " + dir_ + "/far.drc");
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_NE(r.output.find("float32 so far from the origin"), std::string::npos) << r.output;
  r = test::run_command(base + "-o " + dir_ + "/far_draco.glb");
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_EQ(r.output.find("float32 so far from the origin"), std::string::npos) << r.output;
}

TEST_F(GltfOutput, GltfWritesItsBinBesideIt) {
  auto r = meshdec("-o " + dir_ + "/split.gltf");
  ASSERT_EQ(r.status, 0) << r.output;
  const json gltf = json::parse(test::slurp(dir_ + "/split.gltf"));
  EXPECT_EQ(gltf["buffers"][0]["uri"], "split.bin");
  EXPECT_EQ(gltf["buffers"][0]["byteLength"].get<size_t>(), std::filesystem::file_size(dir_ + "/split.bin"));
  EXPECT_EQ(gltf["extensionsRequired"], json::array({"KHR_draco_mesh_compression"}));
  // A name with a space and a '#': its URI percent-encoded (a '#' would
  // start a fragment), the .bin beside it under its own name.
  r = meshdec("-o '" + dir_ + "/my part #1.gltf'");
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_EQ(json::parse(test::slurp(dir_ + "/my part #1.gltf"))["buffers"][0]["uri"], "my%20part%20%231.bin");
  EXPECT_TRUE(std::filesystem::exists(dir_ + "/my part #1.bin"));
  r = meshdec("-o - --format gltf");
  EXPECT_NE(r.status, 0);
  EXPECT_NE(r.output.find("write .glb to standard output"), std::string::npos) << r.output;
}

TEST_F(GltfOutput, ColoursByAFieldAndRefusesAnUnknownOne) {
  const std::string ct = dir_ + "/ct.dtm";
  auto r = test::run_command(std::string(DTM_MESHENC) + " " + DTM_TEST_SOURCE_DIR +
                             "/../data/ct_torus.nrrd --threshold 0 --voxel-interior-step 2 -q -o " + ct);
  ASSERT_EQ(r.status, 0) << r.output;
  const std::string base = std::string(DTM_MESHDEC) + " " + ct + " --no-draco ";
  ASSERT_EQ(test::run_command(base + "--color value -o " + dir_ + "/value.glb").status, 0);
  ASSERT_EQ(test::run_command(base + "--color level -o " + dir_ + "/level.glb").status, 0);
  // Different colours, same geometry.
  const Glb by_value = read_glb(dir_ + "/value.glb"), by_level = read_glb(dir_ + "/level.glb");
  EXPECT_EQ(by_value.bin.size(), by_level.bin.size());
  EXPECT_NE(by_value.bin, by_level.bin);
  r = test::run_command(base + "--color pressure -o " + dir_ + "/nothing.glb");
  EXPECT_NE(r.status, 0);
  EXPECT_NE(r.output.find("--color pressure: no such field (known: level, boundary, value)"),
            std::string::npos)
      << r.output;
  EXPECT_FALSE(std::filesystem::exists(dir_ + "/nothing.glb"));
}

// --color region: a part of two materials is each material's own surface,
// a primitive each, named as its region, closed, in one colour each; its
// triangles are the faces of exactly one of the region's cells as the
// decoder gives them. A stream without regions is refused.
TEST_F(GltfOutput, ByRegionEachRegionIsItsOwnClosedSurfaceAPrimitiveNamedAsTheRegion) {
  const std::string stream = std::string(DTM_TEST_SOURCE_DIR) + "/golden/two_materials.dtm";
  const std::string out = dir_ + "/regions.glb";
  auto r =
      test::run_command(std::string(DTM_MESHDEC) + " " + stream + " --color region --no-draco -o " + out);
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_EQ(r.output.find("the cells' regions"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("the regions' surfaces: "), std::string::npos) << r.output;

  // The decoder's faces of exactly one cell of each region.
  ProgressiveDecoder decoder;
  const std::string bytes = test::slurp(stream);
  ASSERT_TRUE(
      decode_stream(std::span(reinterpret_cast<const uint8_t*>(bytes.data()), bytes.size()), decoder).ok());
  const ProgressiveDecoder::LevelCells level = decoder.level_cells();
  ASSERT_EQ(decoder.regions().size(), 2u);

  const Glb glb = read_glb(out);
  const json& primitives = glb.gltf["meshes"][0]["primitives"];
  ASSERT_EQ(primitives.size(), 2u);
  std::set<std::array<uint8_t, 3>> colours;
  for (size_t p = 0; p < 2; ++p) {
    const json& primitive = primitives[p];
    const json& material = glb.gltf["materials"][primitive["material"].get<int>()];
    EXPECT_EQ(material["name"], decoder.regions()[p].name);
    EXPECT_EQ(material["pbrMetallicRoughness"]["metallicFactor"], 0)
        << "a metal draws black without light to reflect";
    std::vector<uint8_t> in_region(level.kept.size());
    for (size_t c = 0; c < level.kept.size(); ++c) in_region[c] = level.kept[c] == p + 1;
    const std::vector<uint32_t> index = indices(glb, primitive["indices"].get<int>());
    EXPECT_EQ(index.size(), 3 * boundary_faces(level.mesh, in_region).size()) << decoder.regions()[p].name;
    // Closed: every directed edge met once, and once the other way (the
    // corners by their positions: a glTF encoder may repeat a vertex).
    const std::vector<float> positions = floats(glb, primitive["attributes"]["POSITION"].get<int>());
    std::map<std::array<float, 3>, uint32_t> welded;
    const auto corner = [&](uint32_t v) {
      return welded
          .emplace(std::array<float, 3>{positions[3 * v], positions[3 * v + 1], positions[3 * v + 2]},
                   static_cast<uint32_t>(welded.size()))
          .first->second;
    };
    std::map<std::pair<uint32_t, uint32_t>, int> edges;
    for (size_t t = 0; t < index.size(); t += 3)
      for (int k = 0; k < 3; ++k) ++edges[{corner(index[t + k]), corner(index[t + (k + 1) % 3])}];
    for (const auto& [edge, n] : edges) {
      EXPECT_EQ(n, 1);
      EXPECT_EQ(edges.count({edge.second, edge.first}), 1u);
    }
    // One colour for the whole region.
    const json& a = glb.gltf["accessors"][primitive["attributes"]["COLOR_0"].get<int>()];
    const json& view = glb.gltf["bufferViews"][a["bufferView"].get<int>()];
    const size_t at = view.value("byteOffset", 0) + a.value("byteOffset", 0);
    std::set<std::array<uint8_t, 3>> own;
    for (size_t v = 0; v < a["count"].get<size_t>(); ++v) {
      const auto* rgba = reinterpret_cast<const uint8_t*>(glb.bin.data() + at + 4 * v);
      own.insert({rgba[0], rgba[1], rgba[2]});
    }
    EXPECT_EQ(own.size(), 1u);
    colours.insert(own.begin(), own.end());
  }
  EXPECT_EQ(colours.size(), 2u) << "each region in its own colour";

  const std::string none = dir_ + "/no_regions.glb";
  r = test::run_command(std::string(DTM_MESHDEC) + " " + stream_ + " --color region -o " + none);
  EXPECT_NE(r.status, 0);
  EXPECT_NE(r.output.find("--color region: the mesh has no regions"), std::string::npos) << r.output;
  EXPECT_FALSE(std::filesystem::exists(none));
}

TEST_F(GltfOutput, EmptySurfaceAndUnwritableOutputAreErrorsWithNoFile) {
  // Alpha far below any circumradius: level 0 keeps no tetrahedron.
  const std::string empty = dir_ + "/empty.dtm";
  auto r = test::run_command(std::string(DTM_MESHENC) + " " + test::data_path("torus_288.node") +
                             " --preset paper --alpha 0.001 --no-reference -q -o " + empty);
  ASSERT_EQ(r.status, 0) << r.output;
  for (const char* ext : {".glb", ".gltf", ".drc"}) {
    const std::string out = dir_ + "/empty" + ext;
    r = test::run_command(std::string(DTM_MESHDEC) + " " + empty + " -o " + out);
    EXPECT_NE(r.status, 0) << ext;
    EXPECT_NE(r.output.find("boundary surface is empty"), std::string::npos) << r.output;
    EXPECT_FALSE(std::filesystem::exists(out)) << ext;
    EXPECT_FALSE(std::filesystem::exists(dir_ + "/empty.bin"));
  }
  r = meshdec("-o " + dir_ + "/no/such/dir/x.glb");
  EXPECT_NE(r.status, 0);
  EXPECT_NE(r.output.find(dir_ + "/no/such/dir/x.glb"), std::string::npos) << r.output;
  for (const auto& entry : std::filesystem::directory_iterator(dir_))
    EXPECT_EQ(entry.path().string().find(".tmp"), std::string::npos) << entry.path();
}

}  // namespace
}  // namespace dtm
