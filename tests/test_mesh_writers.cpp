// The mesh writers meshdec uses: TetGen files read back by our own reader
// bit for bit, VTU files read by an independent reader (Debian's meshio) and,
// for the ascii variant, by a second minimal parser here.
#include <gtest/gtest.h>

#include <bit>
#include <charconv>
#include <cstdio>
#include <fstream>
#include <sstream>

#include "format_test_support.h"
#include "output_mesh_support.h"
#include "test_support.h"
#include "tools/atomic_file.h"
#include "tools/formats/mesh_writers.h"

namespace dtm {
namespace {

// Two positively oriented tetrahedra on an inexact step (0.1), away from the
// origin, so dequantized coordinates need all 17 digits.
OutputMesh small_mesh() {
  OutputMesh m;
  m.grid.qbits = 8;
  m.grid.origin = {-1.5, 0.25, 1e6 / 3};
  m.grid.step = 0.1;
  m.points = {{0, 0, 0}, {10, 0, 0}, {0, 10, 0}, {0, 0, 10}, {10, 10, 10}};
  m.cells = {{0, 1, 2, 3}, {1, 2, 3, 4}};
  return m;
}

using test::torus_mesh;  // torus_288 with its tetrahedra (output_mesh_support.h)
using test::write;

std::string slurp(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

double to_double(const std::string& token) {
  double v = 0;
  const auto [end, ec] = std::from_chars(token.data(), token.data() + token.size(), v);
  EXPECT_TRUE(ec == std::errc() && end == token.data() + token.size()) << token;
  return v;
}

// Bit-identical, so -0.0 != 0.0 and no tolerance hides a printing error.
void expect_same_double(double got, double want, const std::string& where) {
  EXPECT_EQ(std::bit_cast<uint64_t>(got), std::bit_cast<uint64_t>(want))
      << where << ": got " << got << " want " << want;
}

// --- format_for_path ---------------------------------------------------------

TEST(MeshWriters, FormatForPathByExtension) {
  EXPECT_EQ(format_for_path("out.node"), MeshFormat::kTetgen);
  EXPECT_EQ(format_for_path("/tmp/a.b/out.vtu"), MeshFormat::kVtu);
  EXPECT_EQ(format_for_path("dir.vtu/level3.node"), MeshFormat::kTetgen);  // the file's name decides
}

TEST(MeshWriters, FormatForPathRejectsUnknownNamingThePathAndTakesAnyCase) {
  // Any case, as meshenc reads its inputs' (X.NODE's elements go to X.ELE).
  EXPECT_EQ(format_for_path("OUT.VTU"), MeshFormat::kVtu);
  EXPECT_EQ(format_for_path("out.Node"), MeshFormat::kTetgen);
  EXPECT_EQ(format_for_path("X.MSH"), MeshFormat::kGmsh);
  for (const std::string path : {"mesh.stl", "mesh", "mesh.ele", "dir/.node", "dir/.NODE"}) {
    try {
      format_for_path(path);
      ADD_FAILURE() << path << " was accepted";
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
    }
  }
}

// --- base64 ------------------------------------------------------------------

TEST(MeshWriters, Base64MatchesRfc4648) {
  EXPECT_EQ(base64_encode(""), "");
  EXPECT_EQ(base64_encode("f"), "Zg==");
  EXPECT_EQ(base64_encode("fo"), "Zm8=");
  EXPECT_EQ(base64_encode("foo"), "Zm9v");
  EXPECT_EQ(base64_encode("foob"), "Zm9vYg==");
  EXPECT_EQ(base64_encode("fooba"), "Zm9vYmE=");
  EXPECT_EQ(base64_encode("foobar"), "Zm9vYmFy");
  EXPECT_EQ(base64_encode(std::string("\xff\xfe\x00\x80", 4)), "//4AgA==");  // high bytes, no sign spill
}

// A large array (the encoding runs in ranges on every core): each 4
// characters are their 3 bytes, decoded back, whatever the length's rest.
TEST(MeshWriters, Base64OfALargeArrayDecodesBack) {
  const auto value = [](char c) -> uint32_t {
    const std::string alphabet = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    return static_cast<uint32_t>(alphabet.find(c));
  };
  for (size_t size : {size_t{3} << 19, (size_t{3} << 19) + 1, (size_t{3} << 19) + 2}) {
    std::string bytes(size, '\0');
    for (size_t i = 0; i < size; ++i) bytes[i] = static_cast<char>((i * 2654435761u) >> 13);
    const std::string text = base64_encode(bytes);
    ASSERT_EQ(text.size(), (size + 2) / 3 * 4);
    std::string back;
    for (size_t g = 0; g < text.size(); g += 4) {
      const uint32_t w = value(text[g]) << 18 | value(text[g + 1]) << 12 |
                         (text[g + 2] == '=' ? 0 : value(text[g + 2]) << 6) |
                         (text[g + 3] == '=' ? 0 : value(text[g + 3]));
      back += static_cast<char>(w >> 16);
      if (text[g + 2] != '=') back += static_cast<char>((w >> 8) & 0xff);
      if (text[g + 3] != '=') back += static_cast<char>(w & 0xff);
    }
    EXPECT_EQ(back, bytes) << size;
  }
}

// --- TetGen ------------------------------------------------------------------

void expect_tetgen_round_trip(const OutputMesh& m, const std::string& name) {
  const std::string node_path = write(m, MeshFormat::kTetgen, name + ".node");
  const NodeFile n = read_tetgen_node(node_path);
  EXPECT_EQ(n.index_base, 0);
  ASSERT_EQ(n.points.size(), m.points.size());
  for (size_t i = 0; i < m.points.size(); ++i) {
    const InputPoint want = m.grid.to_input(m.points[i]);
    const std::string where = name + " point " + std::to_string(i);
    expect_same_double(n.points[i].x, want.x, where);
    expect_same_double(n.points[i].y, want.y, where);
    expect_same_double(n.points[i].z, want.z, where);
  }
  if (m.boundary.empty()) {
    EXPECT_TRUE(n.markers.empty());
  } else {
    EXPECT_EQ(n.markers, std::vector<int>(m.boundary.begin(), m.boundary.end()));
  }
  const std::string ele_path = ::testing::TempDir() + "/" + name + ".ele";
  EXPECT_EQ(read_tetgen_ele(ele_path, n.points.size()), m.cells);
}

// More records than one batch of the writer's ranges (they are rendered on
// every core and joined in order): read back the same.
TEST(MeshWriters, ALargeTetgenMeshRoundTrips) {
  OutputMesh m = small_mesh();
  m.points.clear();
  m.cells.clear();
  for (int32_t i = 0; i < 200003; ++i) m.points.push_back({i % 97, (i / 97) % 89, i / (97 * 89)});
  for (uint32_t i = 0; i + 3 < m.points.size(); i += 2) m.cells.push_back({i, i + 1, i + 2, i + 3});
  m.boundary.assign(m.points.size(), 0);
  for (size_t i = 0; i < m.boundary.size(); i += 3) m.boundary[i] = 1;
  expect_tetgen_round_trip(m, "large");
}

TEST(MeshWriters, TetgenRendersTwoFilesWithTheCorpusHeaders) {
  OutputMesh m = small_mesh();
  auto files = render_mesh(m, MeshFormat::kTetgen, "dir/x.y.node");
  ASSERT_EQ(files.size(), 2u);
  EXPECT_EQ(files[0].first, "dir/x.y.node");
  EXPECT_EQ(files[1].first, "dir/x.y.ele");
  EXPECT_EQ(files[0].second.substr(0, 9), "5 3 0 0\n0");
  EXPECT_EQ(files[1].second.substr(0, 16), "2 4 0\n0 0 1 2 3\n");
  m.boundary = {1, 1, 1, 1, 0};
  files = render_mesh(m, MeshFormat::kTetgen, "x.node");
  EXPECT_EQ(files[0].second.substr(0, 8), "5 3 0 1\n");
}

// A stream's node ids go to 2^62 - 1; Abaqus's and Exodus's node numbers
// are 32-bit: such ids are refused there, naming the file, and gmsh's
// 64-bit tags take them.
TEST(MeshWriters, NodeIdsPast32BitsAreRefusedWhereTheFormatCannotHoldThem) {
  OutputMesh m = small_mesh();
  m.node_labels = {1, 2, 3, 4, int64_t{1} << 40};
  for (const auto& [format, path] :
       {std::pair{MeshFormat::kAbaqus, "big.inp"}, std::pair{MeshFormat::kExodus, "big.e"}}) {
    try {
      render_mesh(m, format, path);
      ADD_FAILURE() << path << ": written";
    } catch (const std::invalid_argument& e) {
      EXPECT_EQ(std::string(e.what()).rfind(std::string(path) + ": node ids above 2^31 - 1", 0), 0u)
          << e.what();
    }
  }
  EXPECT_NE(render_mesh(m, MeshFormat::kGmsh, "big.msh")[0].second.find("1099511627776"), std::string::npos);
  m.node_labels.back() = INT32_MAX;
  EXPECT_NO_THROW(render_mesh(m, MeshFormat::kAbaqus, "big.inp"));
}

TEST(MeshWriters, TetgenSmallMeshRoundTrip) {
  OutputMesh m = small_mesh();
  expect_tetgen_round_trip(m, "small_plain");
  m.boundary = {1, 1, 1, 1, 0};
  m.level = {0, 0, 1, 2, 3};  // TetGen has no column for it: ignored
  expect_tetgen_round_trip(m, "small_marked");
}

TEST(MeshWriters, TetgenTorusRoundTrip) {
  const OutputMesh m = torus_mesh();
  ASSERT_EQ(m.points.size(), 288u);
  ASSERT_EQ(m.cells.size(), 1080u);
  expect_tetgen_round_trip(m, "torus_288_out");
}

TEST(MeshWriters, RejectsInconsistentMeshesAndTetgenPathsWithoutNode) {
  OutputMesh m = small_mesh();
  EXPECT_THROW(render_mesh(m, MeshFormat::kTetgen, "x.vtu"), std::invalid_argument);
  m.level = {0, 1};
  EXPECT_THROW(render_mesh(m, MeshFormat::kVtu, "x.vtu"), std::invalid_argument);
  m = small_mesh();
  m.boundary = {1};
  EXPECT_THROW(render_mesh(m, MeshFormat::kVtuAscii, "x.vtu"), std::invalid_argument);
  m = small_mesh();
  m.cells.push_back({0, 1, 2, 5});
  EXPECT_THROW(render_mesh(m, MeshFormat::kTetgen, "x.node"), std::invalid_argument);
}

// --- VTU through meshio --------------------------------------------------------

// Dumps what meshio reads as text: every coordinate as Python's repr (the
// shortest round-trip form), every cell block, every point data array with its
// dtype. For binary arrays it also checks each block's UInt64 byte count
// against its payload, which meshio itself does not (VTK does).
constexpr const char* kMeshioDump = R"(
import base64, struct, sys
import xml.etree.ElementTree as ET
import meshio
m = meshio.read(sys.argv[1], file_format="vtu")
print("points", len(m.points))
for p in m.points:
    print(*(repr(float(x)) for x in p))
print("blocks", len(m.cells))
for b in m.cells:
    print("cells", b.type, len(b.data))
    for c in b.data:
        print(*(int(x) for x in c))
for name in sorted(m.point_data):
    d = m.point_data[name]
    print("pointdata", name, d.dtype, len(d))
    print(*(int(x) for x in d))
for da in ET.parse(sys.argv[1]).iter("DataArray"):
    if da.get("format") == "binary":
        raw = base64.b64decode(da.text.strip())
        print("block", da.get("Name"), struct.unpack("<Q", raw[:8])[0], len(raw) - 8)
print("end")
)";

std::string meshio_dump(const std::string& vtu) {
  const std::string script = ::testing::TempDir() + "/meshio_dump.py";
  std::ofstream(script) << kMeshioDump;
  const test::CommandRun r = test::run_command(test::kPython + " " + script + " " + vtu);
  if (r.status != 0) {
    ADD_FAILURE() << "meshio could not read " << vtu << " with " << test::kPython
                  << ". If python3 or meshio is missing, run scripts/setup.sh --all (it installs the "
                     "Debian package python3-meshio). Output:\n"
                  << r.output;
    return {};
  }
  return r.output;
}

// What meshio must report for `m`, in kMeshioDump's layout.
void expect_meshio_reads(const OutputMesh& m, const std::string& vtu, bool binary) {
  const std::string dump = meshio_dump(vtu);
  ASSERT_FALSE(dump.empty());
  std::istringstream in(dump);
  std::string word, s;
  size_t count = 0;
  in >> word >> count;
  ASSERT_EQ(word, "points");
  ASSERT_EQ(count, m.points.size());
  for (size_t i = 0; i < count; ++i) {
    const InputPoint want = m.grid.to_input(m.points[i]);
    const std::string where = vtu + " point " + std::to_string(i);
    for (double w : {want.x, want.y, want.z}) {
      in >> s;
      expect_same_double(to_double(s), w, where);
    }
  }
  in >> word >> count;
  ASSERT_EQ(word, "blocks");
  ASSERT_EQ(count, 1u);  // one tetra block
  in >> word >> s >> count;
  ASSERT_EQ(word, "cells");
  EXPECT_EQ(s, "tetra");
  ASSERT_EQ(count, m.cells.size());
  for (const auto& c : m.cells) {
    std::array<uint32_t, 4> got;
    for (auto& v : got) in >> v;
    EXPECT_EQ(got, c);
  }
  // Point data, sorted by name: boundary then level.
  auto expect_point_data = [&](const char* name, const char* dtype, const auto& values) {
    if (values.empty()) return;
    in >> word >> s;
    ASSERT_EQ(word, "pointdata");
    ASSERT_EQ(s, name);
    in >> s >> count;
    EXPECT_EQ(s, dtype);
    ASSERT_EQ(count, values.size());
    for (auto want : values) {
      int64_t got;
      in >> got;
      EXPECT_EQ(got, int64_t{want}) << name;
    }
  };
  expect_point_data("boundary", "uint8", m.boundary);
  expect_point_data("level", "int32", m.level);
  // Binary blocks: the header counts exactly the payload's bytes (base64
  // padding aside, which the payload is cut before).
  const size_t n = m.points.size(), t = m.cells.size();
  std::vector<std::pair<std::string, size_t>> blocks;
  if (!m.level.empty()) blocks.emplace_back("level", 4 * n);
  if (!m.boundary.empty()) blocks.emplace_back("boundary", n);
  blocks.insert(blocks.end(),
                {{"Points", 24 * n}, {"connectivity", 32 * t}, {"offsets", 8 * t}, {"types", t}});
  if (binary) {
    for (const auto& [name, bytes] : blocks) {
      size_t header = 0, payload = 0;
      in >> word >> s >> header >> payload;
      ASSERT_EQ(word, "block");
      EXPECT_EQ(s, name);
      EXPECT_EQ(header, bytes) << name;
      EXPECT_EQ(payload, bytes) << name;
    }
  }
  in >> word;
  EXPECT_EQ(word, "end") << dump;
}

TEST(MeshWriters, VtuBinaryReadByMeshio) {
  const OutputMesh torus = torus_mesh();
  expect_meshio_reads(torus, write(torus, MeshFormat::kVtu, "torus_288.vtu"), true);
  const OutputMesh small = small_mesh();  // no point data at all
  expect_meshio_reads(small, write(small, MeshFormat::kVtu, "small.vtu"), true);
}

TEST(MeshWriters, VtuAsciiReadByMeshio) {
  const OutputMesh torus = torus_mesh();
  expect_meshio_reads(torus, write(torus, MeshFormat::kVtuAscii, "torus_288_ascii.vtu"), false);
  const OutputMesh small = small_mesh();
  expect_meshio_reads(small, write(small, MeshFormat::kVtuAscii, "small_ascii.vtu"), false);
}

// --- VTU ascii through a second, minimal parser ---------------------------------

// The whitespace-separated tokens of the DataArray named `name`; checks its
// type and ascii format on the way.
std::vector<std::string> ascii_array(const std::string& xml, const std::string& name,
                                     const std::string& type) {
  const size_t at = xml.find("Name=\"" + name + "\"");
  if (at == std::string::npos) {
    ADD_FAILURE() << "no DataArray " << name;
    return {};
  }
  const size_t open = xml.rfind("<DataArray", at), close = xml.find('>', at);
  const std::string tag = xml.substr(open, close - open);
  EXPECT_NE(tag.find("type=\"" + type + "\""), std::string::npos) << tag;
  EXPECT_NE(tag.find("format=\"ascii\""), std::string::npos) << tag;
  std::istringstream body(xml.substr(close + 1, xml.find("</DataArray>", close) - close - 1));
  std::vector<std::string> out;
  for (std::string s; body >> s;) out.push_back(s);
  return out;
}

TEST(MeshWriters, VtuAsciiByHand) {
  const OutputMesh m = torus_mesh();
  const std::string xml = slurp(write(m, MeshFormat::kVtuAscii, "torus_288_hand.vtu"));
  for (const char* attr : {"type=\"UnstructuredGrid\"", "version=\"0.1\"", "byte_order=\"LittleEndian\"",
                           "header_type=\"UInt64\"", "NumberOfPoints=\"288\"", "NumberOfCells=\"1080\""})
    EXPECT_NE(xml.find(attr), std::string::npos) << attr;
  // VTK reads connectivity as a flat 1-component array, whatever the line layout.
  EXPECT_NE(xml.find("<DataArray type=\"Int64\" Name=\"connectivity\" format=\"ascii\">"), std::string::npos);
  EXPECT_NE(xml.find("Name=\"Points\" NumberOfComponents=\"3\""), std::string::npos);

  const auto coords = ascii_array(xml, "Points", "Float64");
  ASSERT_EQ(coords.size(), 3 * m.points.size());
  for (size_t i = 0; i < m.points.size(); ++i) {
    const InputPoint p = m.grid.to_input(m.points[i]);
    expect_same_double(to_double(coords[3 * i]), p.x, "x");
    expect_same_double(to_double(coords[3 * i + 1]), p.y, "y");
    expect_same_double(to_double(coords[3 * i + 2]), p.z, "z");
  }
  const auto conn = ascii_array(xml, "connectivity", "Int64");
  const auto offsets = ascii_array(xml, "offsets", "Int64");
  const auto types = ascii_array(xml, "types", "UInt8");
  ASSERT_EQ(conn.size(), 4 * m.cells.size());
  ASSERT_EQ(offsets.size(), m.cells.size());
  ASSERT_EQ(types.size(), m.cells.size());
  for (size_t c = 0; c < m.cells.size(); ++c) {
    for (int k = 0; k < 4; ++k) EXPECT_EQ(conn[4 * c + k], std::to_string(m.cells[c][k]));
    EXPECT_EQ(offsets[c], std::to_string(4 * (c + 1)));
    EXPECT_EQ(types[c], "10");  // VTK_TETRA
  }
  const auto level = ascii_array(xml, "level", "Int32");
  const auto boundary = ascii_array(xml, "boundary", "UInt8");
  ASSERT_EQ(level.size(), m.points.size());
  ASSERT_EQ(boundary.size(), m.points.size());
  for (size_t i = 0; i < m.points.size(); ++i) {
    EXPECT_EQ(level[i], std::to_string(m.level[i]));
    EXPECT_EQ(boundary[i], std::to_string(m.boundary[i]));
  }
}

}  // namespace
}  // namespace dtm
