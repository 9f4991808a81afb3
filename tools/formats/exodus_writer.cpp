// The Exodus II writer (exodus.h): libexodusii writes a file, whose bytes
// render_exodus() returns (the tools write their outputs whole, or not).
#include <exodusII.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <set>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "abaqus.h"  // kNodeSetFieldPrefix, is_node_set_field
#include "common/utf8.h"
#include "exodus.h"
#include "exodus_file.h"
#include "face_sides.h"
#include "render_util.h"

namespace dtm {
namespace {

// A temporary file that removes itself.
struct TemporaryFile {
  std::string path;
  TemporaryFile() {
    std::string pattern = (std::filesystem::temp_directory_path() / "meshdec-exodus-XXXXXX").string();
    const int fd = mkstemp(pattern.data());
    if (fd < 0) throw std::runtime_error("cannot make a temporary file in " + pattern);
    ::close(fd);
    path = pattern;
  }
  ~TemporaryFile() {
    std::error_code ignored;
    std::filesystem::remove(path, ignored);
  }
  std::string bytes() const {
    std::ifstream in(path, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
  }
};

// Names as libexodusii takes them.
struct Names {
  std::vector<std::string> names;
  std::vector<char*> pointers() {
    std::vector<char*> out;
    for (std::string& n : names) out.push_back(n.data());
    return out;
  }
};

// An element block: a region's cells of one kind (linear, or with edge nodes).
struct OutBlock {
  int32_t label = 0;  // the region's
  int64_t id = 0;
  std::string name;
  bool second_order = false;
  std::vector<uint32_t> cells;
};

std::vector<std::string> component_names(const OutputField& f) {
  if (f.components == 1) return {f.name};
  std::vector<std::string> out;
  out.reserve(static_cast<size_t>(f.components));
  for (int c = 0; c < f.components; ++c)
    out.push_back(f.name + "_" + (f.components == 3 ? std::string(1, "xyz"[c]) : std::to_string(c + 1)));
  return out;
}

// The blocks: by region, the linear cells apart from the second-order
// ones (a block holds one kind of element), each with its id.
std::vector<OutBlock> exodus_blocks(const OutputMesh& m) {
  std::map<std::pair<int32_t, bool>, std::vector<uint32_t>> grouped;
  for (uint32_t c = 0; c < m.cells.size(); ++c)
    grouped[{m.region.empty() ? 1 : m.region[c], cell_nodes(m, c, kVtkEdgeSlots).second_order()}].push_back(
        c);
  std::vector<OutBlock> blocks;
  std::vector<int64_t> labels;
  for (auto& [key, cells] : grouped) {
    OutBlock& b = blocks.emplace_back();
    b.label = key.first;
    b.second_order = key.second;
    b.cells = std::move(cells);
    labels.push_back(key.first);
    const auto name = m.region_names.find(key.first);
    if (name != m.region_names.end()) b.name = name->second;
  }
  const std::vector<int64_t> ids = exodus_ids(labels);
  for (size_t b = 0; b < blocks.size(); ++b) blocks[b].id = ids[b];
  return blocks;
}

// The side sets' tags, in order, and their ids.
std::vector<std::pair<int32_t, int64_t>> side_set_ids(const OutputMesh& m) {
  std::set<int32_t> tags(m.face_tags.begin(), m.face_tags.end());
  const std::vector<int64_t> ids = exodus_ids(std::vector<int64_t>(tags.begin(), tags.end()));
  std::vector<std::pair<int32_t, int64_t>> out;
  out.reserve(tags.size());
  size_t k = 0;
  for (int32_t tag : tags) out.emplace_back(tag, ids[k++]);
  return out;
}

// The names the file gives its blocks, side sets and node sets, in that
// order, as wanted_names() lists them: ParaView's Exodus reader (IOSS)
// refuses a file where two of them share a name, over all the kinds, and
// Netgen gives several face numbers one boundary name, gmsh a volume and a
// surface one name. The first keeps it, each later one gets "_2", "_3", ...;
// an empty name (the set's id names it) stays empty; each at most
// kWrittenNameLength bytes, cut on a UTF-8 boundary.
struct NamedItem {
  std::string kind;  // "element block 3", "side set 2", ...
  std::string name;
};
std::vector<std::string> unique_exodus_names(const std::vector<NamedItem>& wanted) {
  std::set<std::string> used;
  for (const NamedItem& w : wanted) used.insert(utf8_prefix(w.name, exodus::kWrittenNameLength));
  std::set<std::string> given;
  std::vector<std::string> out;
  for (const NamedItem& w : wanted) {
    std::string name = utf8_prefix(w.name, exodus::kWrittenNameLength);
    if (!name.empty() && !given.insert(name).second) {
      for (int k = 2;; ++k) {
        const std::string suffix = "_" + std::to_string(k);
        const std::string candidate = utf8_prefix(name, exodus::kWrittenNameLength - suffix.size()) + suffix;
        if (!used.count(candidate) && given.insert(candidate).second) {
          name = candidate;
          break;
        }
      }
    }
    out.push_back(name);
  }
  return out;
}

// Every block's, side set's and node set's wanted name (node sets: the
// fields kept as them; one named by a number has it as its id), in the
// file's order.
std::vector<NamedItem> wanted_names(const OutputMesh& m, const std::vector<OutBlock>& blocks) {
  std::vector<NamedItem> out;
  out.reserve(blocks.size() + m.face_tag_names.size() + m.fields.size());
  for (const OutBlock& b : blocks) out.push_back({"element block " + std::to_string(b.id), b.name});
  for (const auto& [tag, set] : side_set_ids(m)) {
    const auto name = m.face_tag_names.find(tag);
    out.push_back({"side set " + std::to_string(set), name != m.face_tag_names.end() ? name->second : ""});
  }
  for (const OutputField& f : m.fields)
    if (is_node_set_field(f)) {
      const std::string name = f.name.substr(std::string(kNodeSetFieldPrefix).size());
      const bool number =
          !name.empty() && name.size() < 10 && std::all_of(name.begin(), name.end(), ::isdigit);
      out.push_back({"node set " + name, number ? "" : name});
    }
  return out;
}

}  // namespace

std::vector<int64_t> exodus_ids(const std::vector<int64_t>& labels) {
  std::set<int64_t> used;
  std::vector<int64_t> out;
  out.reserve(labels.size());
  for (int64_t l : labels) out.push_back(l > 0 && used.insert(l).second ? l : 0);
  int64_t next = 1;
  for (int64_t& id : out)
    if (id == 0) {
      while (used.count(next)) ++next;
      used.insert(next);
      id = next;
    }
  return out;
}

std::string render_exodus(const OutputMesh& m) {
  TemporaryFile temporary;
  exodus::File file = exodus::File::create(temporary.path);
  const int id = file.id();
  std::vector<OutBlock> blocks = exodus_blocks(m);
  // The names, as wanted_names() orders them: the blocks', then the side
  // sets' by tag, then the node sets'.
  const std::vector<std::string> names = unique_exodus_names(wanted_names(m, blocks));
  std::map<int32_t, std::string> side_set_name;
  size_t node_set_name = blocks.size();
  for (const auto& [tag, set] : side_set_ids(m)) side_set_name[tag] = names[node_set_name++];
  // Each cell's element number (1-based, block after block).
  std::vector<int64_t> element_of(m.cells.size());
  int64_t next = 1;
  for (const OutBlock& b : blocks)
    for (uint32_t c : b.cells) element_of[c] = next++;
  // Side sets: a face tag's faces, each as its cell's side.
  std::map<int32_t, std::pair<std::vector<int64_t>, std::vector<int64_t>>> side_sets;
  if (!m.faces.empty()) {
    const std::vector<CellSide> sides = tagged_face_sides(m, [&](uint32_t c, uint8_t s) {
      const exodus::Side side = exodus::side_of(exodus::Shape::kTetrahedron, s + 1);
      const auto& t = m.cells[c];
      return std::array<uint32_t, 3>{t[static_cast<size_t>(side.slots[0])],
                                     t[static_cast<size_t>(side.slots[1])],
                                     t[static_cast<size_t>(side.slots[2])]};
    });
    for (size_t f = 0; f < m.faces.size(); ++f) {
      if (sides[f].cell == CellSide::kNoCell) continue;
      auto& [elements, numbers] = side_sets[m.face_tags[f]];
      elements.push_back(element_of[sides[f].cell]);
      numbers.push_back(sides[f].side + 1);
    }
  }
  // Node sets: the node set fields; the other fields nodal variables.
  std::vector<const OutputField*> node_sets, nodal;
  for (const OutputField& f : m.fields) (is_node_set_field(f) ? node_sets : nodal).push_back(&f);

  ex_init_params p{};
  std::snprintf(p.title, sizeof p.title, "%s", "written by meshdec");
  p.num_dim = 3;
  p.num_nodes = static_cast<int64_t>(m.points.size());
  p.num_elem = static_cast<int64_t>(m.cells.size());
  p.num_elem_blk = static_cast<int64_t>(blocks.size());
  p.num_side_sets = static_cast<int64_t>(side_sets.size());
  p.num_node_sets = static_cast<int64_t>(node_sets.size());
  file.check(ex_put_init_ext(id, &p), "its sizes");

  std::vector<double> x(m.points.size()), y(x.size()), z(x.size());
  for (size_t i = 0; i < m.points.size(); ++i) {
    const InputPoint q = m.grid.to_input(m.points[i]);
    x[i] = q.x, y[i] = q.y, z[i] = q.z;
  }
  file.check(ex_put_coord(id, x.data(), y.data(), z.data()), "the nodes");
  // The input's node ids (22.0, --keep-order) as the node number map
  // (render_mesh() refuses ids past its 32 bits, naming the file).
  if (!m.node_labels.empty()) {
    file.check(ex_put_id_map(id, EX_NODE_MAP, m.node_labels.data()), "the node ids");
  }
  Names axes{{"x", "y", "z"}};
  file.check(ex_put_coord_names(id, axes.pointers().data()), "the axes' names");

  Names block_names;
  for (const OutBlock& b : blocks) {
    const int64_t per = b.second_order ? 10 : 4;
    file.check(ex_put_block(id, EX_ELEM_BLOCK, b.id, b.second_order ? "TETRA10" : "TETRA",
                            static_cast<int64_t>(b.cells.size()), per, 0, 0, 0),
               "element block " + std::to_string(b.id));
    std::vector<int64_t> conn;
    conn.reserve(b.cells.size() * static_cast<size_t>(per));
    for (uint32_t c : b.cells) {
      const ListedNodes n = cell_nodes(m, c, kVtkEdgeSlots);  // (Exodus's order is VTK's)
      for (size_t k = 0; k < n.count; ++k) conn.push_back(int64_t{n.nodes[k]} + 1);
    }
    file.check(ex_put_conn(id, EX_ELEM_BLOCK, b.id, conn.data(), nullptr, nullptr),
               "element block " + std::to_string(b.id) + "'s connectivity");
    block_names.names.push_back(names[block_names.names.size()]);  // (the blocks come first)
  }
  if (!blocks.empty())
    file.check(ex_put_names(id, EX_ELEM_BLOCK, block_names.pointers().data()), "the blocks' names");

  // Side sets, by tag.
  std::map<int32_t, int64_t> set_id;
  for (const auto& [tag, set] : side_set_ids(m)) set_id[tag] = set;
  Names set_names;
  for (const auto& [tag, sides] : side_sets) {
    const int64_t set = set_id.at(tag);
    file.check(ex_put_set_param(id, EX_SIDE_SET, set, static_cast<int64_t>(sides.first.size()), 0),
               "side set " + std::to_string(set));
    file.check(ex_put_set(id, EX_SIDE_SET, set, sides.first.data(), sides.second.data()),
               "side set " + std::to_string(set));
    set_names.names.push_back(side_set_name.at(tag));
  }
  if (!side_sets.empty())
    file.check(ex_put_names(id, EX_SIDE_SET, set_names.pointers().data()), "the side sets' names");

  // Node sets: a set named by a number keeps it as its id (the reader's
  // name for an unnamed set).
  std::vector<int64_t> node_labels;
  std::vector<std::string> node_set_names;
  for (const OutputField* f : node_sets) {
    const std::string name = f->name.substr(std::string(kNodeSetFieldPrefix).size());
    const bool number = !name.empty() && name.size() < 10 && std::all_of(name.begin(), name.end(), ::isdigit);
    node_labels.push_back(number ? std::stoll(name) : 0);
    node_set_names.push_back(names[node_set_name++]);
  }
  const std::vector<int64_t> node_set_ids = exodus_ids(node_labels);
  for (size_t k = 0; k < node_sets.size(); ++k) {
    std::vector<int64_t> nodes;
    for (size_t i = 0; i < node_sets[k]->bits.size(); ++i)
      if (node_sets[k]->bits[i] != 0) nodes.push_back(static_cast<int64_t>(i + 1));
    file.check(ex_put_set_param(id, EX_NODE_SET, node_set_ids[k], static_cast<int64_t>(nodes.size()), 0),
               "node set " + std::to_string(node_set_ids[k]));
    file.check(ex_put_set(id, EX_NODE_SET, node_set_ids[k], nodes.data(), nullptr),
               "node set " + std::to_string(node_set_ids[k]));
  }
  if (!node_sets.empty()) {
    Names n{node_set_names};
    file.check(ex_put_names(id, EX_NODE_SET, n.pointers().data()), "the node sets' names");
  }

  // Variables at one time step: meshdec's level and boundary (as in a
  // .vtu), then the fields.
  std::vector<std::pair<std::string, std::vector<double>>> derived;
  if (!m.level.empty()) derived.emplace_back("level", std::vector<double>(m.level.begin(), m.level.end()));
  if (!m.boundary.empty())
    derived.emplace_back("boundary", std::vector<double>(m.boundary.begin(), m.boundary.end()));
  Names nodal_names, element_names;
  for (const auto& [name, values] : derived) nodal_names.names.push_back(name);
  for (const OutputField* f : nodal)
    for (const std::string& n : component_names(*f)) nodal_names.names.push_back(n);
  for (const OutputField& f : m.cell_fields)
    for (const std::string& n : component_names(f)) element_names.names.push_back(n);
  // (Every variable defined before any value is written: libexodusii
  // writes without fill, and a definition after the values would move them
  // and leave stale bytes in the names.)
  const int nodal_count = static_cast<int>(nodal_names.names.size());
  const int element_count = static_cast<int>(element_names.names.size());
  if (nodal_count > 0) {
    file.check(ex_put_variable_param(id, EX_NODAL, nodal_count), "the nodal variables");
    file.check(ex_put_variable_names(id, EX_NODAL, nodal_count, nodal_names.pointers().data()),
               "the nodal variables' names");
  }
  if (element_count > 0) {
    file.check(ex_put_variable_param(id, EX_ELEM_BLOCK, element_count), "the element variables");
    file.check(ex_put_variable_names(id, EX_ELEM_BLOCK, element_count, element_names.pointers().data()),
               "the element variables' names");
    std::vector<int> truth(blocks.size() * static_cast<size_t>(element_count), 1);
    file.check(
        ex_put_truth_table(id, EX_ELEM_BLOCK, static_cast<int>(blocks.size()), element_count, truth.data()),
        "the element variables' truth table");
  }
  if (nodal_count + element_count > 0) {
    const double time = 0;
    file.check(ex_put_time(id, 1, &time), "the time step");
  }
  int index = 1;
  for (const auto& [name, values] : derived)
    file.check(ex_put_var(id, 1, EX_NODAL, index++, 1, static_cast<int64_t>(values.size()), values.data()),
               "nodal variable '" + name + "'");
  std::vector<double> v(m.points.size());
  for (const OutputField* f : nodal)
    for (int c = 0; c < f->components; ++c, ++index) {
      for (size_t i = 0; i < v.size(); ++i)
        v[i] =
            scalar_value(f->bits[i * static_cast<size_t>(f->components) + static_cast<size_t>(c)], f->type);
      file.check(ex_put_var(id, 1, EX_NODAL, index, 1, static_cast<int64_t>(v.size()), v.data()),
                 "nodal variable '" + f->name + "'");
    }
  for (const OutBlock& b : blocks) {
    int k = 1;
    std::vector<double> w(b.cells.size());
    for (const OutputField& f : m.cell_fields)
      for (int c = 0; c < f.components; ++c, ++k) {
        for (size_t i = 0; i < w.size(); ++i)
          w[i] = scalar_value(
              f.bits[size_t{b.cells[i]} * static_cast<size_t>(f.components) + static_cast<size_t>(c)],
              f.type);
        file.check(ex_put_var(id, 1, EX_ELEM_BLOCK, k, b.id, static_cast<int64_t>(w.size()), w.data()),
                   "element variable '" + f.name + "'");
      }
  }
  file.close();
  return temporary.bytes();
}

std::vector<std::string> exodus_renumbering(const OutputMesh& m) {
  std::vector<std::string> out;
  std::map<int32_t, std::vector<int64_t>> ids_of_region;
  for (const OutBlock& b : exodus_blocks(m)) ids_of_region[b.label].push_back(b.id);
  for (const auto& [label, ids] : ids_of_region) {
    if (m.region.empty()) break;
    if (ids.size() == 1 && ids[0] == label) continue;
    std::string blocks;
    for (int64_t id : ids) blocks += (blocks.empty() ? "" : " and ") + std::to_string(id);
    out.push_back(
        "region " + std::to_string(label) + " as element block" + (ids.size() > 1 ? "s " : " ") + blocks +
        (ids.size() > 1 ? " (its linear and its second-order cells)" : " (Exodus ids are positive)"));
  }
  for (const auto& [tag, id] : side_set_ids(m))
    if (id != tag)
      out.push_back("face tag " + std::to_string(tag) + " as side set " + std::to_string(id) +
                    " (Exodus ids are positive)");
  // (Names cut to 64 bytes are said where the stream is read: a name holds 64.)
  const std::vector<NamedItem> wanted = wanted_names(m, exodus_blocks(m));
  const std::vector<std::string> given = unique_exodus_names(wanted);
  for (size_t k = 0; k < wanted.size(); ++k)
    if (given[k] != wanted[k].name && wanted[k].name.size() <= exodus::kWrittenNameLength)
      out.push_back(wanted[k].kind + "'s name \"" + wanted[k].name + "\" as \"" + given[k] +
                    "\" (a name is unique over an Exodus file's blocks and sets: ParaView refuses the file "
                    "otherwise)");
  return out;
}

}  // namespace dtm
