#include "gmsh.h"

#include <algorithm>
#include <charconv>
#include <unordered_map>

#include "render_util.h"
#include "text_cursor.h"

namespace dtm {
namespace {

constexpr int kGmshTetrahedron = 4;

// Whitespace-separated fields of one line.
std::vector<std::string_view> split(std::string_view line) {
  std::vector<std::string_view> out;
  size_t p = 0;
  while (true) {
    p = line.find_first_not_of(" \t\r", p);
    if (p == std::string_view::npos) return out;
    const size_t e = line.find_first_of(" \t\r", p);
    out.push_back(line.substr(p, e == std::string_view::npos ? e : e - p));
    if (e == std::string_view::npos) return out;
    p = e;
  }
}

class GmshReader {
 public:
  explicit GmshReader(const std::string& path) : c_(TextCursor::open(path)) {}

  InputMesh read() {
    if (c_.at_end()) c_.fail("empty file, expected '$MeshFormat'");
    c_.expect("$MeshFormat");
    const std::string version(c_.token("a version"));
    if (version != "2.2" && version != "4.1")
      c_.fail("unsupported version " + version + " (2.2 and 4.1 are read)");
    v4_ = version == "4.1";
    if (c_.number<int>("the file type (0 = ASCII)") != 0) c_.fail("unsupported: binary .msh (save as ASCII)");
    if (const int size = c_.number<int>("the data size"); size != 8)
      c_.fail("data size must be 8, got " + std::to_string(size));
    c_.expect("$EndMeshFormat");
    bool have_nodes = false;
    while (!c_.at_end()) {
      const std::string section(c_.token("a section"));
      if (section.size() < 2 || section[0] != '$') c_.fail("expected a $Section, found '" + section + "'");
      if (section == "$Nodes") {
        if (have_nodes) c_.fail("a second $Nodes section");
        have_nodes = true;
        v4_ ? nodes_v4() : nodes_v2();
      } else if (section == "$Elements") {
        if (!have_nodes) c_.fail("$Elements before $Nodes");
        v4_ ? elements_v4() : elements_v2();
      } else if (section == "$NodeData") {
        if (!have_nodes) c_.fail("$NodeData before $Nodes");
        node_data();
      } else {
        skip_section(section.substr(1));
        continue;
      }
      c_.expect("$End" + section.substr(1));
    }
    if (!have_nodes) throw FormatError(c_.path() + ": no $Nodes section");
    return std::move(out_);
  }

 private:
  void skip_section(const std::string& name) {
    const std::string end = "$End" + name;
    while (true) {
      if (c_.at_end()) c_.fail("file ends inside $" + name);
      if (c_.token("a line") == end) return;
    }
  }

  void add_node(int64_t tag, size_t index) {
    if (!index_of_.emplace(tag, static_cast<uint32_t>(index)).second)
      c_.fail("node tag " + std::to_string(tag) + " defined twice");
  }

  void nodes_v2() {
    const uint64_t n = c_.count("a node count", c_.remaining() / 8);
    out_.points.reserve(n);
    for (uint64_t i = 0; i < n; ++i) {
      add_node(c_.number<int64_t>("a node tag"), out_.points.size());
      const double x = c_.coordinate(), y = c_.coordinate(), z = c_.coordinate();
      out_.points.push_back({x, y, z});
    }
  }

  void nodes_v4() {
    const uint64_t blocks = c_.count("a block count", c_.remaining() / 8);
    const uint64_t n = c_.count("a node count", c_.remaining() / 8);
    c_.number<int64_t>("the smallest node tag");
    c_.number<int64_t>("the largest node tag");
    out_.points.reserve(n);
    for (uint64_t b = 0; b < blocks; ++b) {
      const int dim = c_.number<int>("an entity dimension");
      c_.number<int>("an entity tag");
      const int parametric = c_.number<int>("0 or 1 (parametric)");
      const uint64_t in_block = c_.count("a node count", c_.remaining() / 8);
      if (dim < 0 || dim > 3 || parametric < 0 || parametric > 1) c_.fail("bad node block header");
      const size_t first = out_.points.size();
      for (uint64_t i = 0; i < in_block; ++i) add_node(c_.number<int64_t>("a node tag"), first + i);
      for (uint64_t i = 0; i < in_block; ++i) {
        const double x = c_.coordinate(), y = c_.coordinate(), z = c_.coordinate();
        out_.points.push_back({x, y, z});
        for (int k = 0; k < dim * parametric; ++k) c_.coordinate();
      }
      if (out_.points.size() - first != in_block) c_.fail("node block size mismatch");
    }
    if (out_.points.size() != n)
      c_.fail("$Nodes announces " + std::to_string(n) + " nodes, its blocks hold " +
              std::to_string(out_.points.size()));
  }

  uint32_t node(std::string_view tag_text) {
    int64_t tag = 0;
    const auto [end, ec] = std::from_chars(tag_text.data(), tag_text.data() + tag_text.size(), tag);
    if (ec != std::errc() || end != tag_text.data() + tag_text.size())
      c_.fail("expected a node tag, found '" + std::string(tag_text) + "'");
    const auto it = index_of_.find(tag);
    if (it == index_of_.end()) c_.fail("node tag " + std::to_string(tag) + " out of range (no such node)");
    return it->second;
  }

  // One element's node tags (the fields after `skip` leading ones).
  void element(const std::vector<std::string_view>& f, size_t skip, int type) {
    if (f.size() <= skip) c_.fail("element without nodes");
    std::array<uint32_t, 4> t{};
    for (size_t k = skip; k < f.size(); ++k) {
      const uint32_t v = node(f[k]);
      if (k - skip < 4) t[k - skip] = v;
    }
    if (type == kGmshTetrahedron) {
      if (f.size() - skip != 4) c_.fail("a tetrahedron with " + std::to_string(f.size() - skip) + " nodes");
      out_.tets.push_back(t);
    }
  }

  void elements_v2() {
    const uint64_t n = c_.count("an element count", c_.remaining() / 8);
    c_.skip_to_next_line();
    for (uint64_t i = 0; i < n; ++i) {
      const auto f = split(c_.rest_of_line());
      if (f.empty())
        c_.fail("file ends after " + std::to_string(i) + " of " + std::to_string(n) + " elements");
      if (f.size() < 3) c_.fail("expected 'tag type ntags ...'");
      int type = 0, tags = 0;
      std::from_chars(f[1].data(), f[1].data() + f[1].size(), type);
      const auto [end, ec] = std::from_chars(f[2].data(), f[2].data() + f[2].size(), tags);
      if (ec != std::errc() || tags < 0 || f.size() < 3 + static_cast<size_t>(tags))
        c_.fail("bad element tag count");
      element(f, 3 + tags, type);
    }
  }

  void elements_v4() {
    const uint64_t blocks = c_.count("a block count", c_.remaining() / 8);
    const uint64_t n = c_.count("an element count", c_.remaining() / 8);
    c_.number<int64_t>("the smallest element tag");
    c_.number<int64_t>("the largest element tag");
    uint64_t seen = 0;
    for (uint64_t b = 0; b < blocks; ++b) {
      c_.number<int>("an entity dimension");
      c_.number<int>("an entity tag");
      const int type = c_.number<int>("an element type");
      const uint64_t in_block = c_.count("an element count", c_.remaining() / 4);
      c_.skip_to_next_line();
      for (uint64_t i = 0; i < in_block; ++i) {
        const auto f = split(c_.rest_of_line());
        if (f.empty()) c_.fail("file ends or blank line inside an element block");
        element(f, 1, type);
      }
      seen += in_block;
    }
    if (seen != n)
      c_.fail("$Elements announces " + std::to_string(n) + " elements, its blocks hold " +
              std::to_string(seen));
  }

  // A view's values at the nodes: kept when it covers every node once.
  void node_data() {
    VertexField f;
    const int strings = c_.number<int>("a string tag count");
    for (int i = 0; i < strings; ++i) {
      std::string s(c_.token("a string tag"));
      if (i == 0)
        f.name = s.size() >= 2 && s.front() == '"' && s.back() == '"' ? s.substr(1, s.size() - 2) : s;
    }
    const int reals = c_.number<int>("a real tag count");
    for (int i = 0; i < reals; ++i) c_.number<double>("a real tag");
    const int ints = c_.number<int>("an integer tag count");
    if (ints < 3) c_.fail("$NodeData needs 3 integer tags (step, components, entries)");
    c_.number<int64_t>("a time step");
    f.components = c_.number<int>("a component count");
    const uint64_t entries = c_.count("an entry count", c_.remaining() / 4);
    for (int i = 3; i < ints; ++i) c_.number<int64_t>("an integer tag");
    if (f.components < 1 || f.components > 9) c_.fail("bad component count");
    f.values.assign(out_.points.size() * f.components, 0.0);
    std::vector<uint8_t> seen(out_.points.size(), 0);
    uint64_t distinct = 0;
    for (uint64_t e = 0; e < entries; ++e) {
      const std::string_view tag = c_.token("a node tag");
      const uint32_t v = node(tag);
      distinct += !seen[v];
      seen[v] = 1;
      for (int k = 0; k < f.components; ++k) f.values[v * f.components + k] = c_.number<double>("a value");
    }
    if (distinct == out_.points.size()) out_.fields.push_back(std::move(f));
  }

  TextCursor c_;
  bool v4_ = false;
  std::unordered_map<int64_t, uint32_t> index_of_;
  InputMesh out_;
};

}  // namespace

InputMesh read_gmsh(const std::string& path) { return GmshReader(path).read(); }

std::string render_gmsh(const OutputMesh& m) {
  const size_t n = m.points.size(), t = m.cells.size();
  std::string out = "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n";
  InputPoint lo{0, 0, 0}, hi{0, 0, 0};
  std::vector<InputPoint> xyz;
  xyz.reserve(n);
  for (const GridPoint& g : m.points) xyz.push_back(m.grid.to_input(g));
  if (n > 0) {
    lo = hi = xyz[0];
    for (const InputPoint& p : xyz) {
      lo = {std::min(lo.x, p.x), std::min(lo.y, p.y), std::min(lo.z, p.z)};
      hi = {std::max(hi.x, p.x), std::max(hi.y, p.y), std::max(hi.z, p.z)};
    }
  }
  // One volume entity (tag 1) holds every node and tetrahedron.
  out += "$Entities\n0 0 0 1\n1";
  for (double v : {lo.x, lo.y, lo.z, hi.x, hi.y, hi.z}) {
    out += ' ';
    append_number(out, v);
  }
  out += " 0 0\n$EndEntities\n$Nodes\n";
  out += "1 " + std::to_string(n) + " " + std::to_string(n ? 1 : 0) + " " + std::to_string(n) + "\n";
  out += "3 1 0 " + std::to_string(n) + "\n";
  for (size_t i = 0; i < n; ++i) {
    append_number(out, i + 1);
    out += '\n';
  }
  for (const InputPoint& p : xyz) {
    append_xyz_line(out, p);
  }
  out += "$EndNodes\n$Elements\n";
  out += "1 " + std::to_string(t) + " " + std::to_string(t ? 1 : 0) + " " + std::to_string(t) + "\n";
  out += "3 1 4 " + std::to_string(t) + "\n";
  for (size_t c = 0; c < t; ++c) {
    append_number(out, c + 1);
    for (uint32_t v : m.cells[c]) {
      out += ' ';
      append_number(out, uint64_t{v} + 1);
    }
    out += '\n';
  }
  out += "$EndElements\n";
  auto node_data = [&](const char* name, const auto& values) {
    if (values.empty()) return;
    out += "$NodeData\n1\n\"" + std::string(name) + "\"\n1\n0\n3\n0\n1\n" + std::to_string(n) + "\n";
    for (size_t i = 0; i < n; ++i) {
      append_number(out, i + 1);
      out += ' ';
      append_number(out, values[i]);
      out += '\n';
    }
    out += "$EndNodeData\n";
  };
  node_data("level", m.level);
  node_data("boundary", m.boundary);
  // $NodeData holds 1, 3 or 9 components (scalar, vector, tensor).
  for (const OutputField& f : m.fields) {
    if (f.components != 1 && f.components != 3 && f.components != 9) continue;
    out += "$NodeData\n1\n\"" + f.name + "\"\n1\n0\n3\n0\n" + std::to_string(f.components) + "\n" +
           std::to_string(n) + "\n";
    for (size_t i = 0; i < n; ++i) {
      append_number(out, i + 1);
      for (int c = 0; c < f.components; ++c) {
        out += ' ';
        append_scalar_text(out, f.bits[i * f.components + c], f.type);
      }
      out += '\n';
    }
    out += "$EndNodeData\n";
  }
  return out;
}

}  // namespace dtm
