// The Abaqus/CalculiX .inp reader (abaqus.h): the mesh of a model, its
// sets, sections and surfaces; the rest of the model named as left out.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <deque>
#include <filesystem>
#include <map>
#include <set>
#include <string>
#include <string_view>
#include <system_error>
#include <type_traits>
#include <unordered_map>
#include <utility>
#include <vector>

#include "abaqus.h"
#include "abaqus_sets.h"
#include "abaqus_syntax.h"
#include "cell_split.h"
#include "format_error.h"
#include "node_labels.h"
#include "second_order.h"
#include "tagged_faces.h"
#include "text_cursor.h"
#include "vtk_cells.h"

namespace dtm {
namespace {

using abaqus::element_type;
using abaqus::ElementType;
using abaqus::entries;
using abaqus::face_slots;
using abaqus::FaceSlots;
using abaqus::is_face;
using abaqus::is_solid;
using abaqus::Keyword;
using abaqus::keyword_of;
using abaqus::Range;
using abaqus::Set;
using abaqus::Sets;
using abaqus::Shape;
using abaqus::trimmed;
using abaqus::upper;

// One element as read: its shape, where its tetrahedra (a solid) or
// triangles (a 2D element) are, and its nodes (for *SURFACE's faces and
// *NSET's ELSET=).
struct Element {
  Shape shape = Shape::kOther;
  uint32_t first = 0;
  uint8_t count = 0;
  uint8_t nodes = 0;
  uint64_t nodes_at = 0;  // in node_pool_
};

// A *SURFACE line: an element or element set (its key), and its face:
// 0..5 for S1..S6, kSides for a 2D element's SPOS or SNEG.
struct SurfaceLine {
  std::string element, written;  // (a set's key, and its name as written)
  bool is_set = false;
  int face = 0;
  std::string where;  // "file:line"
};
constexpr int kSides = 6;

// Where the lines being read belong: an Abaqus/CAE file's *ASSEMBLY holds
// the instances of its parts and its own nodes and sets (reference points,
// loads), numbered apart from the part's.
enum class Scope { kModel, kPart, kAssembly, kInstance };

class AbaqusReader {
 public:
  explicit AbaqusReader(const std::string& path) : path_(path) { open(path, path); }

  InputMesh read() {
    std::string_view line;
    while (next_line(line)) {
      if (line[0] != '*') fail("expected a keyword line (starting with '*'), found '" + shown(line) + "'");
      const Keyword k = keyword_of(keyword_line(line));
      // (*NODE PRINT, *NODE FILE and *ELEMENT OUTPUT are other keywords:
      // the blanks do not count.)
      if (k.name == "NODE") {
        nodes(k);
      } else if (k.name == "ELEMENT") {
        elements(k);
      } else if (k.name == "ELSET" || k.name == "NSET") {
        set_lines(k);
      } else if (k.name == "SOLIDSECTION") {
        if (k.value("ELSET").empty()) fail("*SOLID SECTION without ELSET=");
        sections_.push_back({reference(k.value("ELSET")), k.value("ELSET"), k.value("MATERIAL"), here()});
        skip_data();
      } else if (k.name == "SURFACE") {
        surface(k);
      } else if (k.name == "INCLUDE") {
        include(k);
      } else if (k.name == "PART") {
        if (++parts_ > 1)
          fail("a second *PART: meshenc reads a model of one part (write the assembly as one mesh)");
        scope_ = Scope::kPart;
        skip_data();
      } else if (k.name == "ENDPART" || k.name == "ENDASSEMBLY") {
        scope_ = Scope::kModel;
        skip_data();
      } else if (k.name == "ASSEMBLY" || k.name == "ENDINSTANCE") {
        scope_ = Scope::kAssembly;
        skip_data();
      } else if (k.name == "INSTANCE") {
        instance();
      } else if (kGenerators.count(k.name)) {
        fail("*" + k.written +
             " makes nodes or elements (or moves them): meshenc reads the nodes and elements listed "
             "(write the model with them made, as Abaqus/CAE and CalculiX's cgx can)");
      } else {
        static const std::set<std::string> quiet = {"HEADING", "PREPRINT"};
        if (!quiet.count(k.name)) skipped_keywords_.insert("*" + k.written);
        skip_data();
      }
    }
    if (out_.points.empty()) throw FormatError(path_ + ": no *NODE lines");
    set_node_labels(out_, node_index_);
    defined_nodes_ = sorted_keys(node_index_);
    defined_elements_ = sorted_keys(element_index_);
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
  struct Section {
    std::string key, name, material;
    std::string where;  // "file:line"
  };
  // (Keywords that make, copy or move nodes and elements: what they make
  // is not listed, and the mesh read would lack it.)
  static inline const std::set<std::string> kGenerators = {"NGEN",  "NFILL",  "NCOPY", "NMAP",
                                                           "ELGEN", "ELCOPY", "SYSTEM"};

  void open(const std::string& path, const std::string& named) {
    if (stack_.size() >= 16) fail("*INCLUDE nested more than 16 deep");
    // (A file: not a folder, a device or a pipe, which could be endless.)
    std::error_code ec;
    if (!std::filesystem::is_regular_file(path, ec)) {
      if (stack_.empty()) throw FormatError(path + ": cannot open file (not a regular file)");
      fail("*INCLUDE, INPUT=" + shown(named) + ": not a file that can be read");
    }
    std::string text;
    try {
      text = read_whole_file(path);
    } catch (const FormatError&) {
      if (stack_.empty()) throw;
      fail("*INCLUDE, INPUT=" + shown(named) + ": cannot open " + shown(path));
    }
    if (text.starts_with(kUtf8ByteOrderMark)) text.erase(0, kUtf8ByteOrderMark.size());  // a Windows editor's
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

  // A keyword line with the lines that continue it (each ending with a
  // comma).
  std::string keyword_line(std::string_view first) {
    std::string line(first);
    std::string_view more;
    while (line.back() == ',' && next_line(more)) {
      if (more[0] == '*') {
        unread();
        break;
      }
      line += more;
    }
    return line;
  }

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
  uint64_t count_data() {
    uint64_t n = 0;
    std::string_view line;
    while (data_line(line)) ++n;
    return n;
  }

  // "file:line: problem", of the line last read or of `line` in its file.
  [[noreturn]] void fail(const std::string& problem, size_t line = 0) const {
    if (!where_) throw FormatError(path_ + ": " + problem);
    throw FormatError(where_->path + ":" + std::to_string(line ? line : where_->line) + ": " + problem);
  }
  // Where the line last read is: "file:line".
  std::string here() const { return where_->path + ":" + std::to_string(where_->line); }
  static std::string shown(std::string_view s) {
    return s.size() > 60 ? std::string(s.substr(0, 57)) + "..." : std::string(s);
  }

  template <class T>
  T number(std::string_view entry, const char* what) const {
    if (!entry.empty() && entry.front() == '+') entry.remove_prefix(1);
    T value{};
    if (parse_whole(entry, value)) return value;
    if constexpr (std::is_floating_point_v<T>) {
      // (Fortran's exponent letter, which CalculiX reads: 1.5D3.)
      std::string e(entry);
      std::replace_if(
          e.begin(), e.end(), [](char c) { return c == 'D' || c == 'd'; }, 'E');
      if (parse_whole(std::string_view(e), value)) return value;
    }
    fail(std::string("expected ") + what + ", found '" + shown(entry) + "'");
  }

  uint32_t node(std::string_view entry) const {
    const auto it = node_index_.find(number<int64_t>(entry, "a node number"));
    if (it == node_index_.end()) fail("node " + shown(entry) + " is not defined (by a *NODE line before it)");
    return it->second;
  }

  // A set's key and name as defined here: an assembly's apart from the
  // part's (Abaqus/CAE gives both sets of the same names).
  std::pair<std::string, std::string> defined(const std::string& name) const {
    if (scope_ == Scope::kAssembly) return {"ASSEMBLY." + upper(name), "assembly." + name};
    return {upper(name), name};
  }
  // The key of a set named here: in an assembly, its own set, or with its
  // instance's name before a dot the part's.
  std::string reference(const std::string& name) const {
    if (scope_ != Scope::kAssembly) return upper(name);
    const size_t dot = name.rfind('.');
    return dot == std::string::npos ? "ASSEMBLY." + upper(name) : upper(name.substr(dot + 1));
  }

  void include(const Keyword& k) {
    const std::string input = k.value("INPUT");
    if (input.empty()) fail("*INCLUDE without INPUT=");
    // Relative to the including file's folder (as Abaqus/CAE writes its
    // includes beside the model), else to the working folder.
    std::filesystem::path p(input);
    std::error_code ec;
    if (p.is_relative()) {
      const std::filesystem::path beside = std::filesystem::path(where_->path).parent_path() / p;
      if (std::filesystem::exists(beside, ec)) p = beside;
    }
    open(p.string(), input);
  }

  // An instance placed as its part is: Abaqus/CAE's "*Instance ... *End
  // Instance" with nothing between but the part's mesh, if any. A
  // translation or rotation line moves it, which the mesh read would not
  // show: refused.
  void instance() {
    if (++instances_ > 1) fail("a second *INSTANCE: meshenc reads a model of one part placed once");
    scope_ = Scope::kInstance;
    std::string_view line;
    if (data_line(line))
      fail(
          "an *INSTANCE moved or rotated: meshenc reads the part's mesh where the part defines it "
          "(write the model with the instance's mesh in place)");
  }

  // The set a *NODE's NSET= or an *ELEMENT's ELSET= puts its lines in, or
  // null without one.
  Set* line_set(Sets& sets, const Keyword& k, const char* parameter) const {
    if (k.value(parameter).empty()) return nullptr;
    const auto [key, name] = defined(k.value(parameter));
    Set& s = sets.at(key, name);
    s.from_element_lines = true;
    return &s;
  }

  void nodes(const Keyword& k) {
    if (scope_ == Scope::kAssembly) {
      // Reference points, numbered apart from the part's nodes.
      assembly_nodes_ += count_data();
      return;
    }
    const std::string system = upper(k.value("SYSTEM"));
    if (!system.empty() && system != "R")
      fail("*NODE, SYSTEM=" + shown(k.value("SYSTEM")) + ": meshenc reads rectangular coordinates only");
    Set* nset = line_set(nsets_, k, "NSET");
    std::string_view line;
    while (data_line(line)) {
      const auto e = entries(line);
      if (e.size() < 3 || e.size() > 7) fail("expected 'node number, x, y[, z[, normal]]'");
      const auto id = number<int64_t>(e[0], "a node number");
      const InputPoint p{number<double>(e[1], "a coordinate"), number<double>(e[2], "a coordinate"),
                         e.size() > 3 ? number<double>(e[3], "a coordinate") : 0.0};
      if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z))
        fail("a coordinate is not finite");
      if (!node_index_.emplace(id, static_cast<uint32_t>(out_.points.size())).second)
        fail("node " + std::to_string(id) + " is defined twice");
      if (out_.points.size() >= UINT32_MAX - 1) fail("more than 2^32 - 2 nodes");
      out_.points.push_back(p);
      node_normals_ += e.size() > 4;
      if (nset) nset->numbers.push_back(id);
    }
  }

  void elements(const Keyword& k) {
    const std::string type = upper(k.value("TYPE"));
    if (type.empty()) fail("*ELEMENT without TYPE=");
    if (scope_ == Scope::kAssembly) {
      other_elements_[type + " of the assembly"] += count_data();
      return;
    }
    const ElementType t = element_type(type);
    Set* elset = line_set(elsets_, k, "ELSET");
    std::string_view line;
    std::vector<std::string_view> record;
    std::vector<uint32_t> nodes;
    while (data_line(line)) {
      // A record runs over lines until it has its nodes (an unknown type's:
      // while its lines end with a comma).
      record = entries(line);
      const size_t first_line = where_->line;
      while ((t.shape == Shape::kOther ? line.back() == ','
                                       : record.size() < static_cast<size_t>(t.nodes) + 1) &&
             data_line(line)) {
        const auto more = entries(line);
        record.insert(record.end(), more.begin(), more.end());
      }
      const auto id = number<int64_t>(record.at(0), "an element number");
      if (elset) elset->numbers.push_back(id);
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
      Element e{t.shape, 0, 0, static_cast<uint8_t>(t.nodes), node_pool_.size()};
      node_pool_.insert(node_pool_.end(), nodes.begin(), nodes.end());
      if (t.shape == Shape::kTetrahedron) {
        e.first = static_cast<uint32_t>(out_.tets.size()), e.count = 1;
        out_.tets.push_back({nodes[0], nodes[1], nodes[2], nodes[3]});
        if (t.nodes == 10) {
          std::array<uint32_t, 6> edge{};
          for (size_t s = 0; s < 6; ++s) edge[s] = nodes[static_cast<size_t>(kVtkTetEdgeNodes[s])];
          add_tet_edge_nodes(out_, edge);
        }
      } else if (is_solid(t.shape)) {
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
    if (name.empty()) fail("*" + k.written + " without " + k.name + "=");
    if (scope_ == Scope::kAssembly && k.value("INSTANCE").empty()) {
      // An assembly's own set: of its reference points, not the part's.
      assembly_sets_.insert(name);
      skip_data();
      return;
    }
    const auto [key, shown_name] = defined(name);
    Set& s = (elements ? elsets_ : nsets_).at(key, shown_name);
    s.internal = s.internal || k.has("INTERNAL");
    s.assembly = scope_ == Scope::kAssembly;
    if (!elements && !k.value("ELSET").empty()) s.element_sets.push_back(reference(k.value("ELSET")));
    const bool generate = k.has("GENERATE");
    std::string_view line;
    while (data_line(line)) {
      const auto e = entries(line);
      if (generate) {
        if (e.size() < 2 || e.size() > 3) fail("expected 'first, last[, step]' (GENERATE)");
        const Range r{number<int64_t>(e[0], "a number"), number<int64_t>(e[1], "a number"),
                      e.size() > 2 ? number<int64_t>(e[2], "a step") : 1};
        if (r.step < 1 || r.last < r.first) fail("GENERATE needs first <= last and a step of 1 or more");
        s.ranges.push_back(r);
        continue;
      }
      for (std::string_view entry : e) {
        int64_t id = 0;
        double real = 0;
        if (parse_whole(entry, id))
          s.numbers.push_back(id);
        else if (parse_whole(entry, real) && real == std::trunc(real) && std::abs(real) < 0x1p62)
          s.numbers.push_back(static_cast<int64_t>(real));  // (meshio writes "12.0")
        else if (!entry.empty())
          s.includes.push_back(reference(std::string(entry)));
      }
    }
  }

  void surface(const Keyword& k) {
    const std::string name = k.value("NAME");
    if (name.empty()) fail("*SURFACE without NAME=");
    const std::string type = upper(k.value("TYPE"));
    if (!type.empty() && type != "ELEMENT") {
      skipped_surfaces_.push_back(name + " (TYPE=" + k.value("TYPE") + ")");
      skip_data();
      return;
    }
    const std::string key = defined(name).first;
    auto [it, added] = surfaces_.try_emplace(key);
    if (added) surface_order_.push_back({key, defined(name).second});
    const std::string& shown_name =
        std::find_if(surface_order_.begin(), surface_order_.end(), [&](const auto& s) {
          return s.first == key;
        })->second;
    std::string_view line;
    while (data_line(line)) {
      const auto e = entries(line);
      if (e.empty() || e.size() > 2) fail("expected 'element or element set[, face]'");
      SurfaceLine s;
      int64_t id = 0;
      s.is_set = !parse_whole(e[0], id);
      s.element = s.is_set ? reference(std::string(e[0])) : std::string(e[0]);
      s.written = std::string(e[0]);
      s.where = here();
      const std::string face = e.size() > 1 ? upper(e[1]) : "";
      int f = 0;
      if (face == "SPOS" || face == "SNEG") {
        s.face = kSides;
      } else if (face.size() == 2 && face[0] == 'S' && parse_whole(std::string_view(face).substr(1), f) &&
                 f >= 1 && f <= 6) {
        s.face = f - 1;
      } else {
        // (No face: the elements' free faces; an edge of a 2D element.)
        ++unread_surface_lines_[shown_name];
        continue;
      }
      if (s.is_set) surface_sets_.insert(s.element);
      it->second.push_back(std::move(s));
    }
  }

  template <class Map>
  static std::vector<int64_t> sorted_keys(const Map& m) {
    std::vector<int64_t> out;
    out.reserve(m.size());
    for (const auto& [key, value] : m) out.push_back(key);
    std::sort(out.begin(), out.end());
    return out;
  }

  const std::vector<int64_t>& elements_of(const Set& s) const {
    return elsets_.resolved(s, defined_elements_, path_);
  }

  // `where`: "file:line" of the line that names it ("": the file's).
  const Element& element(int64_t id, const std::string& named_by, const std::string& where = "") const {
    const auto it = element_index_.find(id);
    if (it == element_index_.end())
      throw FormatError((where.empty() ? path_ : where) + ": " + named_by + " names element " +
                        std::to_string(id) + ", which the file does not define");
    return it->second;
  }

  // The chosen sets as labels 1..K of what their elements made (their
  // tetrahedra, or their 2D elements' triangles), the first set claiming an
  // item keeping it; returns the items two sets claimed.
  uint64_t label(const std::vector<const Set*>& family, bool solids, std::vector<int32_t>& labels,
                 std::map<int32_t, std::string>& names) const {
    uint64_t claimed_twice = 0;
    for (size_t k = 0; k < family.size(); ++k) {
      const auto label = static_cast<int32_t>(k + 1);
      names[label] = family[k]->name;
      for (int64_t id : elements_of(*family[k])) {
        const Element& e = element(id, "element set " + shown(family[k]->name));
        if (solids ? !is_solid(e.shape) : !is_face(e.shape)) continue;
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

  // The element sets that label the solids (or the 2D elements): the
  // part's sets of such elements only that no surface names and Abaqus/CAE
  // did not make for itself (a set of them all, such as CalculiX's Eall,
  // is not one when some set holds fewer), no two sharing one.
  std::vector<const Set*> family(bool solids) const {
    const uint64_t total = solids
                               ? element_count_[0] + element_count_[1] + element_count_[2] + element_count_[3]
                               : element_count_[4] + element_count_[5];
    std::vector<const Set*> sets;
    std::vector<uint64_t> sizes;
    for (const Set& s : elsets_.all()) {
      if (s.internal || s.assembly || surface_sets_.count(s.key)) continue;
      const auto& ids = elements_of(s);
      const bool fits = !ids.empty() && std::all_of(ids.begin(), ids.end(), [&](int64_t id) {
        const auto it = element_index_.find(id);
        return it != element_index_.end() &&
               (solids ? is_solid(it->second.shape) : is_face(it->second.shape));
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
      const auto& ids = elements_of(*s);
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
      for (const Section& section : sections_) {
        const Set* s = elsets_.find(section.key);
        if (!s)
          throw FormatError(section.where + ": a *SOLID SECTION names the element set " +
                            shown(section.name) + ", which the file does not define");
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
    for (const Set* s : chosen) used_sets_.insert(s);
  }

  void set_face_tags() {
    // The *SURFACE faces first, tagged 1..S, then the 2D elements, tagged by
    // their sets (0 in none).
    std::vector<std::array<uint32_t, 3>> faces;
    std::vector<int32_t> tags;
    int32_t tag = 0;
    for (const auto& [key, name] : surface_order_) {
      ++tag;
      out_.face_tag_names[tag] = name;
      for (const SurfaceLine& f : surfaces_.at(key)) {
        std::vector<int64_t> ids;
        if (f.is_set) {
          const Set* s = elsets_.find(f.element);
          if (!s)
            throw FormatError(f.where + ": *SURFACE " + shown(name) + " names the element set " +
                              shown(f.written) + ", which the file does not define");
          ids = elements_of(*s);
          used_sets_.insert(s);
        } else {
          ids.push_back(number<int64_t>(f.element, "an element number"));
        }
        for (int64_t id : ids) {
          const Element& e = element(id, "*SURFACE " + shown(name), f.where);
          const uint32_t* n = node_pool_.data() + e.nodes_at;
          if (f.face == kSides) {
            // A 2D element's side: its own triangles.
            if (!is_face(e.shape))
              throw FormatError(f.where + ": *SURFACE " + shown(name) + ": element " + std::to_string(id) +
                                " has no side SPOS or SNEG (not a 2D element)");
            for (uint32_t i = e.first; i < e.first + e.count; ++i)
              faces.push_back(face_triangles_[i]), tags.push_back(tag);
            continue;
          }
          const FaceSlots s = face_slots(e.shape, f.face);
          if (s.count == 0)
            throw FormatError(f.where + ": *SURFACE " + shown(name) + ": element " + std::to_string(id) +
                              " has no face S" + std::to_string(f.face + 1));
          if (s.count == 3) {
            faces.push_back({n[s.slots[0]], n[s.slots[1]], n[s.slots[2]]}), tags.push_back(tag);
          } else {
            for (const auto& half : split_quad({n[s.slots[0]], n[s.slots[1]], n[s.slots[2]], n[s.slots[3]]}))
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
      for (const Set* s : chosen) used_sets_.insert(s);
      for (const auto& [label, name] : names) out_.face_tag_names[label + tag] = name;
      for (size_t i = 0; i < face_triangles_.size(); ++i)
        faces.push_back(face_triangles_[i]), tags.push_back(labels[i] == 0 ? 0 : labels[i] + tag);
    }
    // A face tagged twice keeps its first tag.
    if (std::string note = add_tagged_faces_once(out_, faces, tags); !note.empty())
      notes_.push_back(std::move(note));
    if (!out_.tagged_faces.empty()) out_.face_tag_source = "surfaces and 2D elements' element sets";
  }

  // Each node set a 0/1 field, as many as a stream holds (32 fields, their
  // names within 64 bytes); the others named.
  void set_node_sets() {
    for (const Set& s : nsets_.all()) {
      const std::string name = kNodeSetFieldPrefix + s.name;
      if (out_.fields.size() >= 32 || name.size() > 64) {
        unkept_node_sets_.push_back(s.name);
        continue;
      }
      VertexField f;
      f.name = name;
      f.type = ScalarType::kUInt8;
      f.values.assign(out_.points.size(), 0.0);
      for (int64_t id : nsets_.resolved(s, defined_nodes_, path_)) {
        const auto it = node_index_.find(id);
        if (it == node_index_.end())
          throw FormatError(path_ + ": node set " + shown(s.name) + " names node " + std::to_string(id) +
                            ", which the file does not define");
        f.values[it->second] = 1;
      }
      // ELSET=: the nodes of its elements.
      for (const std::string& key : s.element_sets) {
        const Set* elements = elsets_.find(key);
        if (!elements)
          throw FormatError(path_ + ": node set " + shown(s.name) + " names the element set " + shown(key) +
                            ", which the file does not define");
        for (int64_t id : elements_of(*elements)) {
          const Element& e = element(id, "element set " + shown(elements->name));
          if (e.shape == Shape::kOther) ++other_element_nodes_;
          for (uint64_t i = e.nodes_at; i < e.nodes_at + e.nodes; ++i) f.values[node_pool_[i]] = 1;
        }
      }
      out_.fields.push_back(std::move(f));
    }
  }

  void note_left_out() {
    // (At most 8 names a list: Abaqus/CAE files hold hundreds of sets.)
    const auto joined = [](const auto& items) {
      std::string s;
      size_t n = 0;
      for (const auto& i : items) {
        if (n++ == 8) return s + " and " + std::to_string(std::size(items) - 8) + " more";
        s += (s.empty() ? "" : ", ") + shown(std::string(i));
      }
      return s;
    };
    std::vector<std::string> others;
    for (const auto& [type, count] : other_elements_) others.push_back(std::to_string(count) + " " + type);
    if (!others.empty())
      out_.left_out.push_back("elements other than solids and 2D elements (" + joined(others) + ")");
    if (assembly_nodes_)
      out_.left_out.push_back(std::to_string(assembly_nodes_) +
                              " nodes of the assembly (its reference points)");
    if (!assembly_sets_.empty())
      out_.left_out.push_back("the assembly's sets of its own nodes and elements (" + joined(assembly_sets_) +
                              ")");
    std::vector<std::string> sets;
    for (const Set& s : elsets_.all())
      if (!used_sets_.count(&s)) sets.push_back(s.name);
    if (!sets.empty())
      out_.left_out.push_back(
          "element sets " + joined(sets) + " (the stream keeps one region a tetrahedron and one tag a face" +
          (out_.region_names.empty() ? "" : "; the regions are " + joined(region_list())) + ")");
    if (!unkept_node_sets_.empty())
      out_.left_out.push_back("node sets " + joined(unkept_node_sets_) +
                              " (a stream holds 32 fields, each named in 64 bytes: nset:NAME)");
    if (other_element_nodes_)
      out_.left_out.push_back("the nodes of " + std::to_string(other_element_nodes_) +
                              " elements other than solids and 2D elements in node sets' ELSET=");
    if (!skipped_surfaces_.empty()) out_.left_out.push_back("surfaces " + joined(skipped_surfaces_));
    for (const auto& [surface, lines] : unread_surface_lines_)
      out_.left_out.push_back(
          "surface " + surface + ": " + std::to_string(lines) +
          " lines without a solid's face S1..S6 or a 2D element's side (free faces, edges)");
    std::vector<std::string> materials;
    for (const Section& s : sections_)
      if (!s.material.empty()) materials.push_back(s.name + ": " + s.material);
    if (!materials.empty())
      out_.left_out.push_back("the solid sections' materials (" + joined(materials) + ")");
    if (node_normals_) out_.left_out.push_back("the normals of " + std::to_string(node_normals_) + " nodes");
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

  std::string path_;
  std::deque<Source> sources_;  // every file opened, kept while lines point into them
  std::vector<size_t> stack_;   // the open ones, innermost last
  const Source* where_ = nullptr;
  std::string_view last_;
  bool again_ = false;
  Scope scope_ = Scope::kModel;
  int parts_ = 0, instances_ = 0;
  std::unordered_map<int64_t, uint32_t> node_index_;
  std::unordered_map<int64_t, Element> element_index_;
  std::vector<int64_t> defined_nodes_, defined_elements_;  // their numbers, ascending
  std::array<uint64_t, 7> element_count_{};
  std::vector<uint32_t> node_pool_;
  std::vector<std::array<uint32_t, 3>> face_triangles_;
  std::map<size_t, uint64_t> split_;
  std::map<std::string, uint64_t> other_elements_, unread_surface_lines_;
  uint64_t assembly_nodes_ = 0, node_normals_ = 0, other_element_nodes_ = 0;
  Sets elsets_, nsets_;
  std::vector<Section> sections_;
  std::map<std::string, std::vector<SurfaceLine>> surfaces_;        // by key
  std::vector<std::pair<std::string, std::string>> surface_order_;  // (key, name)
  std::vector<std::string> skipped_surfaces_, unkept_node_sets_, notes_;
  std::set<std::string> skipped_keywords_, surface_sets_, assembly_sets_;
  std::set<const Set*> used_sets_;
  InputMesh out_;
};

}  // namespace

InputMesh read_abaqus(const std::string& path) { return AbaqusReader(path).read(); }

}  // namespace dtm
