#include "vtu_reader.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstring>
#include <map>
#include <optional>

#include "scalar_type.h"
#include "text_cursor.h"

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

constexpr int kVtkTetra = 10;

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

int base64_value(char c) {
  if (c >= 'A' && c <= 'Z') return c - 'A';
  if (c >= 'a' && c <= 'z') return c - 'a' + 26;
  if (c >= '0' && c <= '9') return c - '0' + 52;
  if (c == '+') return 62;
  if (c == '/') return 63;
  return -1;
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
    if (const auto* c = root.attr("compressor"))
      p_.fail_at(root.offset, "unsupported: compressed data (compressor=\"" + *c + "\"); save uncompressed");
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
    if (pieces.size() != 1)
      p_.fail_at(grid.offset, "unsupported: " + std::to_string(pieces.size()) + " pieces (one is read)");
    const Element& piece = p_.element(pieces[0]);
    const uint64_t n = count_attr(piece, "NumberOfPoints"), cells = count_attr(piece, "NumberOfCells");

    InputMesh out;
    const auto xyz = array(only_child(only_child(piece, "Points"), "DataArray"), n, 3);
    for (uint64_t i = 0; i < n; ++i) {
      out.points.push_back({xyz[3 * i], xyz[3 * i + 1], xyz[3 * i + 2]});
      if (!std::isfinite(xyz[3 * i]) || !std::isfinite(xyz[3 * i + 1]) || !std::isfinite(xyz[3 * i + 2]))
        p_.fail_at(only_child(piece, "Points").offset, "point " + std::to_string(i) + " is not finite");
    }
    if (const Element* pd = optional_child(piece, "PointData"))
      for (size_t id : pd->children) {
        const Element& da = p_.element(id);
        if (da.name != "DataArray") continue;
        VertexField f;
        f.name = da.attr("Name") ? *da.attr("Name") : "unnamed";
        f.components = static_cast<int>(count_attr(da, "NumberOfComponents", 1));
        if (f.components < 1 || f.components > 64)
          p_.fail_at(da.offset, "NumberOfComponents must be 1 to 64");
        f.values = array(da, n, f.components);
        if (const auto* t = da.attr("type"); t && xml_type(*t)) f.type = *xml_type(*t);
        out.fields.push_back(std::move(f));
      }
    read_cells(piece, cells, n, out);
    return out;
  }

 private:
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
    const int size = scalar_size(*type), hsize = scalar_size(header_type_);
    std::string bytes;
    size_t where = da.offset;  // for messages
    if (*format == "binary") {
      size_t pos = 0;
      if (const std::string e = base64_decode(da.text, pos, da.text.size(), bytes); !e.empty())
        p_.fail_at(da.offset, what + ": " + e);
    } else if (*format == "appended") {
      const uint64_t offset = count_attr(da, "offset");
      if (offset >= p_.appended().size())
        p_.fail_at(da.offset,
                   what + ": offset " + std::to_string(offset) + " is past the end of the appended data");
      if (p_.appended_raw()) {
        const std::string_view rest = p_.appended().substr(offset);
        where = p_.appended_offset() + offset;
        if (rest.size() < static_cast<size_t>(hsize))
          throw FormatError(p_.path() + ": byte " + std::to_string(where) + ": " + what +
                            ": file ends in its header");
        const auto count = static_cast<uint64_t>(scalar_at(rest.data(), header_type_, big_endian_));
        if (count > rest.size() - hsize)
          throw FormatError(p_.path() + ": byte " + std::to_string(where) + ": " + what + ": " +
                            std::to_string(count) + " bytes announced, " +
                            std::to_string(rest.size() - hsize) + " left");
        bytes.assign(rest.substr(0, hsize + count));
      } else {
        size_t pos = offset;
        std::string e = base64_decode(p_.appended(), pos, hsize, bytes);
        if (e.empty() && bytes.size() >= static_cast<size_t>(hsize)) {
          const auto count = static_cast<uint64_t>(scalar_at(bytes.data(), header_type_, big_endian_));
          if (count > p_.appended().size())
            p_.fail_at(da.offset,
                       what + ": " + std::to_string(count) + " bytes announced, more than the file holds");
          e = base64_decode(p_.appended(), pos, hsize + count, bytes);
        }
        if (!e.empty()) p_.fail_at(da.offset, what + ": " + e);
      }
    } else {
      p_.fail_at(da.offset, what + ": unknown format \"" + *format + "\"");
    }
    if (bytes.size() < static_cast<size_t>(hsize)) p_.fail_at(da.offset, what + ": data ends in its header");
    const auto count = static_cast<uint64_t>(scalar_at(bytes.data(), header_type_, big_endian_));
    if (count != n * size || bytes.size() < hsize + count)
      throw FormatError(
          (where == da.offset ? p_.line_of(da.offset) : p_.path() + ": byte " + std::to_string(where)) +
          ": " + what + ": block of " + std::to_string(count) + " bytes (" +
          std::to_string(bytes.size() - hsize) + " present), expected " + std::to_string(n) + " values of " +
          std::to_string(size) + " bytes");
    out.reserve(n);
    for (uint64_t i = 0; i < n; ++i)
      out.push_back(scalar_at(bytes.data() + hsize + i * size, *type, big_endian_));
    return out;
  }

  void read_cells(const Element& piece, uint64_t cells, uint64_t points, InputMesh& out) {
    const Element* ce = optional_child(piece, "Cells");
    if (!ce) {
      if (cells > 0) p_.fail_at(piece.offset, "NumberOfCells=" + std::to_string(cells) + " but no <Cells>");
      return;
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
          p_.fail_at(conn_element.offset, "cell " + std::to_string(c) + ": point index " +
                                              std::to_string(static_cast<int64_t>(conn[k])) +
                                              " out of range");
      if (types[c] != kVtkTetra) continue;
      if (e - b != 4)
        p_.fail_at(ce->offset,
                   "cell " + std::to_string(c) + " is a VTK_TETRA with " + std::to_string(e - b) + " points");
      out.tets.push_back({static_cast<uint32_t>(conn[b]), static_cast<uint32_t>(conn[b + 1]),
                          static_cast<uint32_t>(conn[b + 2]), static_cast<uint32_t>(conn[b + 3])});
    }
  }

  VtuParser p_;
  bool big_endian_ = false;
  ScalarType header_type_ = ScalarType::kUInt32;
};

}  // namespace

InputMesh read_vtu(const std::string& path) { return VtuReader(path).read(); }

}  // namespace dtm
