#include "vtu_reader.h"

#include <algorithm>
#include <array>
#include <bit>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <map>
#include <optional>
#include <set>
#include <span>
#include <unordered_map>

#include "cell_split.h"
#include "common/parallel_for.h"
#include "scalar_type.h"
#include "second_order.h"
#include "text_cursor.h"
#include "vtk_cells.h"
#include "vtk_compression.h"

namespace dtm {
namespace {

// An attribute value with XML's five predefined entities replaced (a field
// named "p&q" is written Name="p&amp;q").
std::string unescaped(const std::string& v) {
  static const std::pair<const char*, char> kEntities[] = {
      {"&amp;", '&'}, {"&lt;", '<'}, {"&gt;", '>'}, {"&quot;", '"'}, {"&apos;", '\''}};
  std::string out;
  for (size_t i = 0; i < v.size();) {
    bool replaced = false;
    if (v[i] == '&')
      for (const auto& [entity, ch] : kEntities)
        if (v.compare(i, std::strlen(entity), entity) == 0) {
          out += ch;
          i += std::strlen(entity);
          replaced = true;
          break;
        }
    if (!replaced) out += v[i++];
  }
  return out;
}

constexpr uint64_t kMaxBlockSize = uint64_t{1} << 26;

struct Element {
  std::string name;
  std::map<std::string, std::string, std::less<>> attrs;
  std::string_view text;  // character data directly inside (DataArray bodies)
  std::vector<size_t> children;
  size_t offset = 0;  // of the start tag, for error messages
  const std::string* attr(std::string_view key) const {
    const auto it = attrs.find(key);
    return it == attrs.end() ? nullptr : &it->second;
  }
};

// A DataArray's name: "unnamed" where it has none, or an empty one (a
// stream's field names have 1 to 64 bytes).
std::string array_name(const Element& da) {
  const std::string* name = da.attr("Name");
  return name && !name->empty() ? *name : "unnamed";
}

// The XML subset VTK writes: declarations, comments, elements with quoted
// attributes, character data; the raw bytes of <AppendedData> are sliced out
// before parsing continues after them.
class VtuParser {
 public:
  explicit VtuParser(const std::string& path) : path_(path), data_(read_whole_file(path)) {}

  void parse() {
    size_t pos = 0;
    std::vector<size_t> stack;
    while (true) {
      const size_t lt = data_.find('<', pos);
      if (lt == std::string::npos) {
        // (Cut short inside an element, or not XML at all, says so.)
        if (!stack.empty()) fail_at(data_.size(), "file ends inside <" + elements_[stack.back()].name + ">");
        if (elements_.empty()) fail_at(0, "no XML element: not a VTK XML file");
        if (data_.find_first_not_of(" \t\r\n", pos) != std::string::npos)
          fail_at(pos, "text after the last element");
        break;
      }
      if (!stack.empty() && elements_[stack.back()].text.empty())
        elements_[stack.back()].text = std::string_view(data_).substr(pos, lt - pos);
      else if (stack.empty() && data_.find_first_not_of(" \t\r\n\xef\xbb\xbf", pos) < lt)
        fail_at(pos, "text outside the root element");
      if (data_.compare(lt, 4, "<!--") == 0) {
        pos = find_or_fail(data_.find("-->", lt), lt, "unterminated comment") + 3;
      } else if (data_.compare(lt, 2, "<?") == 0 || data_.compare(lt, 2, "<!") == 0) {
        pos = find_or_fail(data_.find('>', lt), lt, "unterminated declaration") + 1;
      } else if (data_.compare(lt, 2, "</") == 0) {
        const size_t gt = find_or_fail(data_.find('>', lt), lt, "unterminated end tag");
        const std::string name = trim(data_.substr(lt + 2, gt - lt - 2));
        if (stack.empty() || elements_[stack.back()].name != name)
          fail_at(lt, "end tag </" + name + "> does not match " +
                          (stack.empty() ? std::string("any element")
                                         : "<" + elements_[stack.back()].name + ">"));
        stack.pop_back();
        pos = gt + 1;
      } else {
        bool self_closing = false;
        Element e = start_tag(lt, pos, self_closing);
        const size_t id = elements_.size();
        if (stack.empty()) {
          if (!elements_.empty()) fail_at(lt, "a second root element");
        } else {
          elements_[stack.back()].children.push_back(id);
        }
        const bool appended = e.name == "AppendedData";
        elements_.push_back(std::move(e));
        if (!self_closing) stack.push_back(id);
        if (appended && !self_closing) pos = slice_appended(id, pos);
      }
    }
    if (!stack.empty()) fail_at(data_.size(), "file ends inside <" + elements_[stack.back()].name + ">");
    if (elements_.empty()) fail_at(0, "no XML element: not a VTK XML file");
  }

  const Element& root() const { return elements_.front(); }
  const Element& element(size_t id) const { return elements_[id]; }
  std::string_view appended() const { return appended_; }
  bool appended_raw() const { return appended_raw_; }
  size_t appended_offset() const { return appended_offset_; }
  const std::string& path() const { return path_; }

  std::string line_of(size_t offset) const {
    return path_ + ":" +
           std::to_string(1 +
                          std::count(data_.begin(), data_.begin() + std::min(offset, data_.size()), '\n'));
  }
  [[noreturn]] void fail_at(size_t offset, const std::string& problem) const {
    throw FormatError(line_of(offset) + ": " + problem);
  }

 private:
  static std::string trim(std::string_view s) {
    const size_t b = s.find_first_not_of(" \t\r\n"), e = s.find_last_not_of(" \t\r\n");
    return b == std::string::npos ? "" : std::string(s.substr(b, e - b + 1));
  }
  size_t find_or_fail(size_t found, size_t from, const char* problem) const {
    if (found == std::string::npos) fail_at(from, problem);
    return found;
  }

  Element start_tag(size_t lt, size_t& pos, bool& self_closing) {
    Element e;
    e.offset = lt;
    size_t p = lt + 1;
    auto is_name = [](char c) {
      return std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == ':' || c == '-' || c == '.';
    };
    while (p < data_.size() && is_name(data_[p])) e.name += data_[p++];
    if (e.name.empty()) fail_at(lt, "malformed tag");
    while (true) {
      while (p < data_.size() && std::isspace(static_cast<unsigned char>(data_[p]))) ++p;
      if (p >= data_.size()) fail_at(lt, "unterminated tag <" + e.name + ">");
      if (data_[p] == '>') {
        pos = p + 1;
        return e;
      }
      if (data_.compare(p, 2, "/>") == 0) {
        self_closing = true;
        pos = p + 2;
        return e;
      }
      std::string key;
      while (p < data_.size() && is_name(data_[p])) key += data_[p++];
      while (p < data_.size() && std::isspace(static_cast<unsigned char>(data_[p]))) ++p;
      if (key.empty() || p >= data_.size() || data_[p] != '=')
        fail_at(lt, "malformed attribute in <" + e.name + ">");
      ++p;
      while (p < data_.size() && std::isspace(static_cast<unsigned char>(data_[p]))) ++p;
      if (p >= data_.size() || (data_[p] != '"' && data_[p] != '\''))
        fail_at(lt, "unquoted attribute " + key);
      const size_t close = find_or_fail(data_.find(data_[p], p + 1), lt, "unterminated attribute value");
      if (!e.attrs.emplace(key, unescaped(data_.substr(p + 1, close - p - 1))).second)
        fail_at(lt, "attribute " + key + " given twice");
      p = close + 1;
    }
  }

  // The payload of <AppendedData>: after the '_' that starts it, up to the
  // last "</AppendedData>" (raw bytes may contain anything, '<' included).
  size_t slice_appended(size_t id, size_t pos) {
    const Element& e = elements_[id];
    const std::string* enc = e.attr("encoding");
    if (!enc || (*enc != "raw" && *enc != "base64"))
      fail_at(e.offset, "AppendedData encoding must be \"raw\" or \"base64\"");
    appended_raw_ = *enc == "raw";
    const size_t underscore = data_.find_first_not_of(" \t\r\n", pos);
    if (underscore == std::string::npos || data_[underscore] != '_')
      fail_at(e.offset, "AppendedData must start with '_'");
    const size_t end =
        appended_raw_ ? data_.rfind("</AppendedData>") : data_.find("</AppendedData>", underscore);
    if (end == std::string::npos || end < underscore) fail_at(e.offset, "file ends inside <AppendedData>");
    appended_offset_ = underscore + 1;
    appended_ = std::string_view(data_).substr(underscore + 1, end - underscore - 1);
    return end;
  }

  std::string path_;
  std::string data_;
  std::vector<Element> elements_;
  std::string_view appended_;
  bool appended_raw_ = true;
  size_t appended_offset_ = 0;
};

std::optional<ScalarType> xml_type(std::string_view name) {
  static const std::map<std::string, ScalarType, std::less<>> kTypes = {
      {"Int8", ScalarType::kInt8},      {"UInt8", ScalarType::kUInt8},   {"Int16", ScalarType::kInt16},
      {"UInt16", ScalarType::kUInt16},  {"Int32", ScalarType::kInt32},   {"UInt32", ScalarType::kUInt32},
      {"Int64", ScalarType::kInt64},    {"UInt64", ScalarType::kUInt64}, {"Float32", ScalarType::kFloat32},
      {"Float64", ScalarType::kFloat64}};
  const auto it = kTypes.find(name);
  if (it == kTypes.end()) return std::nullopt;
  return it->second;
}

// A value as it reads (whole numbers without a fraction; any size, NaN too).
std::string number_text(double v) {
  char text[40];
  std::snprintf(text, sizeof text, "%.17g", v);
  return text;
}

int base64_value(char c) {
  if (c >= 'A' && c <= 'Z') return c - 'A';
  if (c >= 'a' && c <= 'z') return c - 'a' + 26;
  if (c >= '0' && c <= '9') return c - '0' + 52;
  if (c == '+') return 62;
  if (c == '/') return 63;
  return -1;
}

// Each byte's base64 value, or 255 (a blank, '=', anything else).
const std::array<uint8_t, 256>& base64_values() {
  static const std::array<uint8_t, 256> table = [] {
    std::array<uint8_t, 256> t{};
    for (int c = 0; c < 256; ++c) {
      const int v = base64_value(static_cast<char>(c));
      t[c] = static_cast<uint8_t>(v < 0 ? 255 : v);
    }
    return t;
  }();
  return table;
}

// Decodes up to `quanta` whole 4-character quanta of plain base64 (no
// blank, no padding) from text[pos], appending 3 bytes each to `out`;
// stops before the first quantum holding anything else, and moves `pos`
// past those decoded. The rest is the careful loop's below. Windows of
// quanta, each twice the last, are decoded in ranges on every core: `out`
// grows by a window at a time, so text broken into lines (a blank every 76
// characters) costs what it decodes, not what is left.
void decode_plain_quanta(std::string_view text, size_t& pos, uint64_t quanta, std::string& out) {
  constexpr uint64_t kRange = uint64_t{1} << 16;  // quanta a thread decodes at once
  const auto& value = base64_values();
  const auto* in = reinterpret_cast<const unsigned char*>(text.data() + pos);
  uint64_t decoded = 0;
  for (uint64_t window = 1024; decoded < quanta; window *= 2) {
    const uint64_t first = decoded, count = std::min(window, quanta - decoded);
    const size_t at = out.size();
    out.resize(at + 3 * count);
    auto* to = reinterpret_cast<unsigned char*>(out.data() + at);
    const uint64_t ranges = (count + kRange - 1) / kRange;
    // Per range: the quanta it decoded before a quantum it could not.
    std::vector<uint64_t> done(ranges, 0);
    parallel_for(ranges, [&](size_t r) {
      const uint64_t lo = r * kRange, hi = std::min(count, lo + kRange);
      uint64_t q = lo;
      for (; q < hi; ++q) {
        const unsigned char* c = in + 4 * (first + q);
        const uint32_t a = value[c[0]], b = value[c[1]], d = value[c[2]], e = value[c[3]];
        if ((a | b | d | e) > 63) break;
        const uint32_t w = a << 18 | b << 12 | d << 6 | e;
        to[3 * q] = static_cast<unsigned char>(w >> 16);
        to[3 * q + 1] = static_cast<unsigned char>(w >> 8);
        to[3 * q + 2] = static_cast<unsigned char>(w);
      }
      done[r] = q - lo;
    });
    uint64_t plain = 0;  // of this window, up to its first stop
    for (uint64_t r = 0; r < ranges; ++r) {
      plain += done[r];
      if (done[r] < std::min(count, (r + 1) * kRange) - r * kRange) break;
    }
    out.resize(at + 3 * plain);
    decoded += plain;
    if (plain < count) break;
  }
  pos += 4 * decoded;
}

// Decodes base64 quanta from text[pos] until `out` holds `want` bytes or the
// text ends. Each 4-character quantum is decoded on its own, so streams
// encoded in several pieces (header and data apart, with '=' padding in
// between, as some VTK writers do) decode to their concatenation. Returns an
// error message, or "" on success.
std::string base64_decode(std::string_view text, size_t& pos, size_t want, std::string& out) {
  char quantum[4];
  int have = 0;
  while (out.size() < want && pos < text.size()) {
    // Between quanta, the plain ones that follow decoded fast.
    if (have == 0 && want - out.size() >= 3 && text.size() - pos >= 4) {
      const size_t before = pos;
      decode_plain_quanta(text, pos, std::min<uint64_t>((want - out.size()) / 3, (text.size() - pos) / 4),
                          out);
      if (pos != before) continue;
    }
    const char c = text[pos++];
    if (std::isspace(static_cast<unsigned char>(c))) continue;
    if (c != '=' && base64_value(c) < 0) return std::string("invalid base64 character '") + c + "'";
    quantum[have++] = c;
    if (have < 4) continue;
    have = 0;
    if (quantum[0] == '=' || quantum[1] == '=' || (quantum[2] == '=' && quantum[3] != '='))
      return "misplaced base64 padding";
    const uint32_t w = base64_value(quantum[0]) << 18 | base64_value(quantum[1]) << 12 |
                       (quantum[2] == '=' ? 0 : base64_value(quantum[2]) << 6) |
                       (quantum[3] == '=' ? 0 : base64_value(quantum[3]));
    out += static_cast<char>(w >> 16);
    if (quantum[2] != '=') out += static_cast<char>((w >> 8) & 0xff);
    if (quantum[3] != '=') out += static_cast<char>(w & 0xff);
  }
  if (have != 0) return "base64 data ends in the middle of a quantum";
  return "";
}

class VtuReader {
 public:
  explicit VtuReader(const std::string& path) : p_(path) {}

  InputMesh read() {
    p_.parse();
    const Element& root = p_.root();
    if (root.name != "VTKFile") p_.fail_at(root.offset, "root element is <" + root.name + ">, not <VTKFile>");
    if (const auto* t = root.attr("type"); !t || *t != "UnstructuredGrid")
      p_.fail_at(root.offset, "only type=\"UnstructuredGrid\" is supported, got \"" + (t ? *t : "") + "\"");
    if (const auto* c = root.attr("compressor")) {
      compressor_ = vtk_compressor_named(*c);
      if (!compressor_)
        p_.fail_at(root.offset, "unknown compressor \"" + *c +
                                    "\" (vtkZLibDataCompressor, vtkLZ4DataCompressor and "
                                    "vtkLZMADataCompressor are read)");
    }
    if (const auto* b = root.attr("byte_order")) {
      if (*b != "LittleEndian" && *b != "BigEndian")
        p_.fail_at(root.offset, "unknown byte_order \"" + *b + "\"");
      big_endian_ = *b == "BigEndian";
    }
    if (const auto* h = root.attr("header_type")) {
      if (*h != "UInt32" && *h != "UInt64") p_.fail_at(root.offset, "unknown header_type \"" + *h + "\"");
      header_type_ = *h == "UInt64" ? ScalarType::kUInt64 : ScalarType::kUInt32;
    }
    const Element& grid = only_child(root, "UnstructuredGrid");
    std::vector<size_t> pieces;
    for (size_t id : grid.children)
      if (p_.element(id).name == "Piece") pieces.push_back(id);
    if (pieces.empty()) p_.fail_at(grid.offset, "no <Piece>");
    // The dataset's own arrays (ParaView's TimeValue, ...): named.
    for (size_t id : grid.children)
      if (const Element& fd = p_.element(id); fd.name == "FieldData")
        for (size_t a : fd.children)
          if (const Element& da = p_.element(a); da.name == "DataArray" || da.name == "Array")
            dataset_arrays_.insert(array_name(da));
    // Several pieces (a parallel writer's, or VTK's when asked): one mesh,
    // their points one after the other, each piece's cells renumbered.
    InputMesh out;
    for (size_t k = 0; k < pieces.size(); ++k) read_piece(p_.element(pieces[k]), k, out);
    note_left_out(out);
    return out;
  }

 private:
  // One <Piece>'s points, PointData and tetrahedra, added to `out`. A
  // PointData array must be in every piece, with the same components.
  void read_piece(const Element& piece, size_t k, InputMesh& out) {
    const uint64_t n = count_attr(piece, "NumberOfPoints"), cells = count_attr(piece, "NumberOfCells");
    const size_t first = out.points.size();
    if (n > 0) {
      const auto xyz = array(only_child(only_child(piece, "Points"), "DataArray"), n, 3);
      for (uint64_t i = 0; i < n; ++i) {
        out.points.push_back({xyz[3 * i], xyz[3 * i + 1], xyz[3 * i + 2]});
        if (!std::isfinite(xyz[3 * i]) || !std::isfinite(xyz[3 * i + 1]) || !std::isfinite(xyz[3 * i + 2]))
          p_.fail_at(only_child(piece, "Points").offset,
                     "point " + std::to_string(first + i) + " is not finite");
      }
    }
    size_t fields = 0;
    if (const Element* pd = optional_child(piece, "PointData"))
      for (size_t id : pd->children) {
        const Element& da = p_.element(id);
        if (skipped_array(da)) continue;
        VertexField f;
        f.name = array_name(da);
        f.components = static_cast<int>(count_attr(da, "NumberOfComponents", 1));
        if (f.components < 1 || f.components > 64)
          p_.fail_at(da.offset, "NumberOfComponents must be 1 to 64");
        f.values = array(da, n, f.components);
        if (const auto* t = da.attr("type"); t && xml_type(*t)) f.type = *xml_type(*t);
        if (k == 0) {
          out.fields.push_back(std::move(f));
        } else {
          if (fields >= out.fields.size() || out.fields[fields].name != f.name ||
              out.fields[fields].components != f.components)
            p_.fail_at(da.offset, "piece " + std::to_string(k + 1) + ": PointData \"" + f.name +
                                      "\" is not the first piece's array at its place");
          auto& values = out.fields[fields].values;
          values.insert(values.end(), f.values.begin(), f.values.end());
        }
        ++fields;
      }
    if (k > 0 && fields != out.fields.size())
      p_.fail_at(piece.offset, "piece " + std::to_string(k + 1) + " has " + std::to_string(fields) +
                                   " PointData arrays, the first piece " + std::to_string(out.fields.size()));
    // A parallel writer's ghost cells (vtkGhostType's DUPLICATECELL bit, 1):
    // the neighbouring pieces' cells, which their own pieces hold.
    std::vector<double> ghost;
    if (const Element* cd = optional_child(piece, "CellData"))
      for (size_t id : cd->children)
        if (const Element& da = p_.element(id);
            da.name == "DataArray" && da.attr("Name") && *da.attr("Name") == kGhostArray)
          ghost = array(da, cells, 1);
    std::vector<uint64_t> triangles;
    const std::vector<uint64_t> tets = read_cells(piece, cells, n, first, out, triangles, ghost);
    // Integer cell arrays of one component may be the regions
    // (InputMesh::tet_arrays); every other array is cell data
    // (InputMesh::cell_fields). Both are kept on the tetrahedra; an array
    // not in every piece is named as left out.
    std::set<std::string> here;
    size_t cell_fields = 0;
    if (const Element* cd = optional_child(piece, "CellData"))
      for (size_t id : cd->children) {
        const Element& da = p_.element(id);
        if (skipped_array(da)) continue;
        const std::string name = array_name(da);
        // The type the file stores (an unknown one is read as float64).
        ScalarType type = ScalarType::kFloat64;
        if (const auto* t = da.attr("type"))
          if (const auto known = xml_type(*t)) type = *known;
        const bool integer = is_integer(type);
        const int components = static_cast<int>(count_attr(da, "NumberOfComponents", 1));
        if (components < 1 || components > 64) p_.fail_at(da.offset, "NumberOfComponents must be 1 to 64");
        if (!integer || components != 1) {
          const bool known =
              k == 0 || (cell_fields < out.cell_fields.size() && out.cell_fields[cell_fields].name == name &&
                         out.cell_fields[cell_fields].components == components);
          if (!known) {
            cell_arrays_.insert(name);
            continue;
          }
          const auto values = array(da, cells, components);
          if (k == 0) {
            VertexField& f = out.cell_fields.emplace_back();
            f.name = name, f.components = components;
            f.type = type;
            out.cell_array_order.push_back(name);
          }
          std::vector<double>& into = out.cell_fields[cell_fields++].values;
          for (uint64_t c : tets)
            for (int j = 0; j < components; ++j) into.push_back(values[c * components + j]);
          // (Cell data is the tetrahedra's: its values on the triangles are named.)
          const auto n = static_cast<size_t>(components);
          if (any_value_said(triangles.size() * n,
                             [&](size_t i) { return values[triangles[i / n] * n + i % n]; }))
            triangle_values_.insert(name);
          continue;
        }
        if (k > 0 && !out.tet_arrays.count(name)) {
          cell_arrays_.insert(name);
          continue;
        }
        const auto values = array(da, cells, 1);
        const auto keep_on = [&](const std::vector<uint64_t>& on, std::vector<int32_t>& into) {
          for (uint64_t c : on) {
            if (!(values[c] >= INT32_MIN && values[c] <= INT32_MAX))
              p_.fail_at(da.offset, "CellData \"" + name + "\": a value out of the 32-bit range");
            into.push_back(static_cast<int32_t>(values[c]));
          }
        };
        if (k == 0) out.cell_array_order.push_back(name);
        keep_on(tets, out.tet_arrays[name]);
        keep_on(triangles, out.triangle_arrays[name]);
        out.tet_array_types[name] = type;
        here.insert(name);
      }
    // An array not in every piece is not a value of every tetrahedron.
    for (auto it = out.tet_arrays.begin(); it != out.tet_arrays.end();)
      if (!here.count(it->first)) {
        cell_arrays_.insert(it->first);
        out.triangle_arrays.erase(it->first);
        it = out.tet_arrays.erase(it);
      } else {
        ++it;
      }
    while (k > 0 && cell_fields < out.cell_fields.size()) {
      cell_arrays_.insert(out.cell_fields.back().name);
      out.cell_fields.pop_back();
    }
  }

  // What the file holds that the mesh read does not (InputMesh::left_out).
  void note_left_out(InputMesh& out) const {
    if (!cell_arrays_.empty()) {
      std::string names;
      for (const std::string& a : cell_arrays_) names += (names.empty() ? "'" : ", '") + a + "'";
      out.left_out.push_back("CellData arrays " + names);
    }
    std::string others;
    for (const auto& [type, count] : other_cells_)
      others += (others.empty() ? "" : ", ") + std::to_string(count) + " " + vtk_cell_name(type);
    if (!others.empty()) out.left_out.push_back("cells other than tetrahedra (" + others + ")");
    if (!split_cells_.empty()) out.left_out.push_back(split_cells_note(split_cells_));
    const auto quoted = [](const std::set<std::string>& names) {
      std::string s;
      for (const std::string& a : names) s += (s.empty() ? "'" : ", '") + a + "'";
      return s;
    };
    if (!triangle_values_.empty())
      out.left_out.push_back("the values of the cell arrays " + quoted(triangle_values_) +
                             " on the triangles (cell data is the tetrahedra's)");
    if (!text_arrays_.empty()) out.left_out.push_back("arrays of strings or bits " + quoted(text_arrays_));
    if (!dataset_arrays_.empty())
      out.left_out.push_back("the dataset's FieldData " + quoted(dataset_arrays_));
    // (One line alike for every piece of a .pvtu, which its reader joins.)
    if (ghost_cells_ > 0)
      out.left_out.push_back(
          "ghost cells (vtkGhostType: copies of the neighbouring pieces' cells, read from those pieces)");
  }

  // An array not read as values: the ghost cells' and points' flags (used
  // by read_cells()), and arrays of strings or bits (named).
  // (Also what is not a DataArray: VTK's <Array> of strings is named.)
  bool skipped_array(const Element& da) {
    if (da.name != "DataArray" && da.name != "Array") return true;
    if (da.attr("Name") && *da.attr("Name") == kGhostArray) return true;
    const auto* t = da.attr("type");
    if (da.name == "DataArray" && (!t || (*t != "String" && *t != "Bit"))) return false;
    text_arrays_.insert(array_name(da));
    return true;
  }

  const Element* optional_child(const Element& parent, std::string_view name) const {
    const Element* found = nullptr;
    for (size_t id : parent.children)
      if (p_.element(id).name == name) {
        if (found)
          p_.fail_at(p_.element(id).offset, "a second <" + std::string(name) + "> in <" + parent.name + ">");
        found = &p_.element(id);
      }
    return found;
  }
  const Element& only_child(const Element& parent, std::string_view name) const {
    const Element* e = optional_child(parent, name);
    if (!e) p_.fail_at(parent.offset, "<" + parent.name + "> has no <" + std::string(name) + ">");
    return *e;
  }
  const Element& named_array(const Element& parent, std::string_view name) const {
    for (size_t id : parent.children)
      if (const Element& e = p_.element(id);
          e.name == "DataArray" && e.attr("Name") && *e.attr("Name") == name)
        return e;
    p_.fail_at(parent.offset, "<" + parent.name + "> has no DataArray \"" + std::string(name) + "\"");
  }
  uint64_t count_attr(const Element& e, const char* key, std::optional<uint64_t> fallback = {}) const {
    const std::string* v = e.attr(key);
    if (!v) {
      if (fallback) return *fallback;
      p_.fail_at(e.offset, "<" + e.name + "> has no " + key);
    }
    uint64_t n = 0;
    const auto [end, ec] = std::from_chars(v->data(), v->data() + v->size(), n);
    if (ec != std::errc() || end != v->data() + v->size() || n > (uint64_t{1} << 40))
      p_.fail_at(e.offset, std::string(key) + "=\"" + *v + "\" is not a valid count");
    return n;
  }

  // The `tuples` x `components` values of a DataArray, whatever its format.
  std::vector<double> array(const Element& da, uint64_t tuples, int components) {
    const std::string name = da.attr("Name") ? *da.attr("Name") : "";
    const std::string what = name.empty() ? "a DataArray" : "DataArray \"" + name + "\"";
    const std::string* type_name = da.attr("type");
    const auto type = type_name ? xml_type(*type_name) : std::nullopt;
    if (!type)
      p_.fail_at(da.offset, what + ": unknown or unsupported type \"" + (type_name ? *type_name : "") + "\"");
    if (const int c = static_cast<int>(count_attr(da, "NumberOfComponents", 1)); c != components)
      p_.fail_at(da.offset,
                 what + " has " + std::to_string(c) + " components, expected " + std::to_string(components));
    const uint64_t n = tuples * components;
    const std::string* format = da.attr("format");
    if (!format) p_.fail_at(da.offset, what + " has no format");
    std::vector<double> out;
    if (*format == "ascii") {
      TextCursor c(p_.line_of(da.offset) + ": " + what, std::string(da.text));
      if (n > da.text.size())
        p_.fail_at(da.offset, what + " holds fewer than the " + std::to_string(n) + " values expected");
      out.reserve(n);
      for (uint64_t i = 0; i < n; ++i) {
        if (c.at_end())
          p_.fail_at(da.offset,
                     what + " holds " + std::to_string(i) + " values, expected " + std::to_string(n));
        const std::string_view t = c.token("a number");
        double v = 0;
        const auto [end, ec] = std::from_chars(t.data(), t.data() + t.size(), v);
        if (ec != std::errc() || end != t.data() + t.size())
          p_.fail_at(da.offset, what + ": expected a number, found '" + std::string(t) + "'");
        out.push_back(v);
      }
      if (!c.at_end())
        p_.fail_at(da.offset, what + " holds more than the " + std::to_string(n) + " values expected");
      return out;
    }
    const int size = scalar_size(*type);
    const std::string bytes = binary_payload(da, what, n * size);
    out.resize(n);
    parallel_ranges(n, size_t{1} << 16, [&](size_t first, size_t last) {
      for (size_t i = first; i < last; ++i) out[i] = scalar_at(bytes.data() + i * size, *type, big_endian_);
    });
    return out;
  }

  // The `expected` bytes of a binary or appended DataArray, decompressed
  // when the file is: behind a header of header_type_ words, either the
  // byte count, or (compressed) the block count, the block size, the last
  // block's size (0: a whole block) and each block's compressed size.
  std::string binary_payload(const Element& da, const std::string& what, uint64_t expected) {
    const std::string* format = da.attr("format");
    const int hsize = scalar_size(header_type_);
    std::string_view text;  // base64, inline or appended
    size_t pos = 0;
    std::string_view raw;  // raw appended data from the array's offset
    bool is_raw = false;
    size_t where = da.offset;  // for messages: a line, or a byte of raw appended data
    if (*format == "binary") {
      text = da.text;
    } else if (*format == "appended") {
      const uint64_t offset = count_attr(da, "offset");
      if (offset >= p_.appended().size())
        p_.fail_at(da.offset,
                   what + ": offset " + std::to_string(offset) + " is past the end of the appended data");
      if (p_.appended_raw()) {
        is_raw = true;
        raw = p_.appended().substr(offset);
        where = p_.appended_offset() + offset;
      } else {
        text = p_.appended();
        pos = offset;
      }
    } else {
      p_.fail_at(da.offset, what + ": unknown format \"" + *format + "\"");
    }
    const auto fail = [&](const std::string& problem) -> void {
      throw FormatError(
          (where == da.offset ? p_.line_of(da.offset) : p_.path() + ": byte " + std::to_string(where)) +
          ": " + what + ": " + problem);
    };
    // The array's first `want` bytes (header included) into `bytes`; false
    // when the data ends before. Never more than the file holds: raw bytes
    // are sliced, base64 decoded as far as it goes.
    std::string bytes;
    const auto fetch = [&](uint64_t want) -> bool {
      if (is_raw) {
        if (want > raw.size()) return false;
        bytes.assign(raw.substr(0, want));
        return true;
      }
      if (const std::string e = base64_decode(text, pos, want, bytes); !e.empty()) fail(e);
      return bytes.size() >= want;
    };
    const auto word = [&](uint64_t i) { return unsigned_at(bytes.data() + i * hsize, hsize, big_endian_); };
    const uint64_t left = is_raw ? raw.size() : text.size();  // an upper bound on the bytes present
    if (!compressor_) {
      if (!fetch(hsize)) fail(is_raw ? "file ends in its header" : "data ends in its header");
      const uint64_t count = word(0);
      if (is_raw && count > raw.size() - hsize)
        fail(std::to_string(count) + " bytes announced, " + std::to_string(raw.size() - hsize) + " left");
      if (count != expected || !fetch(hsize + count))
        fail("block of " + std::to_string(count) + " bytes (" + std::to_string(bytes.size() - hsize) +
             " present), expected " + std::to_string(expected) + " bytes");
      return bytes.substr(hsize);
    }
    if (!fetch(3 * hsize)) fail("data ends in its compression header");
    const uint64_t blocks = word(0), block_size = word(1), last_size = word(2);
    if (blocks > left / hsize)
      fail(std::to_string(blocks) + " compressed blocks announced, more than the file holds");
    // A block is decompressed into the size its header gives: that size is
    // bounded, so that a file cannot make the reader allocate more than a
    // block beyond what its data really holds (VTK and meshio write 32 KiB).
    if (block_size > kMaxBlockSize)
      fail("blocks of " + std::to_string(block_size) + " bytes announced (at most " +
           std::to_string(kMaxBlockSize) + " are read)");
    const uint64_t last = last_size == 0 ? block_size : last_size;
    if (blocks == 0 ? expected != 0
                    : (last > block_size || block_size == 0 || (blocks - 1) > expected / block_size ||
                       (blocks - 1) * block_size + last != expected))
      fail(std::to_string(blocks) + " blocks of " + std::to_string(block_size) + " bytes (the last " +
           std::to_string(last) + "), expected " + std::to_string(expected) + " bytes");
    if (!fetch((3 + blocks) * hsize)) fail("data ends in its compression header");
    std::vector<uint64_t> sizes(blocks);
    uint64_t total = 0;
    for (uint64_t b = 0; b < blocks; ++b) {
      sizes[b] = word(3 + b);
      if (sizes[b] > left)
        fail("a compressed block of " + std::to_string(sizes[b]) + " bytes, more than the file holds");
      total += sizes[b];
    }
    const uint64_t header = (3 + blocks) * hsize;
    if (total > left || !fetch(header + total))
      fail(std::to_string(total) + " compressed bytes announced, fewer present");
    std::string payload;
    uint64_t at = header;
    for (uint64_t b = 0; b < blocks; ++b) {
      const std::string_view block = std::string_view(bytes).substr(at, sizes[b]);
      if (const std::string e =
              decompress_vtk_block(*compressor_, block, b + 1 < blocks ? block_size : last, payload);
          !e.empty())
        fail("block " + std::to_string(b + 1) + " of " + std::to_string(blocks) + ": " + e);
      at += sizes[b];
    }
    return payload;
  }

  // The piece's tetrahedra, their point indices shifted by `first` (the
  // points of the pieces before).
  // The piece's tetrahedra, added to `out`; returns which of its cells
  // they are.
  std::vector<uint64_t> read_cells(const Element& piece, uint64_t cells, uint64_t points, size_t first,
                                   InputMesh& out, std::vector<uint64_t>& triangles,
                                   const std::vector<double>& ghost) {
    std::vector<uint64_t> tets;
    const Element* ce = optional_child(piece, "Cells");
    if (!ce) {
      if (cells > 0) p_.fail_at(piece.offset, "NumberOfCells=" + std::to_string(cells) + " but no <Cells>");
      return tets;
    }
    const auto offsets = array(named_array(*ce, "offsets"), cells, 1);
    const auto types = array(named_array(*ce, "types"), cells, 1);
    if (cells > 0 && !(offsets.back() >= 0 && offsets.back() <= 9007199254740992.0))  // 2^53
      p_.fail_at(ce->offset, "the last offset (" + std::to_string(offsets.back()) + ") is not a valid count");
    const uint64_t total = cells == 0 ? 0 : static_cast<uint64_t>(offsets.back());
    const Element& conn_element = named_array(*ce, "connectivity");
    const auto conn = array(conn_element, total, 1);
    double previous = 0;
    for (uint64_t c = 0; c < cells; ++c) {
      // Checked before use: an offset past the last one (fuzzing found it)
      // would index past the connectivity array.
      if (!(offsets[c] >= previous)) p_.fail_at(ce->offset, "offsets decrease at cell " + std::to_string(c));
      if (!(offsets[c] <= static_cast<double>(conn.size())) || offsets[c] != std::floor(offsets[c]))
        p_.fail_at(ce->offset, "cell " + std::to_string(c) + ": offset " + std::to_string(offsets[c]) +
                                   " is not a whole number within the " + std::to_string(conn.size()) +
                                   " connectivity values");
      const auto b = static_cast<uint64_t>(previous), e = static_cast<uint64_t>(offsets[c]);
      previous = offsets[c];
      for (uint64_t k = b; k < e; ++k)
        if (!(conn[k] >= 0 && conn[k] < static_cast<double>(points)))
          p_.fail_at(conn_element.offset,
                     "cell " + std::to_string(c) + ": point index " + number_text(conn[k]) + " out of range");
      const auto at = [&](uint64_t i) {
        return static_cast<uint32_t>(first + static_cast<uint64_t>(conn[i]));
      };
      // (The flags are bytes; a damaged file's may be anything.)
      if (!ghost.empty() && ghost[c] >= 0 && ghost[c] < 256 && (static_cast<int>(ghost[c]) & 1)) {
        ++ghost_cells_;
        continue;
      }
      // Triangles may carry tags (InputMesh::tagged_faces): held, tagged
      // or named by choose_regions().
      // (A quadratic one's edge nodes go aside: second_order.h.)
      if ((types[c] == kVtkTriangle && e - b == 3) || (types[c] == kVtkQuadraticTriangle && e - b == 6)) {
        out.tagged_faces.push_back({at(b), at(b + 1), at(b + 2)});
        for (uint64_t k = b + 3; k < e; ++k) out.other_edge_nodes.push_back(at(k));
        triangles.push_back(c);
        continue;
      }
      // A quadrilateral as two triangles, a hexahedron, wedge or pyramid as
      // its tetrahedra (cell_split.h), each with the cell's data.
      // (A second-order one's other nodes go aside: second_order.h.)
      if (const VtkSplitType split = vtk_split_type(types[c]); split.corners > 0 && e - b == split.nodes) {
        std::array<uint32_t, 27> nodes{};
        for (size_t k = 0; k < split.nodes; ++k) nodes[k] = at(b + k);
        const size_t added = add_split_cell(std::span(nodes).first(split.nodes), split.corners, out);
        auto& cells_of = split.corners == 4 ? triangles : tets;
        cells_of.insert(cells_of.end(), added, c);
        if (split.corners > 4) ++split_cells_[split.corners];
        continue;
      }
      if (types[c] != kVtkTetra && types[c] != kVtkQuadraticTetra) {
        // (VTK's types are bytes; a damaged file's may be anything.)
        ++other_cells_[types[c] >= 0 && types[c] < 256 ? static_cast<int>(types[c]) : -1];
        continue;
      }
      const bool quadratic = types[c] == kVtkQuadraticTetra;
      if (e - b != (quadratic ? 10u : 4u))
        p_.fail_at(ce->offset, "cell " + std::to_string(c) + " is a " +
                                   (quadratic ? "VTK_QUADRATIC_TETRA" : "VTK_TETRA") + " with " +
                                   std::to_string(e - b) + " points");
      out.tets.push_back({at(b), at(b + 1), at(b + 2), at(b + 3)});
      if (quadratic) {
        std::array<uint32_t, 6> edge;
        for (size_t k = 0; k < 6; ++k) edge[k] = at(b + kVtkTetEdgeNodes[k]);
        add_tet_edge_nodes(out, edge);
      }
      tets.push_back(c);
    }
    return tets;
  }

  VtuParser p_;
  bool big_endian_ = false;
  ScalarType header_type_ = ScalarType::kUInt32;
  std::optional<VtkCompressor> compressor_;
  static constexpr std::string_view kGhostArray = "vtkGhostType";
  std::set<std::string> cell_arrays_;       // CellData arrays seen, by name
  std::set<std::string> triangle_values_;   // non-label CellData arrays with values on triangles
  std::set<std::string> text_arrays_;       // String and Bit arrays, not read
  std::set<std::string> dataset_arrays_;    // the grid's FieldData
  uint64_t ghost_cells_ = 0;                // vtkGhostType's duplicate cells, not read
  std::map<int, uint64_t> other_cells_;     // cells that are not tetrahedra, by VTK type
  std::map<size_t, uint64_t> split_cells_;  // hexahedra, wedges and pyramids, by corner count
};

}  // namespace

InputMesh read_vtu(const std::string& path) { return VtuReader(path).read(); }

namespace {

// Appends `part` (a piece, read alone) to `whole`: its points after the
// others, its cells renumbered; a point or cell array must be in every
// piece alike (else it is not an array of the whole: named as left out).
void append_piece(InputMesh& whole, InputMesh part, bool first, const std::string& piece) {
  const auto offset = static_cast<uint32_t>(whole.points.size());
  whole.points.insert(whole.points.end(), part.points.begin(), part.points.end());
  for (auto t : part.tets) {
    for (uint32_t& v : t) v += offset;
    whole.tets.push_back(t);
  }
  for (auto f : part.tagged_faces) {
    for (uint32_t& v : f) v += offset;
    whole.tagged_faces.push_back(f);
  }
  if (!part.tet_edge_nodes.empty()) {
    part.tet_edge_nodes.resize(part.tets.size(), kNoEdgeNodes);
    whole.tet_edge_nodes.resize(whole.tets.size() - part.tets.size(), kNoEdgeNodes);
    for (auto& e : part.tet_edge_nodes) {
      for (uint32_t& v : e)
        if (v != InputMesh::kNoEdgeNode) v += offset;
      whole.tet_edge_nodes.push_back(e);
    }
  }
  for (uint32_t v : part.other_edge_nodes) whole.other_edge_nodes.push_back(v + offset);
  whole.second_order_cells += part.second_order_cells;
  if (first) whole.cell_array_order = part.cell_array_order;
  const auto same_arrays = [&](std::vector<VertexField>& into, std::vector<VertexField>& from,
                               const char* what) {
    if (first) {
      into = std::move(from);
      return;
    }
    bool same = into.size() == from.size();
    for (size_t i = 0; same && i < into.size(); ++i)
      same = into[i].name == from[i].name && into[i].components == from[i].components;
    if (!same) throw FormatError(piece + ": its " + what + " are not the first piece's");
    for (size_t i = 0; i < into.size(); ++i)
      into[i].values.insert(into[i].values.end(), from[i].values.begin(), from[i].values.end());
  };
  same_arrays(whole.fields, part.fields, "PointData arrays");
  same_arrays(whole.cell_fields, part.cell_fields, "CellData arrays");
  const auto same_labels = [&](std::map<std::string, std::vector<int32_t>>& into,
                               std::map<std::string, std::vector<int32_t>>& from) {
    if (first) {
      into = std::move(from);
      return;
    }
    for (auto it = into.begin(); it != into.end();) {
      const auto there = from.find(it->first);
      if (there == from.end()) {
        whole.left_out.push_back("the integer cell array '" + it->first + "' (not in every piece)");
        it = into.erase(it);
        continue;
      }
      it->second.insert(it->second.end(), there->second.begin(), there->second.end());
      ++it;
    }
  };
  same_labels(whole.tet_arrays, part.tet_arrays);
  same_labels(whole.triangle_arrays, part.triangle_arrays);
  if (first) whole.tet_array_types = std::move(part.tet_array_types);
  for (std::string& what : part.left_out)
    if (std::find(whole.left_out.begin(), whole.left_out.end(), what) == whole.left_out.end())
      whole.left_out.push_back(std::move(what));
}

// A parallel writer repeats the points on its pieces' borders, one copy
// in each piece (VTK's, ParaView's, meshdec --pieces): a point of a piece
// at exactly the coordinates of a point of an earlier piece is that point.
// Merged here, so that the mesh is one whole (--exact keeps its cells: a
// merge by quantization would refuse it) and the tagged faces meet their
// cells; points that coincide within one piece only are left to
// quantization.
// Where a copy's values differ from the first's, the first's are kept, said.
void merge_shared_points(InputMesh& whole, std::span<const size_t> piece_first) {
  struct Key {
    double x, y, z;
    bool operator==(const Key&) const = default;
  };
  struct KeyHash {
    size_t operator()(const Key& k) const {
      uint64_t h = 0;
      for (double v : {k.x, k.y, k.z})
        h = (h ^ std::bit_cast<uint64_t>(v == 0 ? 0.0 : v)) * 0x9E3779B97F4A7C15ull;
      return h ^ (h >> 31);
    }
  };
  const size_t n = whole.points.size();
  std::unordered_map<Key, uint32_t, KeyHash> first_at;  // coordinates -> the first point there
  first_at.reserve(n);
  std::vector<uint32_t> same_as(n);  // each point's first copy (itself if it is one)
  size_t merged = 0;
  for (size_t k = 0; k < piece_first.size(); ++k) {
    const size_t end = k + 1 < piece_first.size() ? piece_first[k + 1] : n;
    for (size_t i = piece_first[k]; i < end; ++i) {
      const InputPoint& p = whole.points[i];
      const auto [at, fresh] = first_at.emplace(Key{p.x, p.y, p.z}, static_cast<uint32_t>(i));
      same_as[i] = !fresh && at->second < piece_first[k] ? at->second : static_cast<uint32_t>(i);
      merged += same_as[i] != i;
    }
  }
  if (merged == 0) return;
  std::vector<uint32_t> new_index(n);
  uint32_t kept = 0;
  for (size_t i = 0; i < n; ++i) new_index[i] = same_as[i] == i ? kept++ : new_index[same_as[i]];
  size_t differing = 0;
  for (VertexField& f : whole.fields) {
    const auto c = static_cast<size_t>(f.components);
    // (Bit for bit: a NaN a writer repeats is the same NaN.)
    for (size_t i = 0; i < n; ++i)
      if (same_as[i] != i && std::memcmp(f.values.data() + i * c, f.values.data() + size_t{same_as[i]} * c,
                                         c * sizeof(double)) != 0)
        ++differing;
    size_t to = 0;
    for (size_t i = 0; i < n; ++i)
      if (same_as[i] == i)
        for (size_t j = 0; j < c; ++j) f.values[to++] = f.values[i * c + j];
    f.values.resize(to);
  }
  size_t to = 0;
  for (size_t i = 0; i < n; ++i)
    if (same_as[i] == i) whole.points[to++] = whole.points[i];
  whole.points.resize(to);
  for (auto& t : whole.tets)
    for (uint32_t& v : t) v = new_index[v];
  for (auto& f : whole.tagged_faces)
    for (uint32_t& v : f) v = new_index[v];
  for (auto& e : whole.tet_edge_nodes)
    for (uint32_t& v : e)
      if (v != InputMesh::kNoEdgeNode) v = new_index[v];
  for (uint32_t& v : whole.other_edge_nodes) v = new_index[v];
  if (differing > 0)
    whole.left_out.push_back("the values at " + std::to_string(differing) +
                             " copies of points the pieces share that differ from the first piece's "
                             "(its are kept; counted once a field)");
}

}  // namespace

InputMesh read_pvtu(const std::string& path) {
  VtuParser p(path);
  p.parse();
  const Element& root = p.root();
  if (root.name != "VTKFile") p.fail_at(root.offset, "root element is <" + root.name + ">, not <VTKFile>");
  if (const auto* t = root.attr("type"); !t || *t != "PUnstructuredGrid")
    p.fail_at(root.offset, "a .pvtu is type=\"PUnstructuredGrid\", got \"" + (t ? *t : "") + "\"");
  std::vector<std::pair<std::string, size_t>> sources;
  for (size_t id : root.children) {
    const Element& grid = p.element(id);
    if (grid.name != "PUnstructuredGrid") continue;
    for (size_t piece : grid.children)
      if (p.element(piece).name == "Piece") {
        const std::string* source = p.element(piece).attr("Source");
        if (!source || source->empty()) p.fail_at(p.element(piece).offset, "<Piece> without a Source");
        sources.emplace_back(*source, p.element(piece).offset);
      }
  }
  if (sources.empty()) p.fail_at(root.offset, "no <PUnstructuredGrid> with a <Piece Source=...>");
  // The pieces' paths are relative to the .pvtu's folder. Points a parallel
  // writer repeats on the pieces' borders are merged (merge_shared_points).
  const size_t slash = path.find_last_of('/');
  const std::string folder = slash == std::string::npos ? "" : path.substr(0, slash + 1);
  InputMesh whole;
  std::vector<size_t> piece_first;
  for (size_t k = 0; k < sources.size(); ++k) {
    const std::string piece = sources[k].first.front() == '/' ? sources[k].first : folder + sources[k].first;
    piece_first.push_back(whole.points.size());
    append_piece(whole, read_vtu(piece), k == 0, piece);
  }
  merge_shared_points(whole, piece_first);
  return whole;
}

}  // namespace dtm
