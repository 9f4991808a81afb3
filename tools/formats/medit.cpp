#include "medit.h"

#include <map>
#include <set>

#include "render_util.h"
#include "text_cursor.h"

namespace dtm {
namespace {

// Sections other than Vertices that we read past: how many vertex indices and
// how many trailing integers (refs) each record has, or reals for vectors.
struct SectionLayout {
  int indices;   // vertex indices (checked against the vertex count)
  int integers;  // other integers (refs, element numbers)
  int reals;
};
const std::map<std::string, SectionLayout, std::less<>>& sections() {
  static const std::map<std::string, SectionLayout, std::less<>> kSections = {
      {"Edges", {2, 1, 0}},
      {"Triangles", {3, 1, 0}},
      {"Quadrilaterals", {4, 1, 0}},
      {"Tetrahedra", {4, 1, 0}},
      {"Pyramids", {5, 1, 0}},
      {"Prisms", {6, 1, 0}},
      {"Hexahedra", {8, 1, 0}},
      {"Hexaedra", {8, 1, 0}},
      {"Corners", {1, 0, 0}},
      {"RequiredVertices", {1, 0, 0}},
      {"Ridges", {0, 1, 0}},
      {"RequiredEdges", {0, 1, 0}},
      {"RequiredTriangles", {0, 1, 0}},
      {"RequiredQuadrilaterals", {0, 1, 0}},
      {"Normals", {0, 0, 3}},
      {"Tangents", {0, 0, 3}},
      {"NormalAtVertices", {1, 1, 0}},
      {"TangentAtVertices", {1, 1, 0}},
      {"TangentAtEdges", {0, 3, 0}}};
  return kSections;
}

}  // namespace

InputMesh read_medit(const std::string& path) {
  TextCursor c = TextCursor::open(path, '#');
  if (c.at_end()) c.fail("empty file, expected 'MeshVersionFormatted'");
  c.expect("MeshVersionFormatted");
  const int version = c.number<int>("a format version");
  if (version < 1 || version > 4) c.fail("unknown MeshVersionFormatted " + std::to_string(version));
  InputMesh out;
  bool have_dimension = false, have_vertices = false;
  std::vector<std::array<int64_t, 4>> tets;       // 1-based until the vertex count is known
  std::map<std::string, uint64_t> other_records;  // records of other sections, by keyword
  while (true) {
    if (c.at_end()) c.fail("file ends without 'End'");
    const std::string keyword(c.token("a section keyword"));
    if (keyword == "End") break;
    if (keyword == "Dimension") {
      const int dim = c.number<int>("a dimension");
      if (dim != 3) c.fail("dimension must be 3, got " + std::to_string(dim));
      have_dimension = true;
      continue;
    }
    if (!have_dimension) c.fail("'" + keyword + "' before 'Dimension 3'");
    const uint64_t limit = c.remaining() / 2;  // every value takes two bytes at least
    if (keyword == "Vertices") {
      if (have_vertices) c.fail("a second 'Vertices' section");
      have_vertices = true;
      const uint64_t n = c.count("a vertex count", limit / 4);
      out.points.reserve(n);
      VertexField ref{"ref", 1, {}, ScalarType::kInt32};
      ref.values.reserve(n);
      for (uint64_t i = 0; i < n; ++i) {
        const double x = c.coordinate(), y = c.coordinate(), z = c.coordinate();
        out.points.push_back({x, y, z});
        ref.values.push_back(static_cast<double>(c.number<int64_t>("a vertex ref")));
      }
      out.fields.push_back(std::move(ref));
      continue;
    }
    const auto layout = sections().find(keyword);
    if (layout == sections().end()) c.fail("unknown or unsupported section '" + keyword + "'");
    const auto [indices, integers, reals] = layout->second;
    if (indices > 0 && !have_vertices) c.fail("'" + keyword + "' before 'Vertices'");
    const uint64_t n = c.count("a record count", limit / (indices + integers + reals));
    if (keyword != "Tetrahedra" && keyword != "Triangles" && n > 0) other_records[keyword] += n;
    for (uint64_t i = 0; i < n; ++i) {
      std::array<int64_t, 8> v{};
      for (int k = 0; k < indices; ++k) {
        v[k] = c.number<int64_t>("a vertex index");
        if (v[k] < 1 || static_cast<uint64_t>(v[k]) > out.points.size())
          c.fail("vertex index " + std::to_string(v[k]) + " out of range 1.." +
                 std::to_string(out.points.size()));
      }
      for (int k = 0; k < integers; ++k) {
        const int64_t value = c.number<int64_t>("an integer");
        // A tetrahedron's integer is its ref: its region.
        if (keyword == "Tetrahedra" && k == 0) {
          if (value < INT32_MIN || value > INT32_MAX) c.fail("a tetrahedron's ref out of the 32-bit range");
          out.tet_regions.push_back(static_cast<int32_t>(value));
        }
        // A triangle's is its tag (a boundary condition's patch).
        if (keyword == "Triangles" && k == 0) {
          if (value < INT32_MIN || value > INT32_MAX) c.fail("a triangle's ref out of the 32-bit range");
          out.face_tags.push_back(static_cast<int32_t>(value));
        }
      }
      for (int k = 0; k < reals; ++k) c.coordinate();
      if (keyword == "Tetrahedra") tets.push_back({v[0], v[1], v[2], v[3]});
      if (keyword == "Triangles")
        out.tagged_faces.push_back({static_cast<uint32_t>(v[0] - 1), static_cast<uint32_t>(v[1] - 1),
                                    static_cast<uint32_t>(v[2] - 1)});
    }
  }
  if (!other_records.empty()) {
    std::string list;
    for (const auto& [keyword, count] : other_records)
      list += (list.empty() ? "" : ", ") + std::to_string(count) + " " + keyword;
    out.left_out.push_back("sections other than Vertices, Triangles and Tetrahedra (" + list + ")");
  }
  if (!c.at_end()) c.fail("unexpected data after 'End'");
  if (!out.tet_regions.empty()) out.region_source = "tetrahedron refs";
  if (!out.tagged_faces.empty()) out.face_tag_source = "triangle refs";
  if (!have_vertices) throw FormatError(path + ": no 'Vertices' section");
  for (const auto& t : tets)
    out.tets.push_back({static_cast<uint32_t>(t[0] - 1), static_cast<uint32_t>(t[1] - 1),
                        static_cast<uint32_t>(t[2] - 1), static_cast<uint32_t>(t[3] - 1)});
  return out;
}

std::string render_medit(const OutputMesh& m) {
  std::string out = "MeshVersionFormatted 2\n# written by dtmesh\n\nDimension 3\n\nVertices\n";
  append_number(out, m.points.size());
  out += '\n';
  for (size_t i = 0; i < m.points.size(); ++i) {
    const InputPoint p = m.grid.to_input(m.points[i]);
    for (double x : {p.x, p.y, p.z}) {
      append_number(out, x);
      out += ' ';
    }
    append_number(out, m.boundary.empty() ? 0 : int{m.boundary[i]});
    out += '\n';
  }
  // The tagged faces, their refs the tags.
  if (!m.faces.empty()) {
    out += "\nTriangles\n";
    append_number(out, m.faces.size());
    out += '\n';
    for (size_t f = 0; f < m.faces.size(); ++f) {
      for (uint32_t v : m.faces[f]) {
        append_number(out, uint64_t{v} + 1);
        out += ' ';
      }
      append_number(out, m.face_tags[f]);
      out += '\n';
    }
  }
  out += "\nTetrahedra\n";
  append_number(out, m.cells.size());
  out += '\n';
  // A tetrahedron's ref is its region (1 without regions).
  for (size_t c = 0; c < m.cells.size(); ++c) {
    for (uint32_t v : m.cells[c]) {
      append_number(out, uint64_t{v} + 1);
      out += ' ';
    }
    append_number(out, m.region.empty() ? 1 : m.region[c]);
    out += '\n';
  }
  out += "\nEnd\n";
  return out;
}

}  // namespace dtm
