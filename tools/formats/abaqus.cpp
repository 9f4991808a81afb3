#include "abaqus.h"

#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <deque>
#include <filesystem>
#include <map>
#include <set>
#include <span>
#include <string>
#include <string_view>
#include <unordered_map>
#include <utility>
#include <vector>

#include "cell_split.h"
#include "common/release.h"
#include "format_error.h"
#include "render_util.h"
#include "second_order.h"
#include "text_cursor.h"

namespace dtm {
namespace {

std::string upper(std::string_view s) {
  std::string out(s);
  for (char& c : out) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
  return out;
}

std::string_view trimmed(std::string_view s) {
  const auto blank = [](char c) { return c == ' ' || c == '\t' || c == '\r'; };
  while (!s.empty() && blank(s.front())) s.remove_prefix(1);
  while (!s.empty() && blank(s.back())) s.remove_suffix(1);
  return s;
}

// A data line's entries: split at commas, each trimmed; a trailing comma
// (a line continued, or gmsh's set lists) adds none.
std::vector<std::string_view> entries(std::string_view line) {
  std::vector<std::string_view> out;
  size_t at = 0;
  while (at <= line.size()) {
    const size_t comma = std::min(line.find(',', at), line.size());
    out.push_back(trimmed(line.substr(at, comma - at)));
    at = comma + 1;
  }
  if (!out.empty() && out.back().empty()) out.pop_back();
  return out;
}

// A keyword line ("*Element, type=C3D4, ELSET=Volume1"): the keyword and
// its parameters' names in upper case, their values as written (unquoted).
struct Keyword {
  std::string name;
  std::vector<std::pair<std::string, std::string>> parameters;
  bool has(std::string_view p) const {
    return std::any_of(parameters.begin(), parameters.end(), [&](const auto& q) { return q.first == p; });
  }
  std::string value(std::string_view p) const {
    for (const auto& [n, v] : parameters)
      if (n == p) return v;
    return {};
  }
};

Keyword keyword_of(std::string_view line) {
  Keyword k;
  std::vector<std::string_view> pieces;
  size_t at = 1;  // past the '*'
  bool quoted = false;
  size_t start = at;
  for (; at <= line.size(); ++at) {
    if (at < line.size() && line[at] == '"') quoted = !quoted;
    if (at == line.size() || (line[at] == ',' && !quoted)) {
      pieces.push_back(trimmed(line.substr(start, at - start)));
      start = at + 1;
    }
  }
  k.name = upper(pieces.front());
  for (size_t i = 1; i < pieces.size(); ++i) {
    if (pieces[i].empty()) continue;
    const size_t eq = pieces[i].find('=');
    std::string name = upper(trimmed(pieces[i].substr(0, eq)));
    std::string value = eq == std::string_view::npos ? "" : std::string(trimmed(pieces[i].substr(eq + 1)));
    if (value.size() >= 2 && value.front() == '"' && value.back() == '"')
      value = value.substr(1, value.size() - 2);
    k.parameters.emplace_back(std::move(name), std::move(value));
  }
  return k;
}

// What an element type is to the mesh: its shape, nodes and corners.
enum class Shape : uint8_t { kTetrahedron, kPyramid, kPrism, kHexahedron, kTriangle, kQuadrilateral, kOther };
struct ElementType {
  Shape shape = Shape::kOther;
  int nodes = 0, corners = 0;
  bool solid() const { return shape <= Shape::kHexahedron; }
  bool face() const { return shape == Shape::kTriangle || shape == Shape::kQuadrilateral; }
};

// By name: the solids C3D<n> (and heat transfer's DC3D<n>), whatever
// letters follow (C3D10M, C3D8R, C3D4H); the 2D elements whose corners
// can tag a face (shells S, STRI, membranes M3D, SFM3D, rigid R3D,
// continuum CPS and CPE, heat transfer DS) with 3, 4, 6, 8 or 9 nodes.
ElementType element_type(const std::string& type) {
  const auto digits_after = [&](std::string_view prefix) -> int {
    if (type.rfind(prefix, 0) != 0) return -1;
    size_t end = prefix.size();
    while (end < type.size() && std::isdigit(static_cast<unsigned char>(type[end]))) ++end;
    int n = -1;
    if (end == prefix.size() ||
        !parse_whole(std::string_view(type).substr(prefix.size(), end - prefix.size()), n))
      return -1;
    return n;
  };
  for (const char* prefix : {"DC3D", "C3D"}) {
    switch (digits_after(prefix)) {
      case 4:
        return {Shape::kTetrahedron, 4, 4};
      case 10:
        return {Shape::kTetrahedron, 10, 4};
      case 5:
        return {Shape::kPyramid, 5, 5};
      case 6:
        return {Shape::kPrism, 6, 6};
      case 15:
        return {Shape::kPrism, 15, 6};
      case 8:
        return {Shape::kHexahedron, 8, 8};
      case 20:
        return {Shape::kHexahedron, 20, 8};
      case 27:
        return {Shape::kHexahedron, 27, 8};
      default:
        break;
    }
  }
  for (const char* prefix : {"SFM3D", "M3D", "R3D", "STRI", "CPS", "CPE", "DS", "S"}) {
    int n = digits_after(prefix);
    if (n == 65) n = 6;  // STRI65
    if (n == 3 || n == 6) return {Shape::kTriangle, n, 3};
    if (n == 4 || n == 8 || n == 9) return {Shape::kQuadrilateral, n, 4};
    if (n >= 0) break;
  }
  return {};
}

// Abaqus's faces S1..S6 of the solids, as corner slots (0-based).
struct FaceSlots {
  int count;
  std::array<int, 4> slots;
};
const std::array<FaceSlots, 6>* faces_of(Shape shape) {
  static const std::array<FaceSlots, 6> tetrahedron = {
      {{3, {0, 1, 2}}, {3, {0, 3, 1}}, {3, {1, 3, 2}}, {3, {2, 3, 0}}, {0, {}}, {0, {}}}};
  static const std::array<FaceSlots, 6> prism = {
      {{3, {0, 1, 2}}, {3, {3, 5, 4}}, {4, {0, 3, 4, 1}}, {4, {1, 4, 5, 2}}, {4, {2, 5, 3, 0}}, {0, {}}}};
  static const std::array<FaceSlots, 6> hexahedron = {{{4, {0, 1, 2, 3}},
                                                       {4, {4, 7, 6, 5}},
                                                       {4, {0, 4, 5, 1}},
                                                       {4, {1, 5, 6, 2}},
                                                       {4, {2, 6, 7, 3}},
                                                       {4, {3, 7, 4, 0}}}};
  static const std::array<FaceSlots, 6> pyramid = {
      {{4, {0, 1, 2, 3}}, {3, {0, 4, 1}}, {3, {1, 4, 2}}, {3, {2, 4, 3}}, {3, {3, 4, 0}}, {0, {}}}};
  switch (shape) {
    case Shape::kTetrahedron:
      return &tetrahedron;
    case Shape::kPrism:
      return &prism;
    case Shape::kHexahedron:
      return &hexahedron;
    case Shape::kPyramid:
      return &pyramid;
    default:
      return nullptr;
  }
}

// A 10-node tetrahedron's edge nodes, Abaqus's slots 4-9 on the edges
// (0,1) (1,2) (0,2) (0,3) (1,3) (2,3), in kTetEdges' order.
constexpr std::array<int, 6> kAbaqusEdgeSlot = {4, 6, 7, 5, 8, 9};

// A set of elements or nodes, as the file defines it: numbers, and the
// sets it includes by name.
struct Set {
  std::string name;  // as first written
  std::vector<int64_t> ids;
  std::vector<std::string> includes;  // upper case
  bool from_element_lines = false;    // *ELEMENT's ELSET= (or *NODE's NSET=)
};

class Sets {
 public:
  Set& at(const std::string& name, bool from_element_lines) {
    const std::string key = upper(name);
    auto [it, added] = index_.try_emplace(key, sets_.size());
    if (added) sets_.push_back({name, {}, {}, from_element_lines});
    return sets_[it->second];
  }
  const Set* find(const std::string& name) const {
    const auto it = index_.find(upper(name));
    return it == index_.end() ? nullptr : &sets_[it->second];
  }
  const std::vector<Set>& all() const { return sets_; }
  // The numbers of a set with those of the sets it includes (each set once).
  std::vector<int64_t> resolved(const Set& s, const std::string& path) const {
    std::vector<int64_t> out;
    std::set<const Set*> seen;
    std::vector<const Set*> todo = {&s};
    while (!todo.empty()) {
      const Set* t = todo.back();
      todo.pop_back();
      if (!seen.insert(t).second) continue;
      out.insert(out.end(), t->ids.begin(), t->ids.end());
      for (const std::string& name : t->includes) {
        const Set* u = find(name);
        if (!u)
          throw FormatError(path + ": set " + s.name + " names a set " + name +
                            " that the file does not define");
        todo.push_back(u);
      }
    }
    std::sort(out.begin(), out.end());
    out.erase(std::unique(out.begin(), out.end()), out.end());
    return out;
  }

 private:
  std::vector<Set> sets_;
  std::map<std::string, size_t> index_;
};

// One element as read: its type, where its tetrahedra or face triangles
// are, and its corners (for *SURFACE's faces).
struct Element {
  Shape shape = Shape::kOther;
  uint32_t first = 0;    // its first tetrahedron (a solid) or face triangle (a 2D element)
  uint8_t count = 0;     // how many
  uint32_t corners = 0;  // where its corners start in corner_pool_
};

class AbaqusReader {
 public:
  explicit AbaqusReader(const std::string& path) { open(path, path); }

  InputMesh read() {
    std::string_view line;
    while (next_line(line)) {
      if (line[0] != '*')
        fail("expected a keyword line (starting with '*'), found '" + std::string(line) + "'");
      const Keyword k = keyword_of(line);
      if (k.name == "NODE" && !k.has("OUTPUT") && !k.has("PRINT") && !k.has("FILE")) {
        nodes(k);
      } else if (k.name == "ELEMENT" && !k.has("OUTPUT")) {
        elements(k);
      } else if (k.name == "ELSET" || k.name == "NSET") {
        set_lines(k);
      } else if (k.name == "SOLID SECTION") {
        if (k.value("ELSET").empty()) fail("*SOLID SECTION without ELSET=");
        sections_.emplace_back(k.value("ELSET"), k.value("MATERIAL"));
        skip_data();
      } else if (k.name == "SURFACE") {
        surface(k);
      } else if (k.name == "INCLUDE") {
        include(k);
      } else if (k.name == "PART") {
        if (++parts_ > 1)
          fail("a second *PART: meshenc reads a model of one part (write the assembly as one mesh)");
        skip_data();
      } else if (k.name == "INSTANCE") {
        instance();
      } else {
        static const std::set<std::string> quiet = {"HEADING",      "END PART",     "ASSEMBLY",
                                                    "END ASSEMBLY", "END INSTANCE", "PREPRINT"};
        if (!quiet.count(k.name)) skipped_keywords_.insert("*" + k.name);
        skip_data();
      }
    }
    if (out_.points.empty()) throw FormatError(path_ + ": no *NODE lines");
    set_regions();
    set_face_tags();
    set_node_sets();
    note_left_out();
    return std::move(out_);
  }

 private:
  struct Source {
    std::string path, text;
    size_t pos = 0, line = 0;
  };

  void open(const std::string& path, const std::string& named) {
    if (sources_.size() >= 16) fail("*INCLUDE nested more than 16 deep");
    std::string text;
    try {
      text = read_whole_file(path);
    } catch (const FormatError&) {
      if (sources_.empty()) throw;
      fail("*INCLUDE, INPUT=" + named + ": cannot open " + path);
    }
    if (sources_.empty()) path_ = path;
    sources_.push_back({path, std::move(text)});
    stack_.push_back(sources_.size() - 1);
  }

  // The next line that is not blank and not a comment ('**'), from the
  // innermost open file; false at the end of the outermost.
  bool next_line(std::string_view& line) {
    if (again_) {
      again_ = false;
      line = last_;
      return true;
    }
    while (!stack_.empty()) {
      Source& s = sources_[stack_.back()];
      if (s.pos >= s.text.size()) {
        stack_.pop_back();
        continue;
      }
      const size_t end = std::min(s.text.find('\n', s.pos), s.text.size());
      std::string_view l = trimmed(std::string_view(s.text).substr(s.pos, end - s.pos));
      s.pos = end + 1;
      ++s.line;
      where_ = &s;
      if (l.empty() || l.rfind("**", 0) == 0) continue;
      last_ = line = l;
      return true;
    }
    return false;
  }
  void unread() { again_ = true; }

  // The next data line, or false at a keyword line (read again next).
  bool data_line(std::string_view& line) {
    if (!next_line(line)) return false;
    if (line[0] == '*') {
      unread();
      return false;
    }
    return true;
  }
  void skip_data() {
    std::string_view line;
    while (data_line(line)) {
    }
  }

  // "file:line: problem", of the line last read or of `line` in its file.
  [[noreturn]] void fail(const std::string& problem, size_t line = 0) const {
    if (!where_) throw FormatError(path_ + ": " + problem);
    throw FormatError(where_->path + ":" + std::to_string(line ? line : where_->line) + ": " + problem);
  }

  template <class T>
  T number(std::string_view entry, const char* what) const {
    if (!entry.empty() && entry.front() == '+') entry.remove_prefix(1);
    T value{};
    if (!parse_whole(entry, value))
      fail(std::string("expected ") + what + ", found '" + std::string(entry) + "'");
    return value;
  }

  uint32_t node(std::string_view entry) const {
    const auto it = node_index_.find(number<int64_t>(entry, "a node number"));
    if (it == node_index_.end())
      fail("node " + std::string(entry) + " is not defined (by a *NODE line before it)");
    return it->second;
  }

  void include(const Keyword& k) {
    const std::string input = k.value("INPUT");
    if (input.empty()) fail("*INCLUDE without INPUT=");
    // Relative to the including file's folder (as Abaqus/CAE writes its
    // includes beside the model), else to the working folder.
    std::filesystem::path p(input);
    if (p.is_relative()) {
      const std::filesystem::path beside = std::filesystem::path(where_->path).parent_path() / p;
      if (std::filesystem::exists(beside)) p = beside;
    }
    open(p.string(), input);
  }

  // An instance placed as its part is: Abaqus/CAE's "*Instance ... *End
  // Instance" with nothing between. A translation or rotation line moves
  // it, which the mesh read would not show: refused.
  void instance() {
    std::string_view line;
    if (data_line(line))
      fail(
          "an *INSTANCE moved or rotated: meshenc reads the part's mesh where the part defines it "
          "(write the model with the instance's mesh in place)");
  }

  void nodes(const Keyword& k) {
    Set* nset = k.value("NSET").empty() ? nullptr : &nsets_.at(k.value("NSET"), true);
    std::string_view line;
    while (data_line(line)) {
      const auto e = entries(line);
      if (e.size() < 3 || e.size() > 4) fail("expected 'node number, x, y[, z]'");
      const auto id = number<int64_t>(e[0], "a node number");
      const InputPoint p{number<double>(e[1], "a coordinate"), number<double>(e[2], "a coordinate"),
                         e.size() > 3 ? number<double>(e[3], "a coordinate") : 0.0};
      if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z))
        fail("a coordinate is not finite");
      if (!node_index_.emplace(id, static_cast<uint32_t>(out_.points.size())).second)
        fail("node " + std::to_string(id) + " is defined twice");
      if (out_.points.size() >= UINT32_MAX - 1) fail("more than 2^32 - 2 nodes");
      out_.points.push_back(p);
      if (nset) nset->ids.push_back(id);
    }
  }

  void elements(const Keyword& k) {
    const std::string type = upper(k.value("TYPE"));
    if (type.empty()) fail("*ELEMENT without TYPE=");
    const ElementType t = element_type(type);
    Set* elset = k.value("ELSET").empty() ? nullptr : &elsets_.at(k.value("ELSET"), true);
    std::string_view line;
    std::vector<std::string_view> record;
    std::vector<uint32_t> nodes;
    while (data_line(line)) {
      // A record runs over lines until it has its nodes (an unknown type's:
      // while its lines end with a comma).
      record = entries(line);
      const size_t first_line = where_->line;
      while ((t.shape == Shape::kOther ? !line.empty() && line.back() == ','
                                       : record.size() < static_cast<size_t>(t.nodes) + 1) &&
             data_line(line)) {
        const auto more = entries(line);
        record.insert(record.end(), more.begin(), more.end());
      }
      const auto id = number<int64_t>(record.at(0), "an element number");
      if (elset) elset->ids.push_back(id);
      if (t.shape == Shape::kOther) {
        if (!element_index_.emplace(id, Element{}).second)
          fail("element " + std::to_string(id) + " is defined twice");
        ++other_elements_[type];
        continue;
      }
      if (record.size() != static_cast<size_t>(t.nodes) + 1)
        fail("element " + std::to_string(id) + " of type " + type + " needs " + std::to_string(t.nodes) +
                 " nodes, found " + std::to_string(record.size() - 1),
             first_line);
      nodes.clear();
      for (size_t i = 1; i < record.size(); ++i) nodes.push_back(node(record[i]));
      Element e{t.shape, 0, 0, static_cast<uint32_t>(corner_pool_.size())};
      corner_pool_.insert(corner_pool_.end(), nodes.begin(), nodes.begin() + t.corners);
      if (t.shape == Shape::kTetrahedron) {
        e.first = static_cast<uint32_t>(out_.tets.size()), e.count = 1;
        out_.tets.push_back({nodes[0], nodes[1], nodes[2], nodes[3]});
        if (t.nodes == 10) {
          std::array<uint32_t, 6> edge{};
          for (size_t s = 0; s < 6; ++s) edge[s] = nodes[static_cast<size_t>(kAbaqusEdgeSlot[s])];
          add_tet_edge_nodes(out_, edge);
        }
      } else if (t.solid()) {
        e.first = static_cast<uint32_t>(out_.tets.size());
        e.count = static_cast<uint8_t>(add_split_cell(nodes, static_cast<size_t>(t.corners), out_));
        ++split_[static_cast<size_t>(t.corners)];
      } else {
        // A 2D element: its triangles, tagged once the sets are known; its
        // nodes past the corners are a second-order face's.
        e.first = static_cast<uint32_t>(face_triangles_.size());
        if (t.shape == Shape::kTriangle) {
          face_triangles_.push_back({nodes[0], nodes[1], nodes[2]});
          e.count = 1;
        } else {
          for (const auto& half : split_quad({nodes[0], nodes[1], nodes[2], nodes[3]}))
            face_triangles_.push_back(half);
          e.count = 2;
        }
        out_.other_edge_nodes.insert(out_.other_edge_nodes.end(), nodes.begin() + t.corners, nodes.end());
      }
      if (!element_index_.emplace(id, e).second) fail("element " + std::to_string(id) + " is defined twice");
      ++element_count_[static_cast<size_t>(t.shape)];
    }
  }

  void set_lines(const Keyword& k) {
    const bool elements = k.name == "ELSET";
    const std::string name = k.value(elements ? "ELSET" : "NSET");
    if (name.empty()) fail("*" + k.name + " without " + k.name + "=");
    Set& s = (elements ? elsets_ : nsets_).at(name, false);
    const bool generate = k.has("GENERATE");
    std::string_view line;
    while (data_line(line)) {
      const auto e = entries(line);
      if (generate) {
        if (e.size() < 2 || e.size() > 3) fail("expected 'first, last[, step]' (GENERATE)");
        const auto first = number<int64_t>(e[0], "a number"), last = number<int64_t>(e[1], "a number");
        const int64_t step = e.size() > 2 ? number<int64_t>(e[2], "a step") : 1;
        if (step < 1 || last < first) fail("GENERATE needs first <= last and a step of 1 or more");
        if ((last - first) / step >= int64_t{1} << 32) fail("GENERATE names more than 2^32 numbers");
        for (int64_t i = first; i <= last; i += step) s.ids.push_back(i);
        continue;
      }
      for (std::string_view entry : e) {
        int64_t id = 0;
        double real = 0;
        if (parse_whole(entry, id))
          s.ids.push_back(id);
        else if (parse_whole(entry, real) && real == std::trunc(real) && std::abs(real) < 0x1p62)
          s.ids.push_back(static_cast<int64_t>(real));  // (meshio writes "12.0")
        else if (!entry.empty())
          s.includes.push_back(upper(entry));
      }
    }
  }

  void surface(const Keyword& k) {
    const std::string name = k.value("NAME");
    if (name.empty()) fail("*SURFACE without NAME=");
    const std::string type = upper(k.value("TYPE"));
    std::string_view line;
    if (!type.empty() && type != "ELEMENT") {
      skipped_surfaces_.push_back(name + " (TYPE=" + k.value("TYPE") + ")");
      skip_data();
      return;
    }
    auto [it, added] = surfaces_.try_emplace(name);
    if (added) surface_order_.push_back(name);
    auto& faces = it->second;
    while (data_line(line)) {
      const auto e = entries(line);
      if (e.size() != 2) fail("expected 'element or element set, face (S1..S6)'");
      const std::string face = upper(e[1]);
      int f = 0;
      if (face.size() != 2 || face[0] != 'S' || !parse_whole(std::string_view(face).substr(1), f) || f < 1 ||
          f > 6)
        fail("expected a solid's face S1..S6, found '" + std::string(e[1]) + "'");
      faces.push_back({std::string(e[0]), f - 1, where_->line});
    }
  }

  // The chosen sets as labels 1..K of what their elements made
  // (`per_element`: its tetrahedra or face triangles), the first set
  // claiming an item keeping it; returns the items two sets claimed.
  uint64_t label(const std::vector<const Set*>& family, bool solids, std::vector<int32_t>& labels,
                 std::map<int32_t, std::string>& names) const {
    uint64_t claimed_twice = 0;
    for (size_t k = 0; k < family.size(); ++k) {
      const auto label = static_cast<int32_t>(k + 1);
      names[label] = family[k]->name;
      for (int64_t id : elsets_.resolved(*family[k], path_)) {
        const auto it = element_index_.find(id);
        if (it == element_index_.end())
          throw FormatError(path_ + ": element set " + family[k]->name + " names element " +
                            std::to_string(id) + ", which the file does not define");
        const Element& e = it->second;
        if (e.shape == Shape::kOther || (solids != (e.shape <= Shape::kHexahedron))) continue;
        for (uint32_t i = e.first; i < e.first + e.count; ++i) {
          if (labels[i] != 0)
            ++claimed_twice;
          else
            labels[i] = label;
        }
      }
    }
    return claimed_twice;
  }

  // The element sets that label the solids (or the 2D elements): sets of
  // such elements only (a set of them all, such as CalculiX's Eall, is not
  // one when some set holds fewer), no two sharing one.
  std::vector<const Set*> family(bool solids) const {
    std::vector<const Set*> sets;
    const uint64_t total = solids
                               ? element_count_[0] + element_count_[1] + element_count_[2] + element_count_[3]
                               : element_count_[4] + element_count_[5];
    std::vector<uint64_t> sizes;
    for (const Set& s : elsets_.all()) {
      const auto ids = elsets_.resolved(s, path_);
      const bool fits = !ids.empty() && std::all_of(ids.begin(), ids.end(), [&](int64_t id) {
        const auto it = element_index_.find(id);
        return it != element_index_.end() &&
               (solids ? it->second.shape <= Shape::kHexahedron
                       : it->second.shape == Shape::kTriangle || it->second.shape == Shape::kQuadrilateral);
      });
      if (fits) sets.push_back(&s), sizes.push_back(ids.size());
    }
    if (std::any_of(sizes.begin(), sizes.end(), [&](uint64_t n) { return n < total; })) {
      std::vector<const Set*> kept;
      for (size_t i = 0; i < sets.size(); ++i)
        if (sizes[i] < total) kept.push_back(sets[i]);
      sets = kept;
    }
    // The *ELSET sets (a mesher's named groups) before the *ELEMENT lines'
    // (its entities), each taken unless it shares an element with one
    // taken: gmsh's and meshio's files hold both, the same elements twice.
    std::stable_sort(sets.begin(), sets.end(), [](const Set* a, const Set* b) {
      return !a->from_element_lines && b->from_element_lines;
    });
    std::vector<const Set*> taken;
    std::set<int64_t> claimed;
    for (const Set* s : sets) {
      const auto ids = elsets_.resolved(*s, path_);
      if (std::any_of(ids.begin(), ids.end(), [&](int64_t id) { return claimed.count(id) > 0; })) continue;
      claimed.insert(ids.begin(), ids.end());
      taken.push_back(s);
    }
    return taken;
  }

  void set_regions() {
    const size_t tets = out_.tets.size();
    if (tets == 0) return;
    std::vector<const Set*> chosen;
    if (!sections_.empty()) {
      for (const auto& [elset, material] : sections_) {
        const Set* s = elsets_.find(elset);
        if (!s)
          throw FormatError(path_ + ": a *SOLID SECTION names the element set " + elset +
                            ", which the file does not define");
        chosen.push_back(s);
      }
      out_.region_source = "solid sections' element sets";
    } else {
      chosen = family(true);
      out_.region_source = "element sets";
    }
    if (chosen.empty()) return;
    out_.tet_regions.assign(tets, 0);
    if (const uint64_t twice = label(chosen, true, out_.tet_regions, out_.region_names))
      notes_.push_back(std::to_string(twice) +
                       " tetrahedra in a second region's element set (each kept in its first)");
    for (const Set* s : chosen) used_sets_.insert(upper(s->name));
  }

  void set_face_tags() {
    // The *SURFACE faces first, tagged 1..S, then the 2D elements, tagged by
    // their sets (0 in none).
    std::vector<std::array<uint32_t, 3>> faces;
    std::vector<int32_t> tags;
    int32_t tag = 0;
    for (const std::string& name : surface_order_) {
      ++tag;
      out_.face_tag_names[tag] = name;
      for (const SurfaceFace& f : surfaces_.at(name)) {
        std::vector<int64_t> ids;
        int64_t id = 0;
        if (parse_whole(std::string_view(f.element), id)) {
          ids.push_back(id);
        } else {
          const Set* s = elsets_.find(f.element);
          if (!s)
            throw FormatError(path_ + ":" + std::to_string(f.line) + ": *SURFACE " + name +
                              " names the element set " + f.element + ", which the file does not define");
          ids = elsets_.resolved(*s, path_);
          used_sets_.insert(upper(s->name));
        }
        for (int64_t i : ids) {
          const auto it = element_index_.find(i);
          if (it == element_index_.end())
            throw FormatError(path_ + ":" + std::to_string(f.line) + ": *SURFACE " + name +
                              " names element " + std::to_string(i) + ", which the file does not define");
          const auto* slots = faces_of(it->second.shape);
          if (!slots || (*slots)[static_cast<size_t>(f.face)].count == 0)
            throw FormatError(path_ + ":" + std::to_string(f.line) + ": *SURFACE " + name + ": element " +
                              std::to_string(i) + " has no face S" + std::to_string(f.face + 1));
          const FaceSlots& s = (*slots)[static_cast<size_t>(f.face)];
          const uint32_t* c = corner_pool_.data() + it->second.corners;
          if (s.count == 3) {
            faces.push_back({c[s.slots[0]], c[s.slots[1]], c[s.slots[2]]}), tags.push_back(tag);
          } else {
            for (const auto& half : split_quad({c[s.slots[0]], c[s.slots[1]], c[s.slots[2]], c[s.slots[3]]}))
              faces.push_back(half), tags.push_back(tag);
          }
        }
      }
    }
    if (!face_triangles_.empty()) {
      std::vector<int32_t> labels(face_triangles_.size(), 0);
      std::map<int32_t, std::string> names;
      const auto chosen = family(false);
      label(chosen, false, labels, names);
      for (const Set* s : chosen) used_sets_.insert(upper(s->name));
      for (const auto& [label, name] : names) out_.face_tag_names[label + tag] = name;
      for (size_t i = 0; i < face_triangles_.size(); ++i)
        faces.push_back(face_triangles_[i]), tags.push_back(labels[i] == 0 ? 0 : labels[i] + tag);
    }
    // A face tagged twice keeps its first tag.
    std::set<std::array<uint32_t, 3>> seen;
    uint64_t twice = 0;
    for (size_t i = 0; i < faces.size(); ++i) {
      auto key = faces[i];
      std::sort(key.begin(), key.end());
      if (!seen.insert(key).second) {
        ++twice;
        continue;
      }
      out_.tagged_faces.push_back(faces[i]);
      out_.face_tags.push_back(tags[i]);
    }
    if (twice)
      notes_.push_back(std::to_string(twice) + " faces tagged a second time (each keeps its first tag)");
    if (!out_.tagged_faces.empty()) out_.face_tag_source = "surfaces and 2D elements' element sets";
  }

  // Each node set a 0/1 field.
  void set_node_sets() {
    for (const Set& s : nsets_.all()) {
      VertexField f;
      f.name = kNodeSetFieldPrefix + s.name;
      f.type = ScalarType::kUInt8;
      f.values.assign(out_.points.size(), 0.0);
      for (int64_t id : nsets_.resolved(s, path_)) {
        const auto it = node_index_.find(id);
        if (it == node_index_.end())
          throw FormatError(path_ + ": node set " + s.name + " names node " + std::to_string(id) +
                            ", which the file does not define");
        f.values[it->second] = 1;
      }
      out_.fields.push_back(std::move(f));
    }
  }

  void note_left_out() {
    const auto joined = [](const auto& items) {
      std::string s;
      for (const auto& i : items) s += (s.empty() ? "" : ", ") + std::string(i);
      return s;
    };
    std::vector<std::string> others;
    for (const auto& [type, count] : other_elements_) others.push_back(std::to_string(count) + " " + type);
    if (!others.empty())
      out_.left_out.push_back("elements other than solids and 2D elements (" + joined(others) + ")");
    std::vector<std::string> sets;
    for (const Set& s : elsets_.all())
      if (!used_sets_.count(upper(s.name))) sets.push_back(s.name);
    if (!sets.empty())
      out_.left_out.push_back(
          "element sets " + joined(sets) + " (the stream keeps one region a tetrahedron and one tag a face" +
          (out_.region_names.empty() ? "" : "; the regions are " + joined(region_list())) + ")");
    if (!skipped_surfaces_.empty()) out_.left_out.push_back("surfaces " + joined(skipped_surfaces_));
    std::vector<std::string> materials;
    for (const auto& [elset, material] : sections_)
      if (!material.empty()) materials.push_back(elset + ": " + material);
    if (!materials.empty())
      out_.left_out.push_back("the solid sections' materials (" + joined(materials) + ")");
    if (!skipped_keywords_.empty())
      out_.left_out.push_back("keywords " + joined(skipped_keywords_) + " (the model beyond its mesh)");
    for (const std::string& n : notes_) out_.left_out.push_back(n);
    const std::string split = split_cells_note(split_);
    if (!split.empty()) out_.left_out.push_back(split);
  }

  std::vector<std::string> region_list() const {
    std::vector<std::string> out;
    for (const auto& [label, name] : out_.region_names) out.push_back(name);
    return out;
  }

  struct SurfaceFace {
    std::string element;  // a number or an element set
    int face;             // 0..5
    size_t line;
  };

  std::string path_;
  std::deque<Source> sources_;  // every file opened, kept while lines point into them
  std::vector<size_t> stack_;   // the open ones, innermost last
  const Source* where_ = nullptr;
  std::string_view last_;
  bool again_ = false;
  int parts_ = 0;
  std::unordered_map<int64_t, uint32_t> node_index_;
  std::unordered_map<int64_t, Element> element_index_;
  std::array<uint64_t, 7> element_count_{};
  std::vector<uint32_t> corner_pool_;
  std::vector<std::array<uint32_t, 3>> face_triangles_;
  std::map<size_t, uint64_t> split_;
  std::map<std::string, uint64_t> other_elements_;
  Sets elsets_, nsets_;
  std::vector<std::pair<std::string, std::string>> sections_;  // (element set, material)
  std::map<std::string, std::vector<SurfaceFace>> surfaces_;
  std::vector<std::string> surface_order_, skipped_surfaces_, notes_;
  std::set<std::string> skipped_keywords_, used_sets_;
  InputMesh out_;
};

// An Abaqus label: letters, digits and '_', '-', '.', starting with a letter.
std::string abaqus_label(const std::string& name, const std::string& otherwise) {
  std::string out;
  for (char c : name)
    out += std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '-' || c == '.' ? c : '_';
  if (out.empty()) return otherwise;
  if (!std::isalpha(static_cast<unsigned char>(out[0]))) out = "N_" + out;
  return out;
}

// Numbers 16 a line (Abaqus's most on a data line).
void append_list(std::string& out, const std::vector<size_t>& numbers) {
  for (size_t i = 0; i < numbers.size(); ++i) {
    append_number(out, numbers[i]);
    out += (i + 1) % 16 == 0 || i + 1 == numbers.size() ? "\n" : ", ";
  }
}

}  // namespace

InputMesh read_abaqus(const std::string& path) { return AbaqusReader(path).read(); }

std::string render_abaqus(const OutputMesh& m) {
  std::string out = "*HEADING\nwritten by meshdec\n*NODE\n";
  for (size_t i = 0; i < m.points.size(); ++i) {
    const InputPoint p = m.grid.to_input(m.points[i]);
    append_number(out, i + 1);
    for (double v : {p.x, p.y, p.z}) {
      out += ", ";
      append_number(out, v);
    }
    out += '\n';
  }
  // The linear cells in one block, the second-order ones (Abaqus's node
  // order is VTK's) in another; elements numbered in the mesh's order.
  for (const bool second_order : {false, true}) {
    bool begun = false;
    for (size_t c = 0; c < m.cells.size(); ++c) {
      const ListedNodes n = cell_nodes(m, c, kVtkEdgeSlots);
      if (n.second_order() != second_order) continue;
      if (!begun) out += second_order ? "*ELEMENT, TYPE=C3D10\n" : "*ELEMENT, TYPE=C3D4\n", begun = true;
      append_number(out, c + 1);
      for (size_t k = 0; k < n.count; ++k) {
        out += ", ";
        append_number(out, size_t{n.nodes[k]} + 1);
      }
      out += '\n';
    }
  }
  std::set<std::string> labels;
  const auto unique = [&](std::string label) {
    const std::string base = label;
    for (int k = 2; !labels.insert(upper(label)).second; ++k) label = base + "_" + std::to_string(k);
    return label;
  };
  // A region an element set.
  std::map<int32_t, std::vector<size_t>> regions;
  for (size_t c = 0; c < m.region.size(); ++c) regions[m.region[c]].push_back(c + 1);
  for (const auto& [label, cells] : regions) {
    const auto name = m.region_names.find(label);
    const std::string fallback = "REGION_" + std::to_string(label);
    out += "*ELSET, ELSET=" +
           unique(name != m.region_names.end() ? abaqus_label(name->second, fallback) : fallback) + "\n";
    append_list(out, cells);
  }
  // A face tag an element-based surface: each face as the face S1..S4 of
  // the cell it faces out of.
  if (!m.faces.empty()) {
    // The tagged faces by their corners, sorted; then each cell face that
    // is one, as (cell, Abaqus's face number - 1).
    struct FaceHash {
      size_t operator()(const std::array<uint32_t, 3>& f) const {
        return std::hash<uint64_t>()((uint64_t{f[0]} << 42) ^ (uint64_t{f[1]} << 21) ^ f[2]);
      }
    };
    const auto sorted = [](std::array<uint32_t, 3> f) {
      std::sort(f.begin(), f.end());
      return f;
    };
    std::unordered_map<std::array<uint32_t, 3>, uint32_t, FaceHash> face_of;
    for (uint32_t f = 0; f < m.faces.size(); ++f) face_of.emplace(sorted(m.faces[f]), f);
    std::vector<std::vector<std::pair<uint32_t, uint8_t>>> cells_of(m.faces.size());
    // Outward from a positively turned cell: the faces opposite corners
    // 3, 2, 0 and 1 are Abaqus's S1..S4.
    static constexpr std::array<std::array<int, 3>, 4> kOutward = {
        {{0, 2, 1}, {0, 1, 3}, {1, 2, 3}, {0, 3, 2}}};
    const auto outward = [&](uint32_t c, uint8_t s) {
      const auto& t = m.cells[c];
      return std::array<uint32_t, 3>{t[kOutward[s][0]], t[kOutward[s][1]], t[kOutward[s][2]]};
    };
    for (uint32_t c = 0; c < m.cells.size(); ++c)
      for (uint8_t s = 0; s < 4; ++s) {
        const auto it = face_of.find(sorted(outward(c, s)));
        if (it != face_of.end()) cells_of[it->second].emplace_back(c, s);
      }
    std::map<int32_t, std::vector<std::pair<uint32_t, uint8_t>>> surfaces;
    for (size_t f = 0; f < m.faces.size(); ++f) {
      if (cells_of[f].empty()) continue;
      // The cell the face turns out of (its outward face a cyclic turn of
      // the tagged one), else the first.
      std::pair<uint32_t, uint8_t> chosen = cells_of[f].front();
      for (const auto& [c, s] : cells_of[f]) {
        const auto o = outward(c, s);
        for (int r = 0; r < 3; ++r)
          if (o[r] == m.faces[f][0] && o[(r + 1) % 3] == m.faces[f][1]) chosen = {c, s};
      }
      surfaces[m.face_tags[f]].push_back(chosen);
    }
    for (const auto& [tag, faces] : surfaces) {
      const auto name = m.face_tag_names.find(tag);
      const std::string fallback = "FACES_" + std::to_string(tag);
      out += "*SURFACE, NAME=" +
             unique(name != m.face_tag_names.end() ? abaqus_label(name->second, fallback) : fallback) +
             ", TYPE=ELEMENT\n";
      for (const auto& [c, s] : faces) {
        append_number(out, size_t{c} + 1);
        out += ", S" + std::to_string(s + 1) + "\n";
      }
    }
  }
  // The node set fields, back as node sets.
  for (const OutputField& f : m.fields) {
    if (!is_node_set_field(f)) continue;
    std::vector<size_t> nodes;
    for (size_t i = 0; i < f.bits.size(); ++i)
      if (f.bits[i] != 0) nodes.push_back(i + 1);
    out += "*NSET, NSET=" +
           unique(abaqus_label(f.name.substr(std::string(kNodeSetFieldPrefix).size()), "NSET")) + "\n";
    append_list(out, nodes);
  }
  return out;
}

bool is_node_set_field(const OutputField& f) {
  return f.components == 1 && f.name.rfind(kNodeSetFieldPrefix, 0) == 0 &&
         (f.type == ScalarType::kUInt8 || f.type == ScalarType::kInt8);
}

}  // namespace dtm
