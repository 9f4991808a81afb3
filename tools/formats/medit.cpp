#include "medit.h"

#include <array>
#include <atomic>
#include <cmath>
#include <functional>
#include <map>
#include <set>
#include <span>

#include "cell_split.h"
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

// A record's first N vertex indices (1-based, checked against the vertex
// count) as 0-based ids.
template <size_t N>
std::array<uint32_t, N> zero_based(const std::array<int64_t, 8>& v) {
  std::array<uint32_t, N> out{};
  for (size_t k = 0; k < N; ++k) out[k] = static_cast<uint32_t>(v[k] - 1);
  return out;
}

// A section's `n` records one a line, as Netgen, MMG, gmsh and meshio write
// them, parsed on every core: record(i, fields) for each, its `count`
// fields split at blanks. False, with the cursor where it was, when a line
// is not one whole record that record() takes (records split over lines or
// joined on one, a comment, a blank line, a value out of range): then the
// caller reads the section token by token, as the format allows, with its
// checks and its errors at their lines.
bool read_one_a_line(TextCursor& c, uint64_t n, size_t count,
                     const std::function<bool(uint64_t, std::span<const std::string_view>)>& record) {
  constexpr size_t kMostFields = 12;
  if (count > kMostFields) return false;
  const TextCursor::Mark start = c.mark();
  // The count's line ends after the count.
  size_t after_count = 0;
  if (!next_field(c.rest_of_line(), after_count).empty()) {
    c.restore(start);
    return false;
  }
  std::atomic<bool> whole{true};
  c.lines(n, [&](uint64_t i, std::string_view line) {
    if (!whole.load(std::memory_order_relaxed)) return;
    std::array<std::string_view, kMostFields + 1> fields;
    size_t k = 0, at = 0;
    for (std::string_view f = next_field(line, at); !f.empty() && k <= count; f = next_field(line, at))
      fields[k++] = f;
    if (k != count || line.find('#') != std::string_view::npos ||
        !record(i, std::span<const std::string_view>(fields.data(), count)))
      whole.store(false, std::memory_order_relaxed);
  });
  if (whole.load()) return true;
  c.restore(start);
  return false;
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
  std::map<std::string, uint64_t> other_records;  // records of other sections, by keyword
  std::map<size_t, uint64_t> split_cells;         // the cells split into tetrahedra, by corners
  bool had_quads = false;
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
      VertexField ref{"ref", 1, {}, ScalarType::kInt32};
      out.points.resize(n);
      ref.values.resize(n);
      const bool fast = read_one_a_line(c, n, 4, [&](uint64_t i, std::span<const std::string_view> f) {
        double x = 0, y = 0, z = 0;
        int64_t r = 0;
        if (!parse_whole(f[0], x) || !parse_whole(f[1], y) || !parse_whole(f[2], z) ||
            !parse_whole(f[3], r) || !std::isfinite(x) || !std::isfinite(y) || !std::isfinite(z))
          return false;
        out.points[i] = {x, y, z};
        ref.values[i] = static_cast<double>(r);
        return true;
      });
      if (!fast) {
        out.points.clear();
        ref.values.clear();
        for (uint64_t i = 0; i < n; ++i) {
          const double x = c.coordinate(), y = c.coordinate(), z = c.coordinate();
          out.points.push_back({x, y, z});
          ref.values.push_back(static_cast<double>(c.number<int64_t>("a vertex ref")));
        }
      }
      out.fields.push_back(std::move(ref));
      continue;
    }
    const auto layout = sections().find(keyword);
    if (layout == sections().end()) c.fail("unknown or unsupported section '" + keyword + "'");
    // (Not a structured binding: the record's lambda below reads them.)
    const int indices = layout->second.indices, integers = layout->second.integers,
              reals = layout->second.reals;
    if (indices > 0 && !have_vertices) c.fail("'" + keyword + "' before 'Vertices'");
    const uint64_t n = c.count("a record count", limit / (indices + integers + reals));
    const bool is_tets = keyword == "Tetrahedra", is_faces = keyword == "Triangles";
    // Quadrilaterals, pyramids, prisms and hexahedra: read whole, then split
    // (cell_split.h), each piece with the record's ref.
    const bool is_split = keyword == "Quadrilaterals" || keyword == "Pyramids" || keyword == "Prisms" ||
                          keyword == "Hexahedra" || keyword == "Hexaedra";
    if (!is_tets && !is_faces && !is_split && n > 0) other_records[keyword] += n;
    std::vector<std::array<uint32_t, 8>> split_nodes(is_split ? n : 0);
    std::vector<int32_t> split_refs(is_split ? n : 0);
    const size_t tets_before = out.tets.size(), regions_before = out.tet_regions.size();
    const size_t faces_before = out.tagged_faces.size(), tags_before = out.face_tags.size();
    if (is_tets) out.tets.resize(tets_before + n), out.tet_regions.resize(regions_before + n);
    if (is_faces) out.tagged_faces.resize(faces_before + n), out.face_tags.resize(tags_before + n);
    const uint64_t vertices = out.points.size();
    // The record's fields: its indices, then its integers, then its reals.
    const auto first_integer = static_cast<size_t>(indices),
               first_real = first_integer + static_cast<size_t>(integers);
    const size_t fields = first_real + static_cast<size_t>(reals);
    const bool fast = read_one_a_line(c, n, fields, [&](uint64_t i, std::span<const std::string_view> f) {
      std::array<int64_t, 8> v{};
      for (size_t k = 0; k < first_integer; ++k)
        if (!parse_whole(f[k], v[k]) || v[k] < 1 || static_cast<uint64_t>(v[k]) > vertices) return false;
      for (size_t k = first_integer; k < first_real; ++k) {
        int64_t value = 0;
        if (!parse_whole(f[k], value)) return false;
        if (k == first_integer && (is_tets || is_faces || is_split)) {
          if (value < INT32_MIN || value > INT32_MAX) return false;
          (is_tets    ? out.tet_regions[regions_before + i]
           : is_faces ? out.face_tags[tags_before + i]
                      : split_refs[i]) = static_cast<int32_t>(value);
        }
      }
      for (size_t k = first_real; k < fields; ++k) {
        double x = 0;
        if (!parse_whole(f[k], x) || !std::isfinite(x)) return false;
      }
      if (is_tets) out.tets[tets_before + i] = zero_based<4>(v);
      if (is_faces) out.tagged_faces[faces_before + i] = zero_based<3>(v);
      if (is_split) split_nodes[i] = zero_based<8>(v);
      return true;
    });
    const auto add_split_cells = [&] {
      for (uint64_t i = 0; i < split_nodes.size(); ++i) {
        const size_t corners = static_cast<size_t>(indices);
        const size_t added = add_split_cell(std::span(split_nodes[i]).first(corners), corners, out);
        auto& labels = corners == 4 ? out.face_tags : out.tet_regions;
        labels.insert(labels.end(), added, split_refs[i]);
        if (corners > 4) ++split_cells[corners];
        had_quads |= corners == 4;
      }
    };
    if (fast) {
      add_split_cells();
      continue;
    }
    out.tets.resize(tets_before), out.tet_regions.resize(regions_before);
    out.tagged_faces.resize(faces_before), out.face_tags.resize(tags_before);
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
        // Another cell's is its region, a quadrilateral's its tag.
        if (is_split && k == 0) {
          if (value < INT32_MIN || value > INT32_MAX) c.fail("a cell's ref out of the 32-bit range");
          split_refs[i] = static_cast<int32_t>(value);
        }
      }
      for (int k = 0; k < reals; ++k) c.coordinate();
      if (is_tets) out.tets.push_back(zero_based<4>(v));
      if (is_faces) out.tagged_faces.push_back(zero_based<3>(v));
      if (is_split) split_nodes[i] = zero_based<8>(v);
    }
    add_split_cells();
  }
  if (!other_records.empty()) {
    std::string list;
    for (const auto& [keyword, count] : other_records)
      list += (list.empty() ? "" : ", ") + std::to_string(count) + " " + keyword;
    out.left_out.push_back(
        "sections other than Vertices, Triangles, Quadrilaterals, Tetrahedra, Pyramids, Prisms and "
        "Hexahedra (" +
        list + ")");
  }
  if (!split_cells.empty()) out.left_out.push_back(split_cells_note(split_cells));
  if (!c.at_end()) c.fail("unexpected data after 'End'");
  if (!out.tet_regions.empty()) out.region_source = split_cells.empty() ? "tetrahedron refs" : "cell refs";
  if (!out.tagged_faces.empty())
    out.face_tag_source = had_quads ? "triangle and quadrilateral refs" : "triangle refs";
  if (!have_vertices) throw FormatError(path + ": no 'Vertices' section");
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
