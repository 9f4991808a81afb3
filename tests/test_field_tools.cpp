// Fields through the tools: meshenc codes every per-vertex field it reads,
// meshdec writes them back wherever the output format carries point data,
// and the files read back (by our readers, and by meshio) with the values
// the input had, vertex for vertex.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <nlohmann/json.hpp>

#include "format_test_support.h"
#include "output_mesh_support.h"
#include "tools/formats/input.h"

namespace dtm {
namespace {

// The torus with three fields of three types, written as a VTU.
struct FieldInput {
  std::string path;
  InputMesh mesh;  // as read back
};

FieldInput write_input(const std::string& dir) {
  OutputMesh m = test::torus_mesh();
  m.level.clear();
  m.boundary.clear();
  OutputField temperature{"temperature", ScalarType::kFloat32, 1, {}};
  OutputField velocity{"velocity", ScalarType::kFloat64, 3, {}};
  OutputField region{"region", ScalarType::kInt16, 1, {}};
  for (const GridPoint& g : m.points) {
    const InputPoint p = m.grid.to_input(g);
    temperature.bits.push_back(std::bit_cast<uint32_t>(static_cast<float>(20 + 5 * std::sin(p.x) * p.z)));
    for (double v : {p.y * 0.25, -p.x * 0.25, 0.125 * p.z})
      velocity.bits.push_back(std::bit_cast<uint64_t>(v));
    region.bits.push_back(static_cast<uint64_t>(static_cast<int64_t>(p.x > 0 ? -3 : 7)));
  }
  m.fields = {temperature, velocity, region};
  FieldInput in;
  in.path = dir + "/fields_in.vtu";
  write_files_atomically(render_mesh(m, MeshFormat::kVtu, in.path));
  in.mesh = read_input(in.path);
  return in;
}

// The input point nearest to p (the stream's grid moves points by at most
// half a step).
size_t nearest(const InputMesh& in, const InputPoint& p) {
  size_t best = 0;
  double best_d = 1e300;
  for (size_t i = 0; i < in.points.size(); ++i) {
    const double dx = in.points[i].x - p.x, dy = in.points[i].y - p.y, dz = in.points[i].z - p.z;
    if (dx * dx + dy * dy + dz * dz < best_d) best_d = dx * dx + dy * dy + dz * dz, best = i;
  }
  return best;
}

const VertexField* field_named(const InputMesh& m, const std::string& name) {
  for (const auto& f : m.fields)
    if (f.name == name) return &f;
  return nullptr;
}

// For every output vertex, each of the input's fields has its input point's
// values: under its own name, or (PLY) one property per component, or
// (TetGen) as attributes in field order.
void expect_fields_back(const FieldInput& in, const InputMesh& out, const std::string& format) {
  SCOPED_TRACE(format);
  ASSERT_GT(out.points.size(), 100u);
  const VertexField* attributes = field_named(out, "attributes");
  size_t attribute = 0;
  for (const VertexField& want : in.mesh.fields) {
    for (int c = 0; c < want.components; ++c, ++attribute) {
      const VertexField* got = nullptr;
      int got_c = c, got_components = want.components;
      if (attributes) {
        got = attributes, got_c = static_cast<int>(attribute), got_components = attributes->components;
      } else if ((got = field_named(out, want.name)) == nullptr) {
        got = field_named(out, want.name + "_" + std::to_string(c)), got_c = 0, got_components = 1;
      }
      ASSERT_NE(got, nullptr) << want.name;
      for (size_t v = 0; v < out.points.size(); ++v) {
        const size_t i = nearest(in.mesh, out.points[v]);
        ASSERT_EQ(got->values[v * got_components + got_c], want.values[i * want.components + c])
            << want.name << "[" << c << "] at output vertex " << v;
      }
    }
  }
}

TEST(FieldTools, EveryFormatWithPointDataGivesTheFieldsBack) {
  const std::string dir = ::testing::TempDir();
  const FieldInput in = write_input(dir);
  ASSERT_EQ(in.mesh.fields.size(), 3u);
  const std::string stream = dir + "/fields.dtm";
  auto r = test::run_command(std::string(DTM_MESHENC) + " " + in.path + " -o " + stream);
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_NE(r.output.find("'temperature' (float32, lossless)"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("'velocity' (float64 x 3, lossless)"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("field 'region' (int16)"), std::string::npos) << r.output;

  for (const std::string ext : {"vtu", "vtk", "msh", "node", "ply"}) {
    const std::string out = dir + "/fields_out." + ext;
    r = test::run_command(std::string(DTM_MESHDEC) + " " + stream + " -o " + out);
    ASSERT_EQ(r.status, 0) << r.output;
    expect_fields_back(in, read_input(out), ext);
  }
  for (const std::string format : {"vtu-ascii", "vtk-ascii"}) {
    const std::string out = dir + "/fields_out_ascii." + format.substr(0, 3);
    r = test::run_command(std::string(DTM_MESHDEC) + " " + stream + " --format " + format + " -o " + out);
    ASSERT_EQ(r.status, 0) << r.output;
    expect_fields_back(in, read_input(out), format);
  }

  // An independent reader sees the arrays, in their own types.
  r = test::run_command(test::kPython + " -c \"import meshio; m = meshio.read('" + dir +
                        "/fields_out.vtu'); print(sorted((k, str(v.dtype), v.shape[1:]) for k, v in "
                        "m.point_data.items()))\"");
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_NE(r.output.find("('temperature', 'float32', ())"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("('velocity', 'float64', (3,))"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("('region', 'int16', ())"), std::string::npos) << r.output;
}

// A name with XML's special characters is escaped by the writer and read
// back as it was.
TEST(FieldTools, VtuFieldNamesRoundTripThroughXmlEscapes) {
  OutputMesh m = test::torus_mesh();
  m.fields = {{"p&q <\"r\">", ScalarType::kInt8, 1, std::vector<uint64_t>(m.points.size(), 1)}};
  const std::string path = ::testing::TempDir() + "/escaped.vtu";
  write_files_atomically(render_mesh(m, MeshFormat::kVtu, path));
  EXPECT_NE(test::slurp(path).find("Name=\"p&amp;q &lt;&quot;r&quot;&gt;\""), std::string::npos);
  const InputMesh back = read_input(path);
  EXPECT_NE(field_named(back, "p&q <\"r\">"), nullptr);
}

TEST(FieldTools, LossyFieldsKeepTheirBoundAndNoFieldsLeavesThemOut) {
  const std::string dir = ::testing::TempDir();
  const FieldInput in = write_input(dir);
  const std::string stream = dir + "/lossy.dtm", report = dir + "/lossy.json";
  auto r = test::run_command(std::string(DTM_MESHENC) + " " + in.path + " -o " + stream +
                             " --field-error temperature=0.05 --report " + report);
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_NE(r.output.find("every value within 0.05"), std::string::npos) << r.output;
  const std::string out = dir + "/lossy.vtu";
  r = test::run_command(std::string(DTM_MESHDEC) + " " + stream + " -o " + out);
  ASSERT_EQ(r.status, 0) << r.output;
  const InputMesh decoded = read_input(out);
  const VertexField* t = field_named(decoded, "temperature");
  ASSERT_NE(t, nullptr);
  EXPECT_EQ(t->type, ScalarType::kFloat32);
  for (size_t v = 0; v < decoded.points.size(); ++v)
    ASSERT_LE(std::abs(t->values[v] - in.mesh.fields[0].values[nearest(in.mesh, decoded.points[v])]), 0.05);

  r = test::run_command(std::string(DTM_MESHINFO) + " " + stream + " --json");
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_NE(r.output.find("\"mode\": \"lossy\""), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("\"field_bytes\""), std::string::npos) << r.output;
  const auto j = nlohmann::json::parse(test::slurp(report));
  EXPECT_EQ(j["fields"][0]["error_bound"], 0.05);
  uint64_t temperature = 0;
  for (const auto& level : j["levels"])
    if (level.contains("field_bytes")) temperature += level["field_bytes"]["temperature"].get<uint64_t>();
  EXPECT_EQ(temperature, j["fields"][0]["bytes"].get<uint64_t>());

  // Refusals name the problem and write nothing.
  const std::string refused = dir + "/refused.dtm";
  for (const std::string args :
       {" --field-error region=1", " --field-error nothing=1", " --field-error temperature=-1",
        " --no-fields --field-error temperature=1"}) {
    r = test::run_command(std::string(DTM_MESHENC) + " " + in.path + " -o " + refused + args);
    EXPECT_NE(r.status, 0) << args;
    EXPECT_FALSE(std::filesystem::exists(refused)) << args;
  }
  r = test::run_command(std::string(DTM_MESHENC) + " " + in.path + " -o " + refused +
                        " --field-error region=1");
  EXPECT_NE(r.output.find("only float fields can be lossy"), std::string::npos) << r.output;

  r = test::run_command(std::string(DTM_MESHENC) + " " + in.path + " -o " + stream + " --no-fields");
  ASSERT_EQ(r.status, 0) << r.output;
  r = test::run_command(std::string(DTM_MESHINFO) + " " + stream);
  // No field table: the oldest version that holds the carving corrections
  // (7.0), without the values flag.
  EXPECT_NE(r.output.find(".dtm 7.0"), std::string::npos) << r.output;
  EXPECT_EQ(r.output.find("field"), std::string::npos) << r.output;
}

}  // namespace
}  // namespace dtm
