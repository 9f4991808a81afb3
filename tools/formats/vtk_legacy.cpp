#include "vtk_legacy.h"

#include <charconv>
#include <cmath>
#include <map>
#include <optional>
#include <span>

#include "cell_split.h"
#include "common/parallel_for.h"
#include "render_util.h"
#include "scalar_type.h"
#include "second_order.h"
#include "text_cursor.h"
#include "vtk_cells.h"

namespace dtm {
namespace {

std::optional<ScalarType> legacy_type(std::string_view name) {
  static const std::map<std::string, ScalarType, std::less<>> kTypes = {
      {"char", ScalarType::kInt8},
      {"unsigned_char", ScalarType::kUInt8},
      {"short", ScalarType::kInt16},
      {"unsigned_short", ScalarType::kUInt16},
      {"int", ScalarType::kInt32},
      {"unsigned_int", ScalarType::kUInt32},
      {"long", ScalarType::kInt64},
      {"unsigned_long", ScalarType::kUInt64},
      // (VTK 9's and meshio's names of the fixed-size types.)
      {"vtktypeint8", ScalarType::kInt8},
      {"vtktypeuint8", ScalarType::kUInt8},
      {"vtktypeint16", ScalarType::kInt16},
      {"vtktypeuint16", ScalarType::kUInt16},
      {"vtktypeint32", ScalarType::kInt32},
      {"vtktypeuint32", ScalarType::kUInt32},
      {"vtktypeint64", ScalarType::kInt64},
      {"vtktypeuint64", ScalarType::kUInt64},
      {"vtktypefloat32", ScalarType::kFloat32},
      {"vtktypefloat64", ScalarType::kFloat64},
      {"vtkIdType", ScalarType::kInt64},
      {"float", ScalarType::kFloat32},
      {"double", ScalarType::kFloat64}};
  const auto it = kTypes.find(name);
  if (it == kTypes.end()) return std::nullopt;
  return it->second;
}

class LegacyReader {
 public:
  explicit LegacyReader(const std::string& path) : c_(TextCursor::open(path)) {}

  InputMesh read() {
    if (c_.remaining() == 0) c_.fail("empty file, expected '# vtk DataFile Version'");
    const std::string_view magic = c_.rest_of_line();
    if (magic.substr(0, 22) != "# vtk DataFile Version")
      c_.fail("not a VTK legacy file (expected '# vtk DataFile Version x.y')");
    c_.rest_of_line();  // title
    const std::string_view mode = c_.token("ASCII or BINARY");
    if (mode != "ASCII" && mode != "BINARY")
      c_.fail("expected ASCII or BINARY, found '" + std::string(mode) + "'");
    binary_ = mode == "BINARY";
    c_.expect("DATASET");
    const std::string_view kind = c_.token("a dataset type");
    if (kind != "UNSTRUCTURED_GRID")
      c_.fail("only UNSTRUCTURED_GRID datasets are supported, got '" + std::string(kind) + "'");

    bool have_points = false;
    std::vector<int64_t> cell_offsets, connectivity, cell_types;
    uint64_t data_count = 0;  // tuples per array in the current POINT_DATA / CELL_DATA
    bool in_point_data = false, in_data = false;
    while (!c_.at_end()) {
      const std::string key(c_.token("a keyword"));
      if (key == "POINTS") {
        if (have_points) c_.fail("a second POINTS section");
        have_points = true;
        const uint64_t n = c_.count("a point count", c_.remaining() / 3);
        const auto xyz = array(3 * n, c_.token("a point type"));
        out_.points.reserve(n);
        for (uint64_t i = 0; i < n; ++i) out_.points.push_back({xyz[3 * i], xyz[3 * i + 1], xyz[3 * i + 2]});
        for (double v : xyz)
          if (!std::isfinite(v)) c_.fail("a point coordinate is not finite");
      } else if (key == "CELLS") {
        read_cells(cell_offsets, connectivity);
      } else if (key == "CELL_TYPES") {
        const uint64_t n = c_.count("a cell count", c_.remaining());
        for (double t : array(n, "int")) cell_types.push_back(whole(t, "a cell type"));
      } else if (key == "POINT_DATA" || key == "CELL_DATA") {
        data_count = c_.count("a tuple count", c_.remaining());
        in_point_data = key == "POINT_DATA";
        in_data = true;
        if (in_point_data && data_count != out_.points.size())
          c_.fail("POINT_DATA " + std::to_string(data_count) + " for " + std::to_string(out_.points.size()) +
                  " points");
      } else if (key == "SCALARS" || key == "VECTORS" || key == "NORMALS" || key == "TEXTURE_COORDINATES" ||
                 key == "TENSORS") {
        if (!in_data) c_.fail(key + " outside POINT_DATA or CELL_DATA");
        VertexField f{unescaped(c_.token("an array name")), 3, {}};
        if (key == "TENSORS") f.components = 9;
        if (key == "TEXTURE_COORDINATES") f.components = c_.number<int>("a dimension");
        const std::string type(c_.token("a value type"));
        if (key == "SCALARS") {
          // "SCALARS name type [components]", then "LOOKUP_TABLE name" on its own line.
          f.components = 1;
          if (const std::string_view rest = c_.rest_of_line();
              rest.find_first_not_of(" \t") != std::string_view::npos) {
            const std::string_view n = rest.substr(rest.find_first_not_of(" \t"));
            const auto [end, ec] = std::from_chars(n.data(), n.data() + n.size(), f.components);
            if (ec != std::errc() ||
                n.substr(end - n.data()).find_first_not_of(" \t") != std::string_view::npos)
              c_.fail("expected a component count, found '" + std::string(n) + "'");
          }
          c_.expect("LOOKUP_TABLE");
          c_.token("a lookup table name");
        }
        if (f.components < 1 || f.components > 9)
          c_.fail("bad component count " + std::to_string(f.components));
        f.values = array(data_count * f.components, type);
        if (const auto t = legacy_type(type)) f.type = *t;
        if (in_point_data)
          out_.fields.push_back(std::move(f));
        else
          cell_data_.push_back(std::move(f));
      } else if (key == "FIELD") {
        c_.token("a field name");
        const uint64_t arrays = c_.count("an array count", c_.remaining() / 4);
        for (uint64_t a = 0; a < arrays; ++a) {
          VertexField f{unescaped(c_.token("an array name")), 0, {}};
          f.components = c_.number<int>("a component count");
          const uint64_t tuples = c_.count("a tuple count", c_.remaining());
          if (f.components < 1 || f.components > 64)
            c_.fail("bad component count " + std::to_string(f.components));
          const std::string type(c_.token("a value type"));
          if (type == "string") {
            // Text, one value a line (in ASCII): read past, named.
            if (binary_)
              c_.fail("the string array '" + f.name +
                      "' of a BINARY file is not read (save it as ASCII or .vtu)");
            c_.skip_to_next_line();
            for (uint64_t v = 0; v < tuples * static_cast<uint64_t>(f.components); ++v) {
              if (c_.remaining() == 0) c_.fail("file ends inside the string array '" + f.name + "'");
              c_.rest_of_line();
            }
            skip_metadata();
            string_arrays_.push_back("'" + f.name + "'");
            continue;
          }
          f.values = array(tuples * f.components, type);
          if (const auto t = legacy_type(type)) f.type = *t;
          skip_metadata();  // (VTK >= 8: after each array of a FIELD)
          if (!in_data) {
            dataset_arrays_.push_back("'" + f.name + "'");  // the dataset's own (TimeValue, ...)
          } else if (in_point_data && data_count > 0) {
            if (tuples != out_.points.size())
              c_.fail("array '" + f.name + "' has " + std::to_string(tuples) + " tuples for " +
                      std::to_string(out_.points.size()) + " points");
            out_.fields.push_back(std::move(f));
          } else if (!in_point_data && in_data) {
            if (tuples != data_count)
              c_.fail("array '" + f.name + "' has " + std::to_string(tuples) + " tuples in CELL_DATA " +
                      std::to_string(data_count));
            cell_data_.push_back(std::move(f));
          }
        }
      } else if (key == "METADATA") {
        skip_metadata_block();
      } else {
        c_.fail("unknown or unsupported keyword '" + key + "'");
      }
    }
    if (!have_points) throw FormatError(c_.path() + ": no POINTS section");
    const size_t cells = cell_offsets.empty() ? 0 : cell_offsets.size() - 1;
    std::vector<size_t> tet_cells;       // the VTK cell index of each tetrahedron
    std::vector<size_t> triangle_cells;  // and of each triangle
    if (cell_offsets.size() > 1 || !cell_types.empty()) {
      if (cell_types.size() != cells)
        throw FormatError(c_.path() + ": " + std::to_string(cell_types.size()) + " CELL_TYPES for " +
                          std::to_string(cells) + " CELLS");
      for (size_t i = 0; i < cell_types.size(); ++i) {
        const int64_t b = cell_offsets[i], e = cell_offsets[i + 1];
        for (int64_t k = b; k < e; ++k)
          if (connectivity[k] < 0 || static_cast<uint64_t>(connectivity[k]) >= out_.points.size())
            throw FormatError(c_.path() + ": cell " + std::to_string(i) + ": point index " +
                              std::to_string(connectivity[k]) + " out of range");
        // Triangles may carry tags (InputMesh::tagged_faces, as meshdec
        // writes them after the tetrahedra): held, tagged or named by
        // choose_regions().
        // (A quadratic one's edge nodes go aside: second_order.h.)
        const auto at = [&](int64_t k) { return static_cast<uint32_t>(connectivity[k]); };
        if ((cell_types[i] == kVtkTriangle && e - b == 3) ||
            (cell_types[i] == kVtkQuadraticTriangle && e - b == 6)) {
          out_.tagged_faces.push_back({at(b), at(b + 1), at(b + 2)});
          for (int64_t k = b + 3; k < e; ++k) out_.other_edge_nodes.push_back(at(k));
          triangle_cells.push_back(i);
          continue;
        }
        // A quadrilateral as two triangles, a hexahedron, wedge or pyramid
        // as its tetrahedra (cell_split.h), each with the cell's data.
        // (A second-order one's other nodes go aside: second_order.h.)
        if (const VtkSplitType split = vtk_split_type(static_cast<double>(cell_types[i]));
            split.corners > 0 && static_cast<size_t>(e - b) == split.nodes) {
          std::array<uint32_t, 27> nodes{};
          for (size_t k = 0; k < split.nodes; ++k) nodes[k] = at(b + static_cast<int64_t>(k));
          const size_t added = add_split_cell(std::span(nodes).first(split.nodes), split.corners, out_);
          auto& cells_of = split.corners == 4 ? triangle_cells : tet_cells;
          cells_of.insert(cells_of.end(), added, i);
          if (split.corners > 4) ++split_cells_[split.corners];
          continue;
        }
        if (cell_types[i] != kVtkTetra && cell_types[i] != kVtkQuadraticTetra) {
          ++other_cells_[cell_types[i]];
          continue;
        }
        const bool quadratic = cell_types[i] == kVtkQuadraticTetra;
        if (e - b != (quadratic ? 10 : 4))
          throw FormatError(c_.path() + ": cell " + std::to_string(i) + " is a " +
                            (quadratic ? "VTK_QUADRATIC_TETRA" : "VTK_TETRA") + " with " +
                            std::to_string(e - b) + " points");
        out_.tets.push_back({at(b), at(b + 1), at(b + 2), at(b + 3)});
        if (quadratic) {
          std::array<uint32_t, 6> edge;
          for (size_t k = 0; k < 6; ++k) edge[k] = at(b + kVtkTetEdgeNodes[k]);
          add_tet_edge_nodes(out_, edge);
        }
        tet_cells.push_back(i);
      }
    }
    keep_cell_data(cells, tet_cells, triangle_cells);
    // Triangles without tetrahedra are a surface, not tagged faces.
    if (tet_cells.empty() && !triangle_cells.empty()) {
      for (size_t k = 0; k < triangle_cells.size(); ++k)  // (a quadrilateral's two halves: one cell)
        if (k == 0 || triangle_cells[k] != triangle_cells[k - 1])
          ++other_cells_[cell_types[triangle_cells[k]]];
      out_.tagged_faces.clear();
      out_.other_edge_nodes.clear();
      out_.triangle_arrays.clear();
    }
    note_left_out();
    return std::move(out_);
  }

 private:
  // An array name as VTK writes it: a blank or another byte it escapes as
  // %XX (two hex digits).
  static std::string unescaped(std::string_view name) {
    std::string out;
    for (size_t i = 0; i < name.size(); ++i) {
      unsigned value = 0;
      if (name[i] == '%' && i + 2 < name.size() &&
          std::from_chars(name.data() + i + 1, name.data() + i + 3, value, 16).ptr == name.data() + i + 3) {
        out += static_cast<char>(value);
        i += 2;
      } else {
        out += name[i];
      }
    }
    return out;
  }

  // CELL_DATA on the tetrahedra: an integer array of one component may be
  // the regions (InputMesh::tet_arrays, and on the triangles their tags),
  // any other is cell data.
  void keep_cell_data(size_t cells, const std::vector<size_t>& tet_cells,
                      const std::vector<size_t>& triangle_cells) {
    for (VertexField& f : cell_data_) {
      if (f.values.size() != cells * static_cast<size_t>(f.components))
        throw FormatError(c_.path() + ": CELL_DATA array '" + f.name + "' has " +
                          std::to_string(f.values.size() / static_cast<size_t>(f.components)) +
                          " tuples for " + std::to_string(cells) + " cells");
      if (tet_cells.empty()) {
        cell_arrays_.push_back("'" + f.name + "'");
        continue;
      }
      const auto n = static_cast<size_t>(f.components);
      out_.cell_array_order.push_back(f.name);
      if (n == 1 && is_integer(f.type)) {
        // The array on the tetrahedra (their regions) and on the triangles
        // (the faces' tags), each value a 32-bit integer.
        const auto labels = [&](std::span<const size_t> of, std::vector<int32_t>& into) {
          for (size_t c : of) {
            const double v = f.values[c];
            if (!(v >= INT32_MIN && v <= INT32_MAX))
              throw FormatError(c_.path() + ": CELL_DATA '" + f.name + "': a value out of the 32-bit range");
            into.push_back(static_cast<int32_t>(v));
          }
        };
        labels(tet_cells, out_.tet_arrays[f.name]);
        out_.tet_array_types[f.name] = f.type;
        labels(triangle_cells, out_.triangle_arrays[f.name]);
        continue;
      }
      // (Cell data is the tetrahedra's: its values on the triangles and
      // quadrilaterals, which the mesh keeps as tagged faces, are named.)
      if (any_value_said(triangle_cells.size() * n,
                         [&](size_t i) { return f.values[triangle_cells[i / n] * n + i % n]; }))
        triangle_values_.push_back("'" + f.name + "'");
      VertexField& kept = out_.cell_fields.emplace_back();
      kept.name = f.name, kept.components = f.components, kept.type = f.type;
      kept.values.reserve(tet_cells.size() * n);
      for (size_t c : tet_cells)
        for (size_t j = 0; j < n; ++j) kept.values.push_back(f.values[c * n + j]);
    }
    cell_data_.clear();
  }

  // VTK >= 8 writes an array's information after its data ("METADATA",
  // "INFORMATION n" and its entries, up to a blank line): read past.
  void skip_metadata_block() {
    c_.skip_to_next_line();
    while (c_.remaining() > 0 && !c_.rest_of_line().empty()) {
    }
  }
  void skip_metadata() {
    if (c_.at_end() || c_.peek() != "METADATA") return;
    c_.token("METADATA");
    skip_metadata_block();
  }

  // What the file holds that the mesh read does not (InputMesh::left_out).
  void note_left_out() {
    std::string names;
    for (const std::string& a : cell_arrays_) names += (names.empty() ? "" : ", ") + a;
    if (!names.empty()) out_.left_out.push_back("CELL_DATA arrays " + names);
    std::string on_triangles;
    for (const std::string& a : triangle_values_) on_triangles += (on_triangles.empty() ? "" : ", ") + a;
    if (!on_triangles.empty())
      out_.left_out.push_back("the values of the cell arrays " + on_triangles +
                              " on the triangles (cell data is the tetrahedra's)");
    std::string dataset;
    for (const std::string& a : dataset_arrays_) dataset += (dataset.empty() ? "" : ", ") + a;
    if (!dataset.empty()) out_.left_out.push_back("the dataset's field data " + dataset);
    std::string strings;
    for (const std::string& a : string_arrays_) strings += (strings.empty() ? "" : ", ") + a;
    if (!strings.empty()) out_.left_out.push_back("string arrays " + strings);
    std::string others;
    for (const auto& [type, count] : other_cells_)
      others +=
          (others.empty() ? "" : ", ") + std::to_string(count) + " " + vtk_cell_name(static_cast<int>(type));
    if (!others.empty()) out_.left_out.push_back("cells other than tetrahedra (" + others + ")");
    if (!split_cells_.empty()) out_.left_out.push_back(split_cells_note(split_cells_));
  }

  // `n` values of the named type: text tokens, or big-endian bytes after the
  // end of the current line.
  std::vector<double> array(uint64_t n, std::string_view type_name) {
    const auto type = legacy_type(type_name);
    if (!type) c_.fail("unknown or unsupported value type '" + std::string(type_name) + "'");
    std::vector<double> out;
    if (binary_) {
      c_.skip_to_next_line();
      const int size = scalar_size(*type);
      if (n > c_.remaining() / size)
        c_.fail("file ends: " + std::to_string(n) + " values of type " + std::string(type_name) + " need " +
                std::to_string(n * size) + " bytes, " + std::to_string(c_.remaining()) + " left");
      const std::string_view raw = c_.bytes(n * size, "binary data");
      out.resize(n);
      parallel_for(
          n, [&](size_t i) { out[i] = scalar_at(raw.data() + i * size, *type, true); }, 65536);
    } else {
      if (n > c_.remaining() / 2)
        c_.fail("file ends before the " + std::to_string(n) + " values it announces");
      // On every core; where a value does not parse (or the file ends), one
      // by one for the error at its line.
      out.resize(n);
      const bool integer = is_integer(*type);
      if (c_.tokens(n, [&](uint64_t i, std::string_view t) {
            if (integer) {
              int64_t v = 0;
              if (!parse_whole(t, v)) return false;
              out[i] = static_cast<double>(v);
              return true;
            }
            return parse_whole(t, out[i]);
          }))
        return out;
      out.clear();
      out.reserve(n);
      for (uint64_t i = 0; i < n; ++i) {
        if (is_integer(*type))
          out.push_back(static_cast<double>(c_.number<int64_t>("an integer")));
        else
          out.push_back(c_.number<double>("a number"));
      }
    }
    return out;
  }

  // A value of an integer array as an integer: binary arrays may hold any
  // double, and converting one out of range is undefined behaviour.
  int64_t whole(double v, const char* what) {
    if (!(v >= -4611686018427387904.0 && v <= 4611686018427387904.0) || v != std::floor(v))  // 2^62
      c_.fail(std::string(what) + " is not a whole number in range: " + std::to_string(v));
    return static_cast<int64_t>(v);
  }

  void read_cells(std::vector<int64_t>& offsets, std::vector<int64_t>& connectivity) {
    if (!offsets.empty()) c_.fail("a second CELLS section");
    const uint64_t a = c_.count("a cell count", c_.remaining());
    const uint64_t b = c_.count("a cell list size", c_.remaining());
    if (c_.peek() == "OFFSETS") {  // version 5.1: a = cells + 1, b = connectivity size
      c_.token("OFFSETS");
      for (double v : array(a, c_.token("an offset type"))) offsets.push_back(whole(v, "an offset"));
      c_.expect("CONNECTIVITY");
      for (double v : array(b, c_.token("a connectivity type")))
        connectivity.push_back(whole(v, "a point index"));
      if (a == 0 || offsets.front() != 0 || static_cast<uint64_t>(offsets.back()) != b)
        c_.fail("OFFSETS do not span the CONNECTIVITY of " + std::to_string(b) + " indices");
      for (size_t i = 1; i < offsets.size(); ++i)
        if (offsets[i] < offsets[i - 1]) c_.fail("OFFSETS decrease at cell " + std::to_string(i - 1));
      return;
    }
    // Classic: `a` cells, `b` integers in all, each cell "k i1 .. ik".
    const auto list = array(b, "int");
    offsets.push_back(0);
    size_t at = 0;
    for (uint64_t i = 0; i < a; ++i) {
      if (at >= list.size() || list[at] < 0 || list[at] > static_cast<double>(list.size() - at - 1))
        c_.fail("CELLS: cell " + std::to_string(i) + " runs past the " + std::to_string(b) +
                " integers announced");
      const auto k = static_cast<size_t>(list[at]);
      for (size_t j = 1; j <= k; ++j) connectivity.push_back(whole(list[at + j], "a point index"));
      at += k + 1;
      offsets.push_back(static_cast<int64_t>(connectivity.size()));
    }
    if (at != list.size())
      c_.fail("CELLS: " + std::to_string(a) + " cells use " + std::to_string(at) + " of the " +
              std::to_string(b) + " integers announced");
  }

  TextCursor c_;
  bool binary_ = false;
  InputMesh out_;
  std::vector<std::string> cell_arrays_;      // CELL_DATA arrays left out, quoted
  std::vector<std::string> triangle_values_;  // cell data arrays with values on triangles left out, quoted
  std::vector<std::string> string_arrays_;    // arrays of text, quoted
  std::vector<std::string> dataset_arrays_;   // FIELD arrays outside POINT_DATA and CELL_DATA, quoted
  std::vector<VertexField> cell_data_;        // CELL_DATA arrays, per cell
  std::map<int64_t, uint64_t> other_cells_;   // cells that are not tetrahedra, by VTK type
  std::map<size_t, uint64_t> split_cells_;    // hexahedra, wedges and pyramids, by corner count
};

}  // namespace

InputMesh read_vtk_legacy(const std::string& path) { return LegacyReader(path).read(); }

std::string render_vtk_legacy(const OutputMesh& m, bool binary) {
  std::string out = "# vtk DataFile Version 4.2\nwritten by dtmesh\n";
  out += binary ? "BINARY\n" : "ASCII\n";
  out += "DATASET UNSTRUCTURED_GRID\nPOINTS " + std::to_string(m.points.size()) + " double\n";
  // In ASCII every value is followed by a line break or a space; in BINARY
  // the values are packed and the section ends with one line break.
  auto put = [&](auto v, bool end_of_line) {
    if (binary) {
      append_binary(out, v, true);
    } else {
      append_number(out, v);
      out += end_of_line ? '\n' : ' ';
    }
  };
  auto end_section = [&] {
    if (binary) out += '\n';
  };
  for (const GridPoint& g : m.points) {
    const InputPoint p = m.grid.to_input(g);
    put(p.x, false);
    put(p.y, false);
    put(p.z, true);
  }
  end_section();
  // The tetrahedra, then the tagged faces as triangles (second-order ones
  // with their edge nodes after their corners).
  const size_t cells = m.cells.size() + m.faces.size();
  std::vector<ListedNodes> elements;
  elements.reserve(cells);
  size_t listed = 0;
  for (size_t c = 0; c < m.cells.size(); ++c)
    listed += 1 + elements.emplace_back(cell_nodes(m, c, kVtkEdgeSlots)).count;
  for (size_t f = 0; f < m.faces.size(); ++f) listed += 1 + elements.emplace_back(face_nodes(m, f)).count;
  out += "CELLS " + std::to_string(cells) + " " + std::to_string(listed) + "\n";
  for (const ListedNodes& e : elements) {
    put(static_cast<int32_t>(e.count), false);
    for (size_t k = 0; k < e.count; ++k) put(static_cast<int32_t>(e.nodes[k]), k + 1 == e.count);
  }
  end_section();
  out += "CELL_TYPES " + std::to_string(cells) + "\n";
  for (size_t i = 0; i < cells; ++i) {
    const bool cell = i < m.cells.size(), second = elements[i].second_order();
    put(int32_t{cell ? (second ? kVtkQuadraticTetra : kVtkTetra)
                     : (second ? kVtkQuadraticTriangle : kVtkTriangle)},
        true);
  }
  end_section();
  constexpr const char* kTypeNames[] = {"char",  "unsigned_char", "short",        "unsigned_short",
                                        "int",   "unsigned_int",  "vtktypeint64", "vtktypeuint64",
                                        "float", "double"};
  // An array of a FIELD block: its name (VTK writes a blank inside one as
  // %20), components, tuples and type, then its values.
  const auto field_array = [&](const OutputField& f, size_t tuples) {
    std::string name;
    for (char ch : f.name) name += ch == ' ' ? std::string("%20") : std::string(1, ch);
    out += name + " " + std::to_string(f.components) + " " + std::to_string(tuples) + " " +
           kTypeNames[static_cast<int>(f.type)] + "\n";
    for (size_t i = 0; i < f.bits.size(); ++i) {
      if (binary) {
        append_scalar_binary(out, f.bits[i], f.type, true);
      } else {
        append_scalar_text(out, f.bits[i], f.type);
        out += (i + 1) % f.components == 0 ? '\n' : ' ';
      }
    }
    end_section();
  };
  const std::vector<int32_t> physical = physical_tags(m);
  if (!physical.empty() || !m.cell_fields.empty()) {
    out += "CELL_DATA " + std::to_string(cells) + "\nFIELD FieldData " +
           std::to_string(!physical.empty() + m.cell_fields.size()) + "\n";
    if (!physical.empty()) {
      out += "region 1 " + std::to_string(cells) + " int\n";
      for (int32_t v : physical) put(v, true);
      end_section();
    }
    for (const OutputField& f : cell_and_face_fields(m)) field_array(f, cells);
  }
  // Point data as one FIELD block: VTK's legacy reader keeps only the first
  // SCALARS of a file unless asked for all, but always reads every FIELD array.
  const int arrays = !m.level.empty() + !m.boundary.empty() + static_cast<int>(m.fields.size());
  if (arrays > 0)
    out += "POINT_DATA " + std::to_string(m.points.size()) + "\nFIELD FieldData " + std::to_string(arrays) +
           "\n";
  if (!m.level.empty()) {
    out += "level 1 " + std::to_string(m.points.size()) + " int\n";
    for (int32_t v : m.level) put(v, true);
    end_section();
  }
  if (!m.boundary.empty()) {
    out += "boundary 1 " + std::to_string(m.points.size()) + " unsigned_char\n";
    for (uint8_t v : m.boundary) put(v, true);
    end_section();
  }
  for (const OutputField& f : m.fields) field_array(f, m.points.size());
  return out;
}

}  // namespace dtm
