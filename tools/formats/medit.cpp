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
#include "second_order.h"
#include "text_cursor.h"

namespace dtm {
namespace {

// What a section's records are read as: tetrahedra (the regions by their
// refs), triangles (tagged faces by their refs), cells split into
// tetrahedra or triangles (cell_split.h), or records read past.
enum class Kept { kNo, kTetrahedra, kTriangles, kSplit };

// Sections other than Vertices: how many vertex indices and how many
// trailing integers (refs) each record has, or reals for vectors; what it
// is read as, and how many of its indices are corners (the rest a
// second-order element's other nodes, as gmsh writes TetrahedraP2: the
// edges (0,1) (1,2) (0,2) (0,3) (1,3) (2,3), VTK's order).
struct SectionLayout {
  int indices;   // vertex indices (checked against the vertex count)
  int integers;  // other integers (refs, element numbers)
  int reals;
  Kept kept = Kept::kNo;
  int corners = 0;
  // gmsh writes its second-order quadrilaterals (9 nodes) and hexahedra
  // (27) under the linear keywords: the records' other layout, corners
  // first, tried when the first does not fit (0: none).
  int second_order_indices = 0;
};
const std::map<std::string, SectionLayout, std::less<>>& sections() {
  static const std::map<std::string, SectionLayout, std::less<>> kSections = {
      {"Edges", {2, 1, 0}},
      {"EdgesP2", {3, 1, 0}},
      {"Triangles", {3, 1, 0, Kept::kTriangles, 3}},
      {"TrianglesP2", {6, 1, 0, Kept::kTriangles, 3}},
      {"Quadrilaterals", {4, 1, 0, Kept::kSplit, 4, 9}},
      {"Tetrahedra", {4, 1, 0, Kept::kTetrahedra, 4}},
      {"TetrahedraP2", {10, 1, 0, Kept::kTetrahedra, 4}},
      {"Pyramids", {5, 1, 0, Kept::kSplit, 5}},
      {"Prisms", {6, 1, 0, Kept::kSplit, 6}},
      {"Hexahedra", {8, 1, 0, Kept::kSplit, 8, 27}},
      {"Hexaedra", {8, 1, 0, Kept::kSplit, 8, 27}},
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

// A TetrahedraP2 record's edge nodes in kTetEdges' order (second_order.h).
constexpr std::array<size_t, 6> kP2TetEdgeNodes = {4, 6, 7, 5, 8, 9};

// A section's `n` records one a line, as Netgen, MMG, gmsh and meshio write
// them, parsed on every core: record(i, fields) for each, its `count`
// fields split at blanks. False, with the cursor where it was, when a line
// is not one whole record that record() takes (records split over lines or
// joined on one, a comment, a blank line, a value out of range): then the
// caller reads the section token by token, as the format allows, with its
// checks and its errors at their lines.
bool read_one_a_line(TextCursor& c, uint64_t n, size_t count,
                     const std::function<bool(uint64_t, std::span<const std::string_view>)>& record) {
  constexpr size_t kMostFields = 28;  // a 27-node hexahedron and its ref
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
    if (keyword == "Identifier" || keyword == "Geometry") {
      // (libMeshb's: a string, on this line or the next; a Geometry names
      // the file of the geometry, which is not read.)
      std::string_view text = c.rest_of_line();
      if (text.find_first_not_of(" \t\r") == std::string_view::npos) text = c.rest_of_line();
      if (keyword == "Geometry") other_records["Geometry"] += 1;
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
    const Kept kept = layout->second.kept;
    const auto corners = static_cast<size_t>(layout->second.corners);
    if (indices > 0 && !have_vertices) c.fail("'" + keyword + "' before 'Vertices'");
    const uint64_t n = c.count("a record count", limit / (indices + integers + reals));
    if (kept == Kept::kNo && n > 0) other_records[keyword] += n;
    // The records kept: their vertices (0-based) and refs, added to the
    // mesh once the section is read.
    auto width = static_cast<size_t>(indices);
    std::vector<uint32_t> nodes(kept == Kept::kNo ? 0 : n * width);
    std::vector<int32_t> refs(kept == Kept::kNo ? 0 : n);
    const uint64_t vertices = out.points.size();
    // The record's fields: its indices, then its integers, then its reals.
    size_t first_integer = width, first_real = first_integer + static_cast<size_t>(integers);
    size_t fields = first_real + static_cast<size_t>(reals);
    const auto one_a_line = [&] {
      return read_one_a_line(c, n, fields, [&](uint64_t i, std::span<const std::string_view> f) {
        for (size_t k = 0; k < first_integer; ++k) {
          int64_t v = 0;
          if (!parse_whole(f[k], v) || v < 1 || static_cast<uint64_t>(v) > vertices) return false;
          if (kept != Kept::kNo) nodes[i * width + k] = static_cast<uint32_t>(v - 1);
        }
        for (size_t k = first_integer; k < first_real; ++k) {
          int64_t value = 0;
          if (!parse_whole(f[k], value)) return false;
          if (k == first_integer && kept != Kept::kNo) {
            if (value < INT32_MIN || value > INT32_MAX) return false;
            refs[i] = static_cast<int32_t>(value);
          }
        }
        for (size_t k = first_real; k < fields; ++k) {
          double x = 0;
          if (!parse_whole(f[k], x) || !std::isfinite(x)) return false;
        }
        return true;
      });
    };
    bool fast = one_a_line();
    if (!fast && layout->second.second_order_indices > 0) {
      // (gmsh's second-order records under the linear keyword, one a line.)
      width = static_cast<size_t>(layout->second.second_order_indices);
      first_integer = width, first_real = width + static_cast<size_t>(integers);
      fields = first_real + static_cast<size_t>(reals);
      nodes.assign(n * width, 0);
      fast = one_a_line();
      if (!fast) {
        width = static_cast<size_t>(indices);
        nodes.assign(n * width, 0);
      }
    }
    if (!fast) {
      for (uint64_t i = 0; i < n; ++i) {
        for (size_t k = 0; k < width; ++k) {
          const auto v = c.number<int64_t>("a vertex index");
          if (v < 1 || static_cast<uint64_t>(v) > out.points.size())
            c.fail("vertex index " + std::to_string(v) + " out of range 1.." +
                   std::to_string(out.points.size()));
          if (kept != Kept::kNo) nodes[i * width + k] = static_cast<uint32_t>(v - 1);
        }
        for (int k = 0; k < integers; ++k) {
          const int64_t value = c.number<int64_t>("an integer");
          // A cell's first integer is its ref: a tetrahedron's (and a
          // split cell's) its region, a triangle's (and a
          // quadrilateral's) its tag, a boundary condition's patch.
          if (kept != Kept::kNo && k == 0) {
            if (value < INT32_MIN || value > INT32_MAX) c.fail("a cell's ref out of the 32-bit range");
            refs[i] = static_cast<int32_t>(value);
          }
        }
        for (int k = 0; k < reals; ++k) c.coordinate();
      }
    }
    for (uint64_t i = 0; i < refs.size(); ++i) {
      const std::span<const uint32_t> record(nodes.data() + i * width, width);
      switch (kept) {
        case Kept::kTetrahedra:
          out.tets.push_back({record[0], record[1], record[2], record[3]});
          out.tet_regions.push_back(refs[i]);
          // (A second-order one's edge nodes go aside: second_order.h.)
          if (width == 10) {
            std::array<uint32_t, 6> edge;
            for (size_t e = 0; e < 6; ++e) edge[e] = record[kP2TetEdgeNodes[e]];
            add_tet_edge_nodes(out, edge);
          }
          break;
        case Kept::kTriangles:
          out.tagged_faces.push_back({record[0], record[1], record[2]});
          out.face_tags.push_back(refs[i]);
          out.other_edge_nodes.insert(out.other_edge_nodes.end(), record.begin() + 3, record.end());
          break;
        case Kept::kSplit: {
          const size_t added = add_split_cell(record, corners, out);
          auto& labels = corners == 4 ? out.face_tags : out.tet_regions;
          labels.insert(labels.end(), added, refs[i]);
          if (corners > 4) ++split_cells[corners];
          had_quads |= corners == 4;
          break;
        }
        case Kept::kNo:
          break;
      }
    }
  }
  if (!other_records.empty()) {
    std::string list;
    for (const auto& [keyword, count] : other_records)
      list += (list.empty() ? "" : ", ") + std::to_string(count) + " " + keyword;
    out.left_out.push_back(
        "sections other than Vertices, Triangles, Quadrilaterals, Tetrahedra, Pyramids, Prisms, "
        "Hexahedra, TrianglesP2 and TetrahedraP2 (" +
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
