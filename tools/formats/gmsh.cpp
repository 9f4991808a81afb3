#include "gmsh.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstring>
#include <exception>
#include <map>
#include <set>
#include <unordered_map>

#include "cell_split.h"
#include "common/parallel_for.h"
#include "common/release.h"
#include "node_labels.h"
#include "render_util.h"
#include "second_order.h"
#include "text_cursor.h"

namespace dtm {
namespace {

constexpr int kGmshTriangle = 2;
constexpr int kGmshTetrahedron = 4;
constexpr int kGmshTriangle6 = 9;
constexpr int kGmshTetrahedron10 = 11;
constexpr int kGmshQuadrangle = 3;
constexpr int kGmshHexahedron = 5;
constexpr int kGmshPrism = 6;
constexpr int kGmshPyramid = 7;

// gmsh's hexahedra, prisms, pyramids and quadrangles, linear and of second
// order (their corners first): type, nodes, corners.
struct CellType {
  int type;
  size_t nodes, corners;
};
constexpr std::array<CellType, 12> kSplitTypes = {{{kGmshHexahedron, 8, 8},
                                                   {17, 20, 8},
                                                   {12, 27, 8},
                                                   {kGmshPrism, 6, 6},
                                                   {18, 15, 6},
                                                   {13, 18, 6},
                                                   {kGmshPyramid, 5, 5},
                                                   {19, 13, 5},
                                                   {14, 14, 5},
                                                   {kGmshQuadrangle, 4, 4},
                                                   {16, 8, 4},
                                                   {10, 9, 4}}};
const CellType* split_type(int type) {
  for (const CellType& t : kSplitTypes)
    if (t.type == type) return &t;
  return nullptr;
}

// The volume elements read (hexahedra, prisms and pyramids as the
// tetrahedra that split them: cell_split.h), and the faces (a
// quadrangle as two triangles).
bool is_split_cell(int type) { return split_type(type) && split_type(type)->corners > 4; }
bool is_quadrangle(int type) { return split_type(type) && split_type(type)->corners == 4; }
bool is_tetrahedron(int type) {
  return type == kGmshTetrahedron || type == kGmshTetrahedron10 || is_split_cell(type);
}
bool is_triangle(int type) { return type == kGmshTriangle || type == kGmshTriangle6 || is_quadrangle(type); }
// The nodes gmsh gives an element of a type read here.
size_t kept_element_nodes(int type) {
  if (const CellType* t = split_type(type)) return t->nodes;
  switch (type) {
    case kGmshTetrahedron:
      return 4;
    case kGmshTetrahedron10:
      return 10;
    case kGmshTriangle:
      return 3;
    default:
      return 6;  // kGmshTriangle6
  }
}
// gmsh's 10-node tetrahedron numbers its edge nodes 4 (0,1), 5 (1,2),
// 6 (0,2), 7 (0,3), 8 (2,3), 9 (1,3): theirs in kTetEdges' order.
constexpr std::array<int, 6> kGmshTetEdgeNodes = {4, 6, 7, 5, 9, 8};
// One element of a type read here, in words.
const char* element_kind(int type) {
  if (const CellType* t = split_type(type); t && t->nodes > t->corners)
    return t->corners == 8   ? "second-order hexahedron"
           : t->corners == 6 ? "second-order prism"
           : t->corners == 5 ? "second-order pyramid"
                             : "second-order quadrangle";
  switch (type) {
    case kGmshTetrahedron:
      return "tetrahedron";
    case kGmshTetrahedron10:
      return "10-node tetrahedron";
    case kGmshTriangle:
      return "triangle";
    case kGmshQuadrangle:
      return "quadrangle";
    case kGmshHexahedron:
      return "hexahedron";
    case kGmshPrism:
      return "prism";
    case kGmshPyramid:
      return "pyramid";
    default:
      return "6-node triangle";
  }
}
// An element's nodes as read (up to a 10-node tetrahedron's).
using ElementNodes = std::array<uint32_t, 27>;
std::array<uint32_t, 6> tet_edge_nodes(const ElementNodes& n) {
  std::array<uint32_t, 6> e;
  for (size_t k = 0; k < 6; ++k) e[k] = n[kGmshTetEdgeNodes[k]];
  return e;
}

// Whitespace-separated fields of one line.
std::vector<std::string_view> split(std::string_view line) {
  std::vector<std::string_view> out;
  size_t at = 0;
  for (std::string_view f = next_field(line, at); !f.empty(); f = next_field(line, at)) out.push_back(f);
  return out;
}

// gmsh's element types by name, the usual ones.
std::string element_name(int type) {
  switch (type) {
    case 1:
      return "lines";
    case 2:
      return "triangles";
    case 3:
      return "quadrangles";
    case 5:
      return "hexahedra";
    case 6:
      return "prisms";
    case 7:
      return "pyramids";
    case 8:
      return "3-node lines";
    case 9:
      return "6-node triangles";
    case 11:
      return "10-node tetrahedra";
    case 15:
      return "points";
    case 21:
      return "10-node triangles";
    case 26:
      return "4-node lines";
    case 29:
      return "20-node tetrahedra";
    case 30:
      return "35-node tetrahedra";
    case 31:
      return "56-node tetrahedra";
    case 92:
      return "64-node hexahedra";
    case 93:
      return "125-node hexahedra";
    default:
      return "of gmsh type " + std::to_string(type);
  }
}

class GmshReader {
 public:
  explicit GmshReader(const std::string& path) : c_(TextCursor::open(path)) {}

  InputMesh read() {
    if (c_.at_end()) c_.fail("empty file, expected '$MeshFormat'");
    // (Other files named .msh: gmsh 1.0's, Fluent's and ANSYS's.)
    if (const std::string_view first = c_.peek(); first == "$NOD" || first == "$NOE")
      c_.fail(
          "gmsh's format 1.0 ($NOD), which is not read: save the mesh as 2.2 or 4.1 (gmsh FILE -0 -format "
          "msh41)");
    else if (!first.empty() && first[0] == '(')
      c_.fail("not a gmsh file: a Fluent or ANSYS mesh (its sections in parentheses), which is not read");
    c_.expect("$MeshFormat");
    const std::string version(c_.token("a version"));
    // A number: Netgen writes 2.0 as "2.000000". 2.0 and 2.1 are 2.2 less
    // the sections 2.2 added.
    double number = 0;
    const auto [end, ec] = std::from_chars(version.data(), version.data() + version.size(), number);
    const bool v2 =
        ec == std::errc() && end == version.data() + version.size() && number >= 2.0 && number <= 2.2;
    v4_ = ec == std::errc() && end == version.data() + version.size() && number == 4.1;
    if (!v2 && !v4_) c_.fail("unsupported version " + version + " (2.0, 2.2 and 4.1 are read)");
    const int file_type = c_.number<int>("the file type (0 ASCII, 1 binary)");
    if (file_type != 0 && file_type != 1) c_.fail("file type must be 0 (ASCII) or 1 (binary)");
    binary_ = file_type == 1;
    if (const int size = c_.number<int>("the data size"); size != 8)
      c_.fail("data size must be 8, got " + std::to_string(size));
    if (binary_) {
      // The int 1, to tell the byte order; this reader takes little-endian.
      c_.skip_to_next_line();
      if (int32(c_.bytes(4, "the byte order mark")) != 1)
        c_.fail("the int after the header is not 1 (a big-endian or damaged binary .msh)");
    }
    c_.expect("$EndMeshFormat");
    bool have_nodes = false, have_elements = false;
    while (!c_.at_end()) {
      const std::string section(c_.token("a section"));
      if (section.size() < 2 || section[0] != '$') c_.fail("expected a $Section, found '" + section + "'");
      if (section == "$Nodes") {
        if (have_nodes) c_.fail("a second $Nodes section");
        have_nodes = true;
        if (binary_)
          v4_ ? nodes_v4_binary() : nodes_v2_binary();
        else
          v4_ ? nodes_v4() : nodes_v2();
      } else if (section == "$ParametricNodes" && !v4_) {
        // (2.x with Mesh.SaveParametric: the nodes with where they lie on
        // the geometry, which is read past.)
        if (have_nodes) c_.fail("a second $Nodes section");
        have_nodes = true;
        binary_ ? parametric_nodes_v2_binary() : nodes_v2(true);
      } else if (section == "$Elements") {
        if (!have_nodes) c_.fail("$Elements before $Nodes");
        // (Element data and regions are per element of the one section.)
        if (have_elements) c_.fail("a second $Elements section");
        have_elements = true;
        if (binary_)
          v4_ ? elements_v4_binary() : elements_v2_binary();
        else
          v4_ ? elements_v4() : elements_v2();
      } else if (section == "$NodeData") {
        if (!have_nodes) c_.fail("$NodeData before $Nodes");
        node_data();
      } else if (section == "$ElementData") {
        element_data();
      } else if (section == "$PhysicalNames") {
        physical_names();
      } else if (section == "$Entities" && v4_) {
        binary_ ? entities_binary() : entities();
      } else if (section == "$PartitionedEntities" && v4_) {
        binary_ ? partitioned_entities_binary() : partitioned_entities();
      } else {
        // Sections that describe the geometry ($Entities, $Periodic, ...)
        // carry nothing of the mesh; data sections do, and are named.
        // So are a mesh's own relations: periodic boundaries' node pairs,
        // a partitioned mesh's ghost cells.
        const std::string name = section.substr(1);
        if (name.find("Data") != std::string::npos || name == "Periodic" || name == "GhostElements")
          skipped_data_.insert(name);
        skip_section(name);
        continue;
      }
      c_.expect("$End" + section.substr(1));
    }
    if (!have_nodes) throw FormatError(c_.path() + ": no $Nodes section");
    set_node_labels(out_, index_of_);
    // (Elements of order 3 and more are not read as their linear cells, as
    // the second-order ones are: their nodes would all become vertices.)
    for (const int high : {29, 30, 31, 92, 93})
      if (other_elements_.count(high))
        throw FormatError(c_.path() + ": " + std::to_string(other_elements_.at(high)) + " " +
                          element_name(high) +
                          ": volume elements of order 3 or more are not read (save the mesh at order "
                          "1 or 2: gmsh -order 2, Mesh.ElementOrder)");
    if (!v4_) drop_repeated_elements();
    index_element_tags();
    release(by_element_);
    for (const auto& e : face_edge_nodes_)
      for (uint32_t v : e)
        if (v != InputMesh::kNoEdgeNode) out_.other_edge_nodes.push_back(v);
    release(face_edge_nodes_);
    set_regions();
    set_face_tags();
    split_cells();
    keep_node_views();
    note_left_out();
    return std::move(out_);
  }

 private:
  // $PhysicalNames: "dimension tag name" lines. A volume's names its
  // region; the others are named when left out.
  void physical_names() {
    const uint64_t n = c_.count("a physical name count", c_.remaining() / 4);
    c_.skip_to_next_line();
    for (uint64_t i = 0; i < n; ++i) {
      const std::string_view line = c_.rest_of_line();
      const auto f = split(line);
      if (f.size() < 3) c_.fail("expected 'dimension tag \"name\"'");
      // The name as written, its blanks kept (from the third field on).
      std::string_view rest = line.substr(static_cast<size_t>(f[2].data() - line.data()));
      while (!rest.empty() && (rest.back() == ' ' || rest.back() == '\t' || rest.back() == '\r'))
        rest.remove_suffix(1);
      std::string name(rest);
      if (name.size() >= 2 && name.front() == '"' && name.back() == '"')
        name = name.substr(1, name.size() - 2);
      int dim = 0;
      int64_t tag = 0;
      std::from_chars(f[0].data(), f[0].data() + f[0].size(), dim);
      std::from_chars(f[1].data(), f[1].data() + f[1].size(), tag);
      if (dim == 3)
        volume_names_[tag] = name;
      else if (dim == 2)
        surface_names_[tag] = name;
      else
        physical_names_.push_back(std::string(f[0]) + ":" + std::string(f[1]) + " \"" + name + "\"");
    }
  }

  // 4.1's $Entities: which physical groups each volume entity is in (its
  // tetrahedra's region: the first). Points, curves and surfaces are read
  // past.
  void entities() {
    uint64_t counts[4];
    for (auto& k : counts) k = c_.count("an entity count", c_.remaining() / 2);
    for (int dim = 0; dim < 4; ++dim)
      for (uint64_t e = 0; e < counts[dim]; ++e) entity_record(dim, c_.number<int>("an entity tag"));
  }
  // 4.1's $PartitionedEntities (gmsh -part N, a mesh cut for a parallel
  // solver): the partitions' entities, which the elements are in, each
  // with its parent's physical groups; read as $Entities is. Which
  // partition each is in is named as left out (note_left_out()).
  void partitioned_entities() {
    partitions_ = c_.count("a partition count", c_.remaining());
    ghost_entities_ = c_.count("a ghost entity count", c_.remaining() / 4);
    for (uint64_t g = 0; g < ghost_entities_; ++g)
      c_.number<int>("a ghost entity tag"), c_.number<int>("a ghost entity's partition");
    uint64_t counts[4];
    for (auto& k : counts) k = c_.count("an entity count", c_.remaining() / 2);
    for (int dim = 0; dim < 4; ++dim)
      for (uint64_t e = 0; e < counts[dim]; ++e) {
        const int tag = c_.number<int>("an entity tag");
        const int parent_dim = c_.number<int>("a parent entity's dimension");
        const int parent = c_.number<int>("a parent entity's tag");
        const uint64_t parts = c_.count("a partition count", c_.remaining() / 2);
        for (uint64_t k = 0; k < parts; ++k) c_.number<int>("a partition tag");
        entity_record(dim, partitioned(dim, tag, parent_dim, parent));
      }
  }
  // A partitioned entity's parent, where it is one of the model's entities
  // cut: what it stands for where it is in no physical group. A surface
  // whose parent is a volume is an interface between two partitions, no
  // surface of the model: gmsh gives it (and its triangles) the volume's
  // physical groups. Returns the tag under which to record its groups
  // (kNoEntity: not recorded).
  static constexpr int kNoEntity = INT32_MIN;
  int partitioned(int dim, int tag, int parent_dim, int parent) {
    if (dim == 2 && parent_dim == 3) {
      interface_surfaces_.insert(tag);
      return kNoEntity;
    }
    if (dim == 3 && parent_dim == 3) volume_parent_[tag] = parent;
    if (dim == 2 && parent_dim == 2) surface_parent_[tag] = parent;
    return tag;
  }
  // An entity's box, physical groups and bounding entities (none for a
  // point), after its tag.
  void entity_record(int dim, int tag) {
    for (int k = 0; k < (dim == 0 ? 3 : 6); ++k) c_.number<double>("a coordinate");
    const uint64_t physicals = c_.count("a physical tag count", c_.remaining() / 2);
    for (uint64_t p = 0; p < physicals; ++p) {
      const int physical = c_.number<int>("a physical tag");
      if (dim == 3 && p == 0 && tag != kNoEntity) volume_physical_[tag] = physical;
      if (dim == 2 && p == 0 && tag != kNoEntity) surface_physical_[tag] = physical;
      if ((dim == 3 || dim == 2) && p > 0 && tag != kNoEntity) later_groups_[dim - 2].insert(physical);
    }
    if (dim == 0) return;
    const uint64_t bounding = c_.count("a bounding entity count", c_.remaining() / 2);
    for (uint64_t b = 0; b < bounding; ++b) c_.number<int>("a bounding entity tag");
  }
  void entities_binary() {
    c_.skip_to_next_line();
    const std::string_view h = c_.bytes(32, "the $Entities header");
    for (int dim = 0; dim < 4; ++dim)
      for (uint64_t e = 0, n = size_t64(h.substr(8 * static_cast<size_t>(dim))); e < n; ++e)
        entity_record_binary(dim, int32(c_.bytes(4, "an entity tag")), "$Entities");
  }
  void partitioned_entities_binary() {
    c_.skip_to_next_line();
    partitions_ = size_t64(c_.bytes(8, "the partition count"));
    ghost_entities_ = size_t64(c_.bytes(8, "the ghost entity count"));
    if (ghost_entities_ > c_.remaining() / 8)
      c_.fail("$PartitionedEntities announces more than the file holds");
    c_.bytes(8 * ghost_entities_, "the ghost entities");
    const std::string_view h = c_.bytes(32, "the $PartitionedEntities counts");
    for (int dim = 0; dim < 4; ++dim)
      for (uint64_t e = 0, n = size_t64(h.substr(8 * static_cast<size_t>(dim))); e < n; ++e) {
        const int tag = int32(c_.bytes(4, "an entity tag"));
        const std::string_view parent = c_.bytes(8, "a parent entity");
        const uint64_t parts = size_t64(c_.bytes(8, "a partition count"));
        if (parts > c_.remaining() / 4) c_.fail("$PartitionedEntities announces more than the file holds");
        c_.bytes(4 * parts, "partition tags");
        entity_record_binary(dim, partitioned(dim, tag, int32(parent), int32(parent.substr(4))),
                             "$PartitionedEntities");
      }
  }
  void entity_record_binary(int dim, int tag, const char* section) {
    c_.bytes(dim == 0 ? 24 : 48, "an entity's box");
    const uint64_t physicals = size_t64(c_.bytes(8, "a physical tag count"));
    if (physicals > c_.remaining() / 4) c_.fail(std::string(section) + " announces more than the file holds");
    const std::string_view p = c_.bytes(4 * physicals, "physical tags");
    if (dim == 3 && physicals > 0 && tag != kNoEntity) volume_physical_[tag] = int32(p);
    if (dim == 2 && physicals > 0 && tag != kNoEntity) surface_physical_[tag] = int32(p);
    for (uint64_t k = 1; k < physicals && (dim == 3 || dim == 2) && tag != kNoEntity; ++k)
      later_groups_[dim - 2].insert(int32(p.substr(4 * k)));
    if (dim == 0) return;
    const uint64_t bounding = size_t64(c_.bytes(8, "a bounding entity count"));
    if (bounding > c_.remaining() / 4) c_.fail(std::string(section) + " announces more than the file holds");
    c_.bytes(4 * bounding, "bounding entity tags");
  }

  // 2.x writes an element once per physical group it is in (gmsh, a
  // volume or surface in several groups): the copies after the first, with
  // the same nodes, are dropped, their groups named as left out (a
  // tetrahedron has one region, a face one tag); so are a hexahedron's,
  // prism's or pyramid's (keyed by all their corners), which would
  // otherwise be split into tetrahedra twice, one set over the other.
  // Copies in one group are left as they are.
  void drop_repeated_elements() {
    // (Only a file whose elements are in several groups can repeat one in
    // another: most have one volume group and one surface group, or none.)
    const auto one_group = [](const std::vector<int64_t>& tags) {
      return std::adjacent_find(tags.begin(), tags.end(), std::not_equal_to<>()) == tags.end();
    };
    if (one_group(tet_tag_) && one_group(tri_tag_)) return;
    std::set<int64_t> groups[2];  // surfaces', volumes'
    const auto drop = [&](size_t count, auto key_of, auto&& compact, int d) {
      // (A copy in the same group is a repeated element, not another
      // group's: left as it is.)
      struct KeyHash {
        size_t operator()(const std::array<uint32_t, 8>& k) const {
          uint64_t h = 0;
          for (uint32_t v : k) h = (h ^ v) * 0x9E3779B97F4A7C15ull;
          return h ^ (h >> 29);
        }
      };
      std::unordered_map<std::array<uint32_t, 8>, int64_t, KeyHash> first_group;
      first_group.reserve(count);
      std::vector<uint32_t> new_index(count);
      uint32_t kept = 0;
      for (size_t i = 0; i < count; ++i) {
        const int64_t group = d == 1 ? tet_tag_[i] : tri_tag_[i];
        const auto [at, fresh] = first_group.emplace(key_of(i), group);
        if (!fresh && at->second != group) {
          groups[d].insert(group);
          new_index[i] = UINT32_MAX;
          continue;
        }
        new_index[i] = kept++;
      }
      if (kept < count) compact(new_index, kept);
    };
    // (The key: an element's corners ascending, UINT32_MAX after them.)
    const auto sorted_key = [](std::span<const uint32_t> corners) {
      std::array<uint32_t, 8> key;
      key.fill(UINT32_MAX);
      std::copy_n(corners.begin(), std::min(corners.size(), key.size()), key.begin());
      std::sort(key.begin(), key.end());  // (the padding stays last)
      return key;
    };
    std::vector<uint32_t> split_of_slot(out_.tets.size(), UINT32_MAX);  // the slot's split cell
    for (size_t k = 0; k < split_cells_.size(); ++k)
      split_of_slot[split_cells_[k].slot] = static_cast<uint32_t>(k);
    const auto keep_where = [](auto& items, const std::vector<uint32_t>& new_index) {
      if (items.empty()) return;
      size_t k = 0;
      for (size_t i = 0; i < new_index.size(); ++i)
        if (new_index[i] != UINT32_MAX) items[k++] = items[i];
      items.resize(k);
    };
    drop(
        out_.tets.size(),
        [&](size_t i) {
          if (split_of_slot[i] == UINT32_MAX) return sorted_key(out_.tets[i]);
          const SplitCell& c = split_cells_[split_of_slot[i]];
          return sorted_key(std::span(c.corners).first(c.count));
        },
        [&](const std::vector<uint32_t>& new_index, uint32_t) {
          keep_where(out_.tets, new_index);
          keep_where(tet_tag_, new_index);
          keep_where(tet_entity_, new_index);
          keep_where(tet_element_, new_index);
          keep_where(out_.tet_edge_nodes, new_index);
          for (VertexField& f : out_.cell_fields) {
            const auto n = static_cast<size_t>(f.components);
            size_t k = 0;
            for (size_t i = 0; i < new_index.size(); ++i) {
              if (new_index[i] == UINT32_MAX) continue;
              for (size_t j = 0; j < n; ++j) f.values[k * n + j] = f.values[i * n + j];
              ++k;
            }
            f.values.resize(k * n);
          }
          for (SplitCell& c : split_cells_) c.slot = new_index[c.slot];
          std::erase_if(split_cells_, [](const SplitCell& c) { return c.slot == UINT32_MAX; });
        },
        1);
    drop(
        triangles_.size(),
        [&](size_t i) {
          const std::array<uint32_t, 4> q = {triangles_[i][0], triangles_[i][1], triangles_[i][2],
                                             quad_fourth_.empty() ? UINT32_MAX : quad_fourth_[i]};
          return sorted_key(std::span(q).first(q[3] == UINT32_MAX ? 3 : 4));
        },
        [&](const std::vector<uint32_t>& new_index, uint32_t) {
          keep_where(triangles_, new_index);
          keep_where(tri_tag_, new_index);
          keep_where(tri_entity_, new_index);
          keep_where(face_edge_nodes_, new_index);
          keep_where(quad_fourth_, new_index);
        },
        0);
    for (int d = 1; d >= 0; --d) {
      std::string list;
      const auto& names = d == 1 ? volume_names_ : surface_names_;
      for (int64_t g : groups[d]) {
        const auto name = names.find(static_cast<int32_t>(g));
        list += (list.empty() ? "" : ", ") + std::to_string(g) +
                (name != names.end() ? " \"" + name->second + "\"" : std::string());
      }
      if (!list.empty())
        out_.left_out.push_back(std::string("physical ") + (d == 1 ? "volumes" : "surfaces") +
                                " an element is in after its first (2.x repeats the element: the first " +
                                "copy kept, " + (d == 1 ? "a cell has one region" : "a face one tag") +
                                "): " + list);
    }
  }

  // Each tetrahedron's region: 2.x its physical tag (the first tag); 4.1
  // its volume entity's physical group where $Entities gives one, else (no
  // volume in a physical group) the entity itself. A volume in no physical
  // group beside others in one (gmsh -save_all) is not theirs: an entity's
  // number may be a group's tag. Its tetrahedra are one region of their own,
  // labelled one above the groups' largest tag (a label gmsh takes back as a
  // physical group), named "no physical group".
  void set_regions() {
    if (tet_tag_.size() != out_.tets.size() || tet_tag_.empty() || (!v4_ && !tagged_)) return;
    // (2.x's physical tag 0 is no physical group. A file without any
    // takes its elementary entities instead, as 4.1's volume entities;
    // tetrahedra in none of either, as meshio writes a mesh without
    // groups, are no regions.)
    const auto none = [](const std::vector<int64_t>& tags) {
      return std::all_of(tags.begin(), tags.end(), [](int64_t t) { return t == 0; });
    };
    if (!v4_ && none(tet_tag_) && none(tri_tag_) && !none(tet_entity_)) {
      // (gmsh -save_all writes 2.x's physical tag 0 on every element even
      // where $PhysicalNames lists groups: which entities those groups
      // hold is not in the file. Their names are not the entities' and
      // are named as left out.)
      std::string groups;
      for (int d = 1; d >= 0; --d)
        for (const auto& [tag, name] : d == 1 ? volume_names_ : surface_names_)
          groups += (groups.empty() ? "" : ", ") + std::string(d == 1 ? "volume " : "surface ") +
                    std::to_string(tag) + " \"" + name + "\"";
      if (!groups.empty())
        out_.left_out.push_back("the physical groups of $PhysicalNames (" + groups +
                                "): no element carries a physical tag (gmsh -save_all writes 0), so the "
                                "regions and face tags are the elementary entities, unnamed");
      volume_names_.clear(), surface_names_.clear();
      tet_tag_ = tet_entity_;
      if (!none(tri_entity_)) tri_tag_ = tri_entity_, by_entities_ = true;
      out_.tet_regions.reserve(tet_tag_.size());
      for (int64_t t : tet_tag_) {
        if (t < INT32_MIN || t > INT32_MAX) c_.fail("a region tag out of the 32-bit range");
        out_.tet_regions.push_back(static_cast<int32_t>(t));
      }
      out_.region_source = "volume entities";
      return;
    }
    if (!v4_ && none(tet_tag_)) return;
    std::set<int64_t> unnamed_entities;
    int64_t largest = 0;
    for (const auto& [entity, physical] : volume_physical_) largest = std::max<int64_t>(largest, physical);
    if (largest >= INT32_MAX) c_.fail("a region tag out of the 32-bit range");
    const auto unassigned = static_cast<int32_t>(largest + 1);
    uint64_t unassigned_tets = 0;
    out_.tet_regions.reserve(tet_tag_.size());
    for (int64_t tag : tet_tag_) {
      int64_t region = tag;
      if (v4_) {
        const auto it = volume_physical_.find(static_cast<int>(tag));
        if (it != volume_physical_.end()) {
          region = it->second;
        } else {
          // (A partition's volume stands for the model's it was cut from.)
          if (const auto p = volume_parent_.find(static_cast<int>(tag)); p != volume_parent_.end())
            region = p->second;
          unnamed_entities.insert(region);
          if (!volume_physical_.empty()) region = unassigned, ++unassigned_tets;
        }
      }
      if (region < INT32_MIN || region > INT32_MAX) c_.fail("a region tag out of the 32-bit range");
      out_.tet_regions.push_back(static_cast<int32_t>(region));
    }
    out_.region_names = volume_names_;
    if (!v4_) {
      out_.region_source = "physical tags";
    } else if (unnamed_entities.empty()) {
      out_.region_source = "physical volumes";
    } else if (volume_physical_.empty()) {
      out_.region_source = "volume entities";
    } else {
      out_.region_names.emplace(unassigned, "no physical group");
      out_.region_source = "physical volumes; " + std::to_string(unassigned_tets) + " tetrahedra of " +
                           std::to_string(unnamed_entities.size()) + " volume" +
                           (unnamed_entities.size() == 1 ? "" : "s") + " in no physical group as region " +
                           std::to_string(unassigned);
    }
  }

  // Each triangle's tag: 2.x its physical tag; 4.1 its surface entity's
  // physical group where $Entities gives one, else (no physical group in
  // the file) the entity.
  void set_face_tags() {
    if (tri_tag_.empty()) return;
    if (!v4_ && !tagged_) {  // 2.x elements without tags: nothing to tag them with
      out_.left_out.push_back(std::to_string(triangles_.size()) + " triangles without tags");
      return;
    }
    // A triangle of a surface in no physical group beside others in one
    // (gmsh -save_all: 4.1's entity, 2.x's physical tag 0) is no boundary
    // condition: not tagged (an entity's number may be a group's tag).
    uint64_t untagged = 0, on_interfaces = 0;
    std::vector<std::array<uint32_t, 3>> tagged;
    for (size_t i = 0; i < tri_tag_.size(); ++i) {
      int64_t t = tri_tag_[i];
      bool in_no_group = !v4_ && t == 0;
      if (v4_) {
        if (interface_surfaces_.count(static_cast<int>(t))) {
          ++on_interfaces;
          continue;
        }
        if (const auto it = surface_physical_.find(static_cast<int>(t)); it != surface_physical_.end())
          t = it->second;
        else if (const auto p = surface_parent_.find(static_cast<int>(t)); p != surface_parent_.end())
          t = p->second, in_no_group = !surface_physical_.empty() || !volume_physical_.empty();
        else  // (with -save_all beside any physical group, volumes' too)
          in_no_group = !surface_physical_.empty() || !volume_physical_.empty();
      }
      if (in_no_group) {
        ++untagged;
        continue;
      }
      if (t < INT32_MIN || t > INT32_MAX) c_.fail("a surface tag out of the 32-bit range");
      if (!quad_fourth_.empty() && quad_fourth_[i] != InputMesh::kNoEdgeNode) {
        // A quadrangle: its two triangles, as its cell splits it.
        const auto& q = triangles_[i];
        for (const auto& half : split_quad({q[0], q[1], q[2], quad_fourth_[i]})) {
          out_.face_tags.push_back(static_cast<int32_t>(t));
          tagged.push_back(half);
        }
        continue;
      }
      out_.face_tags.push_back(static_cast<int32_t>(t));
      tagged.push_back(triangles_[i]);
    }
    if (untagged > 0)
      out_.left_out.push_back(std::to_string(untagged) + " triangles of surfaces in no physical group");
    if (on_interfaces > 0)
      out_.left_out.push_back(std::to_string(on_interfaces) +
                              " triangles of the interfaces between partitions (gmsh -part)");
    release(triangles_);
    out_.tagged_faces = std::move(tagged);
    out_.face_tag_names = surface_names_;
    out_.face_tag_source = by_entities_ || (v4_ && surface_physical_.empty()) ? "surface entities"
                           : v4_                                              ? "physical surfaces"
                                                                              : "physical tags";
  }

  // The hexahedra, prisms and pyramids as their tetrahedra (cell_split.h),
  // each with the cell's region, cell data and no edge nodes.
  void split_cells() {
    if (split_cells_.empty()) return;
    std::map<size_t, uint64_t> split;  // cells by corner count
    std::vector<std::array<uint32_t, 4>> tets;
    std::vector<uint32_t> cell_of;  // each new tetrahedron's cell
    size_t next = 0;                // the next cell to split, in split_cells_
    for (size_t t = 0; t < out_.tets.size(); ++t) {
      const size_t before = tets.size();
      if (next < split_cells_.size() && split_cells_[next].slot == t) {
        const SplitCell& c = split_cells_[next++];
        split_cell(std::span(c.corners).first(c.count), out_.points, tets), ++split[c.count];
        // A second-order cell's other nodes are set aside (second_order.h).
        out_.other_edge_nodes.insert(out_.other_edge_nodes.end(), c.extras.begin(),
                                     c.extras.begin() + c.extra);
        out_.second_order_cells += c.extra > 0;
      } else {
        tets.push_back(out_.tets[t]);
      }
      cell_of.insert(cell_of.end(), tets.size() - before, static_cast<uint32_t>(t));
    }
    const auto spread = [&](auto& per_cell, size_t per) {
      if (per_cell.empty()) return;
      std::remove_reference_t<decltype(per_cell)> out;
      out.reserve(cell_of.size() * per);
      for (size_t c : cell_of)
        out.insert(out.end(), per_cell.begin() + c * per, per_cell.begin() + (c + 1) * per);
      per_cell = std::move(out);
    };
    spread(out_.tet_regions, 1);
    spread(out_.tet_edge_nodes, 1);
    for (VertexField& f : out_.cell_fields) spread(f.values, static_cast<size_t>(f.components));
    out_.tets = std::move(tets);
    release(split_cells_);
    out_.left_out.push_back(split_cells_note(split));
  }

  void note_left_out() {
    auto joined = [](const auto& items) {
      std::string s;
      for (const auto& i : items) s += (s.empty() ? "" : ", ") + i;
      return s;
    };
    std::vector<std::string> others;
    for (const auto& [type, count] : other_elements_)
      others.push_back(std::to_string(count) + " " + element_name(type));
    if (!others.empty()) out_.left_out.push_back("elements other than tetrahedra (" + joined(others) + ")");
    if (!physical_names_.empty())
      out_.left_out.push_back("$PhysicalNames of points, curves and surfaces (" + joined(physical_names_) +
                              ")");
    if (!partial_node_data_.empty())
      out_.left_out.push_back("$NodeData not given at every node (" + joined(partial_node_data_) + ")");
    if (!partial_element_data_.empty())
      out_.left_out.push_back("$ElementData not given at every tetrahedron (" +
                              joined(partial_element_data_) + ")");
    if (!element_data_elsewhere_.empty())
      out_.left_out.push_back("$ElementData's values on elements other than tetrahedra (" +
                              joined(element_data_elsewhere_) + "; cell data is the tetrahedra's)");
    if (!skipped_data_.empty()) out_.left_out.push_back("sections $" + joined(skipped_data_));
    // (4.1: an entity in several physical groups is its first's.)
    for (int d = 1; d >= 0; --d) {
      std::vector<std::string> groups;
      for (int g : later_groups_[d]) {
        const auto& names = d == 1 ? volume_names_ : surface_names_;
        const auto name = names.find(g);
        groups.push_back(std::to_string(g) + (name != names.end() ? " \"" + name->second + "\"" : ""));
      }
      if (!groups.empty())
        out_.left_out.push_back(std::string(d == 1 ? "physical volumes" : "physical surfaces") +
                                " beyond an entity's first (an entity in several groups is its first's: " +
                                (d == 1 ? "a cell has one region" : "a face one tag") +
                                "): " + joined(groups));
    }
    if (partitions_ > 0)
      out_.left_out.push_back("the partitioning into " + std::to_string(partitions_) +
                              " partitions (gmsh -part: which partition each element is in" +
                              (ghost_entities_ > 0
                                   ? ", and its " + std::to_string(ghost_entities_) + " ghost entities"
                                   : std::string()) +
                              ")");
  }

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

  // "tag x y z" a line; `parametric` ($ParametricNodes): then "dimension
  // entity [u [v]]", read past.
  void nodes_v2(bool parametric = false) {
    const uint64_t n = c_.count("a node count", c_.remaining() / 8);
    out_.points.reserve(n);
    for (uint64_t i = 0; i < n; ++i) {
      add_node(c_.number<int64_t>("a node tag"), out_.points.size());
      const double x = c_.coordinate(), y = c_.coordinate(), z = c_.coordinate();
      out_.points.push_back({x, y, z});
      if (parametric) c_.rest_of_line();
    }
  }

  void nodes_v4() {
    const uint64_t blocks = c_.count("a block count", c_.remaining() / 8);
    const uint64_t n = c_.count("a node count", c_.remaining() / 8);
    const std::string announced = c_.where();  // the count's line
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
      // The tags, then the coordinates: a line each, parsed on every core.
      c_.skip_to_next_line();
      std::vector<int64_t> tags(in_block);
      c_.lines(in_block, [&](uint64_t i, std::string_view line) {
        size_t at = 0;
        const std::string_view f = next_field(line, at);
        if (!parse_whole(f, tags[i]) || !next_field(line, at).empty())
          c_.fail_line(i, "expected a node tag, found '" + std::string(line) + "'");
      });
      for (uint64_t i = 0; i < in_block; ++i)
        if (!index_of_.emplace(tags[i], static_cast<uint32_t>(first + i)).second)
          c_.fail_line(i, "node tag " + std::to_string(tags[i]) + " defined twice");
      release(tags);
      out_.points.resize(first + in_block);
      const int fields = 3 + dim * parametric;
      c_.lines(in_block, [&](uint64_t i, std::string_view line) {
        size_t at = 0;
        double xyz[3] = {0, 0, 0};
        for (int k = 0; k < fields; ++k) {
          const std::string_view f = next_field(line, at);
          double v = 0;
          if (!parse_whole(f, v))
            c_.fail_line(i, f.empty() ? "expected " + std::to_string(fields) + " coordinates"
                                      : "expected a coordinate, found '" + std::string(f) + "'");
          if (!std::isfinite(v)) c_.fail_line(i, "coordinate is not finite");
          if (k < 3) xyz[k] = v;
        }
        if (!next_field(line, at).empty())
          c_.fail_line(i, "more than " + std::to_string(fields) + " coordinates");
        out_.points[first + i] = {xyz[0], xyz[1], xyz[2]};
      });
    }
    if (out_.points.size() != n)
      throw FormatError(announced + ": $Nodes announces " + std::to_string(n) + " nodes, its blocks hold " +
                        std::to_string(out_.points.size()));
  }

  // A node's index by its tag (its text), or fail(problem), which throws.
  template <class Fail>
  uint32_t node_of(int64_t tag, const Fail& fail) const {
    const auto it = index_of_.find(tag);
    if (it == index_of_.end()) fail("node tag " + std::to_string(tag) + " out of range (no such node)");
    return it->second;
  }
  template <class Fail>
  uint32_t node_of(std::string_view tag_text, const Fail& fail) const {
    int64_t tag = 0;
    if (!parse_whole(tag_text, tag)) fail("expected a node tag, found '" + std::string(tag_text) + "'");
    return node_of(tag, fail);
  }
  uint32_t node(std::string_view tag_text) const {
    return node_of(tag_text, [&](const std::string& problem) { c_.fail(problem); });
  }
  uint32_t node(int64_t tag) const {
    return node_of(tag, [&](const std::string& problem) { c_.fail(problem); });
  }

  // The element tag of the tetrahedron about to be added ($ElementData names it).
  void note_tetrahedron(int64_t element_tag) { tet_element_.push_back(element_tag); }

  // Room for the tetrahedra up to `count` (their tags, element tags and,
  // for 10-node ones or once the mesh has some, edge nodes), filled by
  // put_element() on every core.
  void make_room_for_tetrahedra(int type, size_t count) {
    const size_t first = out_.tets.size();
    out_.tets.resize(count);
    tet_tag_.resize(count, tag_);
    if (!v4_) tet_entity_.resize(count, entity_);
    tet_element_.resize(count);
    if (type == kGmshTetrahedron10 || !out_.tet_edge_nodes.empty())
      out_.tet_edge_nodes.resize(count, kNoEdgeNodes);
    if (is_split_cell(type)) {
      // (Blocks are read one after the other: put_element() finds each
      // cell's place from the block's first.)
      split_block_ = {split_cells_.size(), first};
      split_cells_.resize(split_cells_.size() + (count - first));
    }
  }
  void make_room_for_triangles(int type, size_t count) {
    triangles_.resize(count);
    tri_tag_.resize(count, tag_);
    if (!v4_) tri_entity_.resize(count, entity_);
    // (A second-order face's nodes past its corners, set aside with the
    // cells' unless they are some cell's corners: second_order.h.)
    if (kept_element_nodes(type) > (is_quadrangle(type) ? 4u : 3u) || !face_edge_nodes_.empty()) {
      std::array<uint32_t, 5> none;
      none.fill(InputMesh::kNoEdgeNode);
      face_edge_nodes_.resize(count, none);
    }
    if (is_quadrangle(type) || !quad_fourth_.empty()) quad_fourth_.resize(count, InputMesh::kNoEdgeNode);
  }
  // Element `at` of the room made above, from its nodes as read.
  void put_element(int type, size_t at, const ElementNodes& n) {
    if (is_tetrahedron(type)) {
      // (A hexahedron's, prism's or pyramid's place holds its first four
      // corners until split_cells() splits it.)
      out_.tets[at] = {n[0], n[1], n[2], n[3]};
      if (type == kGmshTetrahedron10) out_.tet_edge_nodes[at] = tet_edge_nodes(n);
      if (is_split_cell(type)) {
        SplitCell& c = split_cells_[split_block_.first + (at - split_block_.second)];
        const CellType& t = *split_type(type);
        c.slot = static_cast<uint32_t>(at);
        c.count = static_cast<uint8_t>(t.corners);
        c.extra = static_cast<uint8_t>(t.nodes - t.corners);
        std::copy_n(n.begin(), t.corners, c.corners.begin());
        std::copy_n(n.begin() + static_cast<std::ptrdiff_t>(t.corners), c.extra, c.extras.begin());
      }
    } else {
      triangles_[at] = {n[0], n[1], n[2]};
      const size_t corners = is_quadrangle(type) ? 4 : 3;
      for (size_t k = corners; k < kept_element_nodes(type); ++k) face_edge_nodes_[at][k - corners] = n[k];
      if (is_quadrangle(type)) quad_fourth_[at] = n[3];
    }
  }
  void add_tetrahedron(int type, const ElementNodes& n) {
    make_room_for_tetrahedra(type, out_.tets.size() + 1);
    put_element(type, out_.tets.size() - 1, n);
  }
  void add_triangle(int type, const ElementNodes& n) {
    make_room_for_triangles(type, triangles_.size() + 1);
    put_element(type, triangles_.size() - 1, n);
  }

  // Fails when two tetrahedra share an element tag; afterwards tet_of()
  // finds a tetrahedron by its tag. gmsh numbers its elements in order, so
  // the tags mostly ascend and are searched where they are.
  void index_element_tags() {
    if (indexed_ == tet_element_.size()) return;
    indexed_ = tet_element_.size();
    by_element_.clear();
    tags_ascend_ = std::adjacent_find(tet_element_.begin(), tet_element_.end(),
                                      [](int64_t a, int64_t b) { return a >= b; }) == tet_element_.end();
    if (tags_ascend_) return;
    by_element_.reserve(tet_element_.size());
    for (uint32_t t = 0; t < tet_element_.size(); ++t) by_element_.emplace_back(tet_element_[t], t);
    std::sort(by_element_.begin(), by_element_.end());
    const auto twice = std::adjacent_find(by_element_.begin(), by_element_.end(),
                                          [](const auto& a, const auto& b) { return a.first == b.first; });
    if (twice != by_element_.end())
      throw FormatError(c_.path() + ": two elements are tagged " + std::to_string(twice->first));
  }
  // The tetrahedron of an element tag, or -1 (another element's).
  int64_t tet_of(int64_t tag) const {
    if (tags_ascend_) {
      const auto it = std::lower_bound(tet_element_.begin(), tet_element_.end(), tag);
      return it != tet_element_.end() && *it == tag ? it - tet_element_.begin() : -1;
    }
    const auto it =
        std::lower_bound(by_element_.begin(), by_element_.end(), std::pair<int64_t, uint32_t>{tag, 0});
    return it != by_element_.end() && it->first == tag ? int64_t{it->second} : -1;
  }

  // The tag of the tetrahedron read next: its physical tag (2.x: the first
  // tag), or its volume entity (4.1); set_regions() makes it its region.
  void note_volume_tag(int64_t tag, int64_t entity = 0) { tag_ = tag, entity_ = entity; }

  // 2.x's element lines ("tag type ntags tags... nodes..."), parsed on every
  // core a chunk at a time (each line into its record), then added in order.
  void elements_v2() {
    const uint64_t n = c_.count("an element count", c_.remaining() / 8);
    c_.skip_to_next_line();
    struct Line {
      ElementNodes nodes;
      int64_t physical;  // the first tag (0: none)
      int64_t entity;    // the second (the elementary entity)
      int64_t tag;       // a tetrahedron's element tag
      int32_t type;
      int32_t partition;  // gmsh -part: the largest of its partitions (0: none)
      bool tagged;
      bool odd_triangle;  // a triangle of other than 3 or 6 nodes (counted, not kept)
    };
    constexpr uint64_t kChunk = uint64_t{1} << 19;  // lines held at once (70 MB)
    std::vector<Line> chunk;
    for (uint64_t done = 0; done < n; done += chunk.size()) {
      chunk.assign(std::min(kChunk, n - done), Line{});
      c_.lines(chunk.size(), [&](uint64_t i, std::string_view line) {
        size_t at = 0;
        const std::string_view tag = next_field(line, at), type_text = next_field(line, at),
                               count = next_field(line, at);
        if (tag.empty())
          c_.fail_line(
              i, "file ends after " + std::to_string(done + i) + " of " + std::to_string(n) + " elements");
        if (count.empty()) c_.fail_line(i, "expected 'tag type ntags ...'");
        Line& r = chunk[i];
        r.type = 0;
        r.odd_triangle = false;
        // A field read whole: "4x" or "1.5" is an error, not 4 or 1.
        const auto whole = [&](std::string_view f, auto& value, const char* what) {
          const auto [end, ec] = std::from_chars(f.data(), f.data() + f.size(), value);
          if (ec != std::errc() || end != f.data() + f.size())
            c_.fail_line(i, std::string("expected ") + what + ", found '" + std::string(f) + "'");
        };
        whole(type_text, r.type, "an element type");
        int tags = 0;
        whole(count, tags, "an element tag count");
        if (tags < 0) c_.fail_line(i, "bad element tag count");
        const bool kept = is_tetrahedron(r.type) || is_triangle(r.type);
        r.physical = 0;
        r.entity = 0;
        r.partition = 0;
        // (The tags: physical, elementary, then gmsh -part's partition
        // count and partitions, a ghost cell's negative.)
        for (int k = 0; k < tags; ++k) {
          const std::string_view t = next_field(line, at);
          if (t.empty()) c_.fail_line(i, "bad element tag count");
          if (k == 0 && kept) whole(t, r.physical, "a physical tag");
          if (k == 1 && kept) whole(t, r.entity, "an elementary tag");
          if (k >= 3) {
            int32_t part = 0;
            whole(t.substr(t[0] == '-'), part, "a partition");
            r.partition = std::max(r.partition, part);
          }
        }
        r.tagged = kept && tags > 0;
        size_t nodes = 0;
        r.nodes = {};
        for (std::string_view f = next_field(line, at); !f.empty(); f = next_field(line, at), ++nodes) {
          const uint32_t v = node_on_line(f, i);
          if (nodes < r.nodes.size()) r.nodes[nodes] = v;
        }
        if (nodes == 0) c_.fail_line(i, "element without nodes");
        if (is_tetrahedron(r.type)) {
          if (nodes != kept_element_nodes(r.type))
            c_.fail_line(
                i, std::string("a ") + element_kind(r.type) + " with " + std::to_string(nodes) + " nodes");
          whole(tag, r.tag, "an element tag");
        } else if (is_triangle(r.type) && nodes != kept_element_nodes(r.type)) {
          r.odd_triangle = true;
        }
      });
      for (const Line& r : chunk) {
        partitions_ = std::max<uint64_t>(partitions_, static_cast<uint64_t>(r.partition));
        if (is_tetrahedron(r.type) || is_triangle(r.type)) {
          tagged_ = tagged_ || r.tagged;
          note_volume_tag(r.physical, r.entity);
        }
        if (is_tetrahedron(r.type)) {
          note_tetrahedron(r.tag);
          add_tetrahedron(r.type, r.nodes);
        } else if (is_triangle(r.type) && !r.odd_triangle) {
          add_triangle(r.type, r.nodes);
        } else {
          ++other_elements_[r.type];
        }
      }
    }
  }

  void elements_v4() {
    const uint64_t blocks = c_.count("a block count", c_.remaining() / 8);
    const uint64_t n = c_.count("an element count", c_.remaining() / 8);
    const std::string announced = c_.where();  // the count's line
    c_.number<int64_t>("the smallest element tag");
    c_.number<int64_t>("the largest element tag");
    uint64_t seen = 0;
    for (uint64_t b = 0; b < blocks; ++b) {
      c_.number<int>("an entity dimension");
      const int entity = c_.number<int>("an entity tag");
      const int type = c_.number<int>("an element type");
      if (is_tetrahedron(type) || is_triangle(type)) note_volume_tag(entity);
      const uint64_t in_block = c_.count("an element count", c_.remaining() / 4);
      c_.skip_to_next_line();
      element_block(in_block, type);
      seen += in_block;
    }
    if (seen != n)
      throw FormatError(announced + ": $Elements announces " + std::to_string(n) +
                        " elements, its blocks hold " + std::to_string(seen));
  }

  // A node's index by its tag, read by the threads of an element block
  // (line i of it).
  uint32_t node_on_line(std::string_view tag_text, uint64_t i) const {
    return node_of(tag_text, [&](const std::string& problem) { c_.fail_line(i, problem); });
  }

  // 4.1's element lines of one block ("tag node node ..."), all of one
  // type, parsed on every core, each into its place.
  void element_block(uint64_t in_block, int type) {
    const bool tet = is_tetrahedron(type), tri = is_triangle(type);
    // Room is made before the lines are read: no more than their bytes can
    // hold (a field and its separator take two bytes at least).
    const size_t per = tet || tri ? kept_element_nodes(type) : 0;
    if ((tet || tri) && in_block > c_.remaining() / (2 * (1 + per)))
      c_.fail("an element count " + std::to_string(in_block) + " is more than the file can hold");
    const size_t first = tet ? out_.tets.size() : triangles_.size();
    if (tet) make_room_for_tetrahedra(type, first + in_block);
    if (tri) make_room_for_triangles(type, first + in_block);
    c_.lines(in_block, [&](uint64_t i, std::string_view line) {
      size_t at = 0;
      const std::string_view element_tag = next_field(line, at);
      if (element_tag.empty()) c_.fail_line(i, "file ends or blank line inside an element block");
      ElementNodes t{};
      size_t nodes = 0;
      for (std::string_view f = next_field(line, at); !f.empty(); f = next_field(line, at), ++nodes) {
        const uint32_t v = node_on_line(f, i);
        if (nodes < t.size()) t[nodes] = v;
      }
      if (nodes == 0) c_.fail_line(i, "element without nodes");
      if ((tet || tri) && nodes != per)
        c_.fail_line(i, std::string("a ") + element_kind(type) + " with " + std::to_string(nodes) + " nodes");
      if (tet) {
        int64_t tag = 0;
        if (!parse_whole(element_tag, tag))
          c_.fail_line(i, "expected an element tag, found '" + std::string(element_tag) + "'");
        tet_element_[first + i] = tag;
      }
      if (tet || tri) put_element(type, first + i, t);
    });
    if (!tet && !tri && in_block > 0) other_elements_[type] += in_block;
  }

  // Binary sections (file type 1): little-endian ints (4 bytes), size_t
  // (8: the data size) and doubles, as gmsh and meshio write them.
  static int32_t int32(std::string_view b) {
    int32_t v;
    std::memcpy(&v, b.data(), 4);
    return v;
  }
  static uint64_t size_t64(std::string_view b) {
    uint64_t v;
    std::memcpy(&v, b.data(), 8);
    return v;
  }
  static double float64(std::string_view b) {
    double v;
    std::memcpy(&v, b.data(), 8);
    return v;
  }
  void add_point(std::string_view xyz) {
    const double p[3] = {float64(xyz), float64(xyz.substr(8)), float64(xyz.substr(16))};
    for (double v : p)
      if (!std::isfinite(v)) c_.fail("coordinate is not finite");
    out_.points.push_back({p[0], p[1], p[2]});
  }
  // A binary element's node tags, `per` of them `size` bytes each.
  void binary_element(int64_t element_tag, std::string_view nodes, int type, int per, int size) {
    ElementNodes t{};
    for (int k = 0; k < per; ++k) {
      const std::string_view b = nodes.substr(static_cast<size_t>(k) * size);
      const uint32_t v = node(size == 4 ? int64_t{int32(b)} : static_cast<int64_t>(size_t64(b)));
      if (static_cast<size_t>(k) < t.size()) t[k] = v;
    }
    if (is_tetrahedron(type)) {
      note_tetrahedron(element_tag);
      add_tetrahedron(type, t);
    } else if (is_triangle(type)) {
      add_triangle(type, t);
    } else {
      ++other_elements_[type];
    }
  }

  // A 4.1 binary block of tetrahedra or triangles (element tag, then node
  // tags, 8 bytes each), on every core, each element into its place.
  void binary_block(std::string_view b, uint64_t in_block, uint64_t record, int type) {
    const bool tet = is_tetrahedron(type);
    const size_t first = tet ? out_.tets.size() : triangles_.size();
    const size_t per = kept_element_nodes(type);
    if (tet)
      make_room_for_tetrahedra(type, first + in_block);
    else
      make_room_for_triangles(type, first + in_block);
    constexpr uint64_t kRange = uint64_t{1} << 16;
    std::vector<std::exception_ptr> failure((in_block + kRange - 1) / kRange);
    parallel_ranges(in_block, kRange, [&](size_t lo, size_t hi) {
      try {
        for (size_t e = lo; e < hi; ++e) {
          const std::string_view r = b.substr(e * record, record);
          ElementNodes t{};
          for (size_t k = 0; k < per; ++k) t[k] = node(static_cast<int64_t>(size_t64(r.substr(8 * (k + 1)))));
          if (tet) tet_element_[first + e] = static_cast<int64_t>(size_t64(r));
          put_element(type, first + e, t);
        }
      } catch (...) {
        failure[lo / kRange] = std::current_exception();
      }
    });
    for (const std::exception_ptr& e : failure)
      if (e) std::rethrow_exception(e);
  }

  // int tag, 3 doubles, int dimension, int entity, then a curve's u or a
  // surface's u and v (doubles).
  void parametric_nodes_v2_binary() {
    const uint64_t n = c_.count("a node count", c_.remaining() / 36);
    c_.skip_to_next_line();
    out_.points.reserve(n);
    for (uint64_t i = 0; i < n; ++i) {
      const std::string_view b = c_.bytes(36, "a node");
      add_node(int32(b), out_.points.size());
      add_point(b.substr(4, 24));
      const int dim = int32(b.substr(28));
      if (dim < 0 || dim > 3) c_.fail("a parametric node of dimension " + std::to_string(dim));
      if (dim == 1 || dim == 2) c_.bytes(8 * static_cast<uint64_t>(dim), "a node's parameters");
    }
  }

  void nodes_v2_binary() {
    const uint64_t n = c_.count("a node count", c_.remaining() / 28);
    c_.skip_to_next_line();
    const std::string_view b = c_.bytes(n * 28, "the nodes");
    out_.points.reserve(n);
    for (uint64_t i = 0; i < n; ++i) {
      add_node(int32(b.substr(28 * i)), out_.points.size());
      add_point(b.substr(28 * i + 4, 24));
    }
  }

  void elements_v2_binary() {
    const uint64_t n = c_.count("an element count", c_.remaining() / 8);
    c_.skip_to_next_line();
    for (uint64_t seen = 0; seen < n;) {
      const std::string_view h = c_.bytes(12, "an element block header");
      const int type = int32(h), tags = int32(h.substr(8));
      const int64_t count = int32(h.substr(4));
      const int per = nodes_per_element(type);
      if (count <= 0 || static_cast<uint64_t>(count) > n - seen || tags < 0 || tags > 64)
        c_.fail("bad element block header (type " + std::to_string(type) + ", " + std::to_string(count) +
                " elements, " + std::to_string(tags) + " tags)");
      const uint64_t record = 4 * (1 + static_cast<uint64_t>(tags) + per);
      if (static_cast<uint64_t>(count) > c_.remaining() / record)
        c_.fail("file ends inside an element block");
      const std::string_view b = c_.bytes(count * record, "the elements");
      for (int64_t e = 0; e < count; ++e) {
        const std::string_view r = b.substr(e * record, record);
        for (int k = 3; k < tags; ++k)  // (gmsh -part's partitions, as in elements_v2())
          partitions_ = std::max<uint64_t>(
              partitions_,
              static_cast<uint64_t>(std::abs(static_cast<int64_t>(int32(r.substr(4 * (1 + k)))))));
        const bool kept = is_tetrahedron(type) || is_triangle(type);
        if (kept) note_volume_tag(tags > 0 ? int32(r.substr(4)) : 0, tags > 1 ? int32(r.substr(8)) : 0);
        tagged_ = tagged_ || (kept && tags > 0);
        binary_element(int32(r), r.substr(4 * (1 + tags)), type, per, 4);
      }
      seen += count;
    }
  }

  void nodes_v4_binary() {
    c_.skip_to_next_line();
    const std::string_view h = c_.bytes(32, "the $Nodes header");
    const uint64_t blocks = size_t64(h), n = size_t64(h.substr(8));
    if (n > c_.remaining() / 32 || blocks > c_.remaining() / 20)
      c_.fail("$Nodes announces more than the file holds");
    out_.points.reserve(n);
    for (uint64_t k = 0; k < blocks; ++k) {
      const std::string_view bh = c_.bytes(20, "a node block header");
      const int dim = int32(bh), parametric = int32(bh.substr(8));
      const uint64_t in_block = size_t64(bh.substr(12));
      if (dim < 0 || dim > 3 || parametric < 0 || parametric > 1) c_.fail("bad node block header");
      const uint64_t stride = 8 * (3 + static_cast<uint64_t>(dim) * parametric);
      if (in_block > c_.remaining() / (8 + stride)) c_.fail("file ends inside a node block");
      const std::string_view tags = c_.bytes(8 * in_block, "node tags");
      const size_t first = out_.points.size();
      for (uint64_t i = 0; i < in_block; ++i)
        add_node(static_cast<int64_t>(size_t64(tags.substr(8 * i))), first + i);
      const std::string_view xyz = c_.bytes(stride * in_block, "node coordinates");
      for (uint64_t i = 0; i < in_block; ++i) add_point(xyz.substr(stride * i, 24));
    }
    if (out_.points.size() != n)
      c_.fail("$Nodes announces " + std::to_string(n) + " nodes, its blocks hold " +
              std::to_string(out_.points.size()));
  }

  void elements_v4_binary() {
    c_.skip_to_next_line();
    const std::string_view h = c_.bytes(32, "the $Elements header");
    const uint64_t blocks = size_t64(h), n = size_t64(h.substr(8));
    if (blocks > c_.remaining() / 20) c_.fail("$Elements announces more than the file holds");
    uint64_t seen = 0;
    for (uint64_t k = 0; k < blocks; ++k) {
      const std::string_view bh = c_.bytes(20, "an element block header");
      const int entity = int32(bh.substr(4)), type = int32(bh.substr(8));
      const uint64_t in_block = size_t64(bh.substr(12));
      const int per = nodes_per_element(type);
      const uint64_t record = 8 * (1 + static_cast<uint64_t>(per));
      if (in_block > c_.remaining() / record) c_.fail("file ends inside an element block");
      if (is_tetrahedron(type) || is_triangle(type)) note_volume_tag(entity);
      const std::string_view b = c_.bytes(in_block * record, "the elements");
      if (is_tetrahedron(type) || is_triangle(type)) {
        binary_block(b, in_block, record, type);
      } else {
        for (uint64_t e = 0; e < in_block; ++e)
          binary_element(static_cast<int64_t>(size_t64(b.substr(e * record))),
                         b.substr(e * record + 8, record - 8), type, per, 8);
      }
      seen += in_block;
    }
    if (seen != n)
      c_.fail("$Elements announces " + std::to_string(n) + " elements, its blocks hold " +
              std::to_string(seen));
  }

  // The nodes of an element of this type; a binary file cannot be read
  // past a type whose count is not known.
  int nodes_per_element(int type) const {
    static const std::map<int, int> kNodes = {
        {1, 2},   {2, 3},   {3, 4},   {4, 4},   {5, 8},   {6, 6},   {7, 5},   {8, 3},   {9, 6},
        {10, 9},  {11, 10}, {12, 27}, {13, 18}, {14, 14}, {15, 1},  {16, 8},  {17, 20}, {18, 15},
        {19, 13}, {20, 9},  {21, 10}, {22, 12}, {23, 15}, {24, 15}, {25, 21}, {26, 4},  {27, 5},
        {28, 6},  {29, 20}, {30, 35}, {31, 56}, {92, 64}, {93, 125}};
    const auto it = kNodes.find(type);
    if (it == kNodes.end()) c_.fail("element type " + std::to_string(type) + " is not known to this reader");
    return it->second;
  }

  // A data section's string tags, one a line (gmsh quotes them; a name may
  // hold blanks): the first is the view's name.
  std::string view_name() {
    const int strings = c_.number<int>("a string tag count");
    std::string name;
    if (strings > 0) c_.skip_to_next_line();
    for (int i = 0; i < strings; ++i) {
      std::string_view s = c_.rest_of_line();
      while (!s.empty() && (s.back() == ' ' || s.back() == '\t' || s.back() == '\r')) s.remove_suffix(1);
      while (!s.empty() && (s.front() == ' ' || s.front() == '\t')) s.remove_prefix(1);
      if (s.empty()) c_.fail("expected a string tag");
      if (i == 0) name = s.size() >= 2 && s.front() == '"' && s.back() == '"' ? s.substr(1, s.size() - 2) : s;
    }
    return name;
  }

  // A view's values at the nodes: kept when it covers every node once.
  void node_data() {
    VertexField f;
    f.name = view_name();
    const int reals = c_.number<int>("a real tag count");
    for (int i = 0; i < reals; ++i) c_.number<double>("a real tag");
    const int ints = c_.number<int>("an integer tag count");
    if (ints < 3) c_.fail("$NodeData needs 3 integer tags (step, components, entries)");
    const int64_t step = c_.number<int64_t>("a time step");
    f.components = c_.number<int>("a component count");
    const uint64_t entries = c_.count("an entry count", c_.remaining() / 4);
    for (int i = 3; i < ints; ++i) c_.number<int64_t>("an integer tag");
    if (f.components < 1 || f.components > 9) c_.fail("bad component count");
    f.values.assign(out_.points.size() * f.components, 0.0);
    std::vector<uint8_t> seen(out_.points.size(), 0);
    uint64_t distinct = 0;
    if (binary_) {
      // (int node tag, components doubles) per entry.
      const uint64_t record = 4 + 8 * static_cast<uint64_t>(f.components);
      c_.skip_to_next_line();
      if (entries > c_.remaining() / record) c_.fail("$NodeData announces more than the file holds");
      const std::string_view b = c_.bytes(entries * record, "node data");
      for (uint64_t e = 0; e < entries; ++e) {
        const auto it = index_of_.find(int32(b.substr(e * record)));
        if (it == index_of_.end()) c_.fail("$NodeData names a node that does not exist");
        const uint32_t v = it->second;
        distinct += !seen[v];
        seen[v] = 1;
        for (int k = 0; k < f.components; ++k)
          f.values[v * f.components + k] = float64(b.substr(e * record + 4 + 8 * k));
      }
    } else {
      for (uint64_t e = 0; e < entries; ++e) {
        const std::string_view tag = c_.token("a node tag");
        const uint32_t v = node(tag);
        distinct += !seen[v];
        seen[v] = 1;
        for (int k = 0; k < f.components; ++k) f.values[v * f.components + k] = c_.number<double>("a value");
      }
    }
    if (distinct == out_.points.size()) release(seen);
    // A view of several time steps: one field a step (as $ElementData's).
    for (const NodeView& g : node_views_)
      if (g.field.name == f.name) f.name += " (step " + std::to_string(step) + ")";
    node_views_.push_back({std::move(f), std::move(seen), distinct});
  }

  // The views given at some nodes only: kept when the nodes they miss are
  // all second-order elements' edge nodes (a solver that writes its results
  // at the linear cells' corners), the stream then giving those nodes their
  // corners' mean; named as left out otherwise. Once the elements are read.
  void keep_node_views() {
    std::vector<uint8_t> role;
    for (NodeView& view : node_views_) {
      if (!view.seen.empty()) {
        if (role.empty()) role = node_roles(out_);
        bool corners = true;
        for (size_t v = 0; v < role.size() && corners; ++v)
          corners = (view.seen[v] != 0) == (role[v] != kNodeOnEdge);
        if (!corners) {
          partial_node_data_.push_back("'" + view.field.name + "' at " + std::to_string(view.distinct) +
                                       " of " + std::to_string(out_.points.size()) + " nodes");
          continue;
        }
        view.field.at_corners_only = true;
      }
      out_.fields.push_back(std::move(view.field));
    }
    release(node_views_);
  }

  // A view's values on the elements: kept as cell data when it covers every
  // tetrahedron once (entries on other elements are not the mesh's).
  void element_data() {
    VertexField f;
    f.name = view_name();
    const int reals = c_.number<int>("a real tag count");
    for (int i = 0; i < reals; ++i) c_.number<double>("a real tag");
    const int ints = c_.number<int>("an integer tag count");
    if (ints < 3) c_.fail("$ElementData needs 3 integer tags (step, components, entries)");
    const int64_t step = c_.number<int64_t>("a time step");
    f.components = c_.number<int>("a component count");
    const uint64_t entries = c_.count("an entry count", c_.remaining() / 4);
    for (int i = 3; i < ints; ++i) c_.number<int64_t>("an integer tag");
    if (f.components < 1 || f.components > 9) c_.fail("bad component count");
    const size_t tets = out_.tets.size();
    f.values.assign(tets * f.components, 0.0);
    std::vector<uint8_t> seen(tets, 0);
    uint64_t distinct = 0, elsewhere = 0;
    index_element_tags();
    const auto take = [&](int64_t tag, auto&& value) {
      const int64_t t = tet_of(tag);
      if (t < 0) {
        // Another element's (a triangle's flux): not the mesh's cell data,
        // said unless it is 0 or NaN, what a writer puts where it has no
        // value (meshdec's .msh on its tagged faces).
        bool says = false;
        for (int k = 0; k < f.components; ++k) says |= value(k) != 0 && !std::isnan(value(k));
        elsewhere += says;
        return;
      }
      distinct += !seen[t];
      seen[t] = 1;
      for (int k = 0; k < f.components; ++k) f.values[t * f.components + k] = value(k);
    };
    if (binary_) {
      const uint64_t record = 4 + 8 * static_cast<uint64_t>(f.components);
      c_.skip_to_next_line();
      if (entries > c_.remaining() / record) c_.fail("$ElementData announces more than the file holds");
      const std::string_view b = c_.bytes(entries * record, "element data");
      for (uint64_t e = 0; e < entries; ++e)
        take(int32(b.substr(e * record)), [&](int k) { return float64(b.substr(e * record + 4 + 8 * k)); });
    } else {
      for (uint64_t e = 0; e < entries; ++e) {
        const int64_t tag = c_.number<int64_t>("an element tag");
        std::array<double, 9> v{};
        for (int k = 0; k < f.components; ++k) v[k] = c_.number<double>("a value");
        take(tag, [&](int k) { return v[k]; });
      }
    }
    // A view of several time steps: one array a step.
    for (const VertexField& g : out_.cell_fields)
      if (g.name == f.name) f.name += " (step " + std::to_string(step) + ")";
    if (elsewhere > 0) element_data_elsewhere_.push_back("'" + f.name + "' at " + std::to_string(elsewhere));
    if (tets > 0 && distinct == tets)
      out_.cell_fields.push_back(std::move(f));
    else
      partial_element_data_.push_back("'" + f.name + "' at " + std::to_string(distinct) + " of " +
                                      std::to_string(tets) + " tetrahedra");
  }

  TextCursor c_;
  bool v4_ = false;
  bool binary_ = false;  // file type 1
  // What is not read into the mesh (InputMesh::left_out).
  std::map<int, uint64_t> other_elements_;  // by gmsh element type
  int64_t tag_ = 0;
  int64_t entity_ = 0;                            // 2.x: the element's elementary entity (its second tag)
  std::vector<int64_t> tet_entity_, tri_entity_;  // 2.x, per tetrahedron and triangle
  bool by_entities_ = false;            // 2.x without physical groups: the faces tagged by their entities
  bool tagged_ = false;                 // 2.x: some tetrahedron has tags
  std::vector<int64_t> tet_tag_;        // per tetrahedron
  std::map<int, int> volume_physical_;  // 4.1: volume entity -> its first physical group
  std::map<int32_t, std::string> volume_names_;
  std::vector<std::array<uint32_t, 3>> triangles_;
  std::vector<int64_t> tri_tag_;  // per triangle
  // Per triangle (or quadrangle), once a second-order one is read: its
  // nodes past its corners (kNoEdgeNode past its count).
  std::vector<std::array<uint32_t, 5>> face_edge_nodes_;
  std::vector<uint32_t> quad_fourth_;  // per triangle, once a quadrangle is read: its fourth corner
  // Each hexahedron, prism and pyramid read: its place in out_.tets, which
  // holds its first four corners, and all its corners, for split_cells();
  // in the order of their places. split_block_: where the block being read
  // starts in split_cells_ and in out_.tets.
  struct SplitCell {
    uint32_t slot = 0;
    uint8_t count = 0, extra = 0;  // corners, and other nodes (second order)
    std::array<uint32_t, 8> corners{};
    std::array<uint32_t, 19> extras{};
  };
  std::vector<SplitCell> split_cells_;
  std::pair<size_t, size_t> split_block_;
  std::map<int, int> surface_physical_;  // 4.1: surface entity -> its first physical group
  std::map<int32_t, std::string> surface_names_;
  // $NodeData in file order, each with the nodes it gives (empty: every
  // node) until keep_node_views().
  struct NodeView {
    VertexField field;
    std::vector<uint8_t> seen;
    uint64_t distinct = 0;
  };
  std::vector<NodeView> node_views_;
  std::vector<std::string> physical_names_, partial_node_data_, partial_element_data_,
      element_data_elsewhere_;  // $ElementData with values on triangles and other elements
  std::set<std::string> skipped_data_;
  // 4.1's $PartitionedEntities: their count, the partitions' entities'
  // parents, the surfaces between partitions.
  uint64_t partitions_ = 0, ghost_entities_ = 0;
  std::set<int> later_groups_[2];  // surfaces', volumes' physical groups after an entity's first
  std::map<int, int> volume_parent_, surface_parent_;
  std::set<int> interface_surfaces_;
  std::unordered_map<int64_t, uint32_t> index_of_;
  std::vector<int64_t> tet_element_;  // per tetrahedron: its element tag
  size_t indexed_ = 0;                // tetrahedra index_element_tags() has seen
  bool tags_ascend_ = true;
  std::vector<std::pair<int64_t, uint32_t>> by_element_;  // (tag, tetrahedron) ascending, unless they ascend
  InputMesh out_;
};

}  // namespace

InputMesh read_gmsh(const std::string& path) { return GmshReader(path).read(); }

namespace {

// Each label's physical tag: itself, but 0 (gmsh's "no physical group",
// which gmsh renumbers): the tag above the labels' largest.
template <class Labels>
std::map<int32_t, int64_t> physical_tags(const Labels& labels) {
  std::map<int32_t, int64_t> tag_of;
  for (int32_t label : labels) tag_of.emplace(label, label);
  int64_t next = std::max<int64_t>(0, tag_of.empty() ? 0 : tag_of.rbegin()->first);
  for (auto& [label, tag] : tag_of)
    if (label == 0) tag = ++next;
  return tag_of;
}

}  // namespace

std::vector<std::string> gmsh_renumbering(const OutputMesh& m) {
  std::vector<std::string> out;
  for (const auto& [label, tag] : physical_tags(m.region))
    if (tag != label)
      out.push_back("region " + std::to_string(label) + " as physical volume " + std::to_string(tag) +
                    " (gmsh's physical tag 0 is no group)");
  for (const auto& [label, tag] : physical_tags(m.face_tags))
    if (tag != label)
      out.push_back("face tag " + std::to_string(label) + " as physical surface " + std::to_string(tag) +
                    " (gmsh's physical tag 0 is no group)");
  return out;
}

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
  // One volume entity (tag 1) holds every node and tetrahedron; with
  // regions, one a region (tags 1, 2, ...), each in the physical group of
  // its label, and the nodes in the first.
  std::map<int32_t, size_t> entity_of;  // region label -> its entity's tag
  for (int32_t r : m.region) entity_of.emplace(r, 0);
  size_t entities = 0;
  for (auto& [label, entity] : entity_of) entity = ++entities;
  // The tagged faces: one surface entity a tag, in the physical group of
  // the tag.
  std::map<int32_t, size_t> surface_of;
  for (int32_t tag : m.face_tags) surface_of.emplace(tag, 0);
  size_t surfaces = 0;
  for (auto& [tag, entity] : surface_of) entity = ++surfaces;
  // Tagged faces without regions: the tetrahedra go in a physical volume of
  // their own (tag 1, "volume"). A volume entity in no physical group beside
  // surfaces in some is valid gmsh, but meshio's reader then gives
  // gmsh:physical fewer blocks than cells and refuses the file (gmsh's own
  // files with Mesh.SaveAll alike).
  const bool whole_volume_group = entity_of.empty() && !surface_of.empty();
  // (Each label's physical tag: gmsh_renumbering().)
  const std::map<int32_t, int64_t> volume_tag = physical_tags(m.region),
                                   surface_tag = physical_tags(m.face_tags);
  if (!entity_of.empty() || !surface_of.empty()) {
    out += "$PhysicalNames\n" +
           std::to_string(entity_of.size() + surface_of.size() + (whole_volume_group ? 1 : 0)) + "\n";
    for (const auto& [tag, entity] : surface_of) {
      const auto name = m.face_tag_names.find(tag);
      out += "2 " + std::to_string(surface_tag.at(tag)) + " \"" +
             (name != m.face_tag_names.end() ? name->second : "surface " + std::to_string(tag)) + "\"\n";
    }
    for (const auto& [label, entity] : entity_of) {
      const auto name = m.region_names.find(label);
      out += "3 " + std::to_string(volume_tag.at(label)) + " \"" +
             (name != m.region_names.end() ? name->second : "region " + std::to_string(label)) + "\"\n";
    }
    if (whole_volume_group) out += "3 1 \"volume\"\n";
    out += "$EndPhysicalNames\n";
  }
  // Per volume entity: its box (the mesh's), its physical groups, no
  // bounding surface.
  std::vector<std::string> physical(std::max<size_t>(1, entities), "0");
  for (const auto& [label, entity] : entity_of)
    physical[entity - 1] = "1 " + std::to_string(volume_tag.at(label));
  if (whole_volume_group) physical[0] = "1 1";
  out += "$Entities\n0 0 " + std::to_string(surfaces) + " " + std::to_string(physical.size()) + "\n";
  for (const auto& [tag, entity] : surface_of) {
    out += std::to_string(entity);
    for (double v : {lo.x, lo.y, lo.z, hi.x, hi.y, hi.z}) {
      out += ' ';
      append_number(out, v);
    }
    out += " 1 " + std::to_string(surface_tag.at(tag)) + " 0\n";
  }
  for (size_t e = 0; e < physical.size(); ++e) {
    out += std::to_string(e + 1);
    for (double v : {lo.x, lo.y, lo.z, hi.x, hi.y, hi.z}) {
      out += ' ';
      append_number(out, v);
    }
    out += " " + physical[e] + " 0\n";
  }
  // Each node's tag: the input's (22.0, --keep-order), else its number.
  const auto tag = [&](size_t i) {
    return m.node_labels.empty() ? static_cast<uint64_t>(i + 1) : static_cast<uint64_t>(m.node_labels[i]);
  };
  uint64_t least_tag = n ? 1 : 0, most_tag = n;
  if (!m.node_labels.empty()) {
    least_tag = static_cast<uint64_t>(*std::min_element(m.node_labels.begin(), m.node_labels.end()));
    most_tag = static_cast<uint64_t>(*std::max_element(m.node_labels.begin(), m.node_labels.end()));
  }
  out += "$EndEntities\n$Nodes\n";
  out += "1 " + std::to_string(n) + " " + std::to_string(least_tag) + " " + std::to_string(most_tag) + "\n";
  out += "3 1 0 " + std::to_string(n) + "\n";
  for (size_t i = 0; i < n; ++i) {
    append_number(out, tag(i));
    out += '\n';
  }
  for (const InputPoint& p : xyz) {
    append_xyz_line(out, p);
  }
  out += "$EndNodes\n$Elements\n";
  // One block a region (its entity's), cells numbered in the mesh's order.
  std::vector<std::vector<size_t>> blocks(std::max<size_t>(1, entities));
  for (size_t c = 0; c < t; ++c) blocks[m.region.empty() ? 0 : entity_of[m.region[c]] - 1].push_back(c);
  // The faces' blocks first (numbered after the cells), then the cells'.
  std::vector<std::vector<size_t>> face_blocks(surfaces);
  for (size_t f = 0; f < m.faces.size(); ++f) face_blocks[surface_of[m.face_tags[f]] - 1].push_back(f);
  // (A block holds one element type: second-order cells, gmsh's 10-node
  // tetrahedra and 6-node triangles, in blocks of their own.)
  const auto of_order = [](const std::vector<size_t>& items, const auto& nodes_of, bool second) {
    std::vector<std::pair<size_t, ListedNodes>> out;
    for (size_t i : items)
      if (const ListedNodes e = nodes_of(i); e.second_order() == second) out.emplace_back(i, e);
    return out;
  };
  const auto cell_nodes_of = [&](size_t c) { return cell_nodes(m, c, kGmshEdgeSlots); };
  const auto face_nodes_of = [&](size_t f) { return face_nodes(m, f); };
  struct Block {
    int dimension;
    size_t entity;
    int type;
    std::vector<std::pair<size_t, ListedNodes>> elements;
  };
  std::vector<Block> written;
  for (size_t e = 0; e < face_blocks.size(); ++e)
    for (const bool second : {false, true})
      if (auto items = of_order(face_blocks[e], face_nodes_of, second);
          !items.empty() || (!second && m.edge_nodes == 0))
        written.push_back({2, e + 1, second ? 9 : 2, std::move(items)});
  for (size_t e = 0; e < blocks.size(); ++e)
    for (const bool second : {false, true})
      if (auto items = of_order(blocks[e], cell_nodes_of, second);
          !items.empty() || (!second && m.edge_nodes == 0))
        written.push_back({3, e + 1, second ? 11 : 4, std::move(items)});
  const size_t elements = t + m.faces.size();
  out += std::to_string(written.size()) + " " + std::to_string(elements) + " " +
         std::to_string(elements ? 1 : 0) + " " + std::to_string(elements) + "\n";
  for (const Block& b : written) {
    out += std::to_string(b.dimension) + " " + std::to_string(b.entity) + " " + std::to_string(b.type) + " " +
           std::to_string(b.elements.size()) + "\n";
    for (const auto& [i, e] : b.elements) {
      append_number(out, (b.dimension == 2 ? t : 0) + i + 1);
      for (size_t k = 0; k < e.count; ++k) {
        out += ' ';
        append_number(out, tag(e.nodes[k]));
      }
      out += '\n';
    }
  }
  out += "$EndElements\n";
  auto node_data = [&](const char* name, const auto& values) {
    if (values.empty()) return;
    out += "$NodeData\n1\n\"" + std::string(name) + "\"\n1\n0\n3\n0\n1\n" + std::to_string(n) + "\n";
    for (size_t i = 0; i < n; ++i) {
      append_number(out, tag(i));
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
      append_number(out, tag(i));
      for (int c = 0; c < f.components; ++c) {
        out += ' ';
        append_scalar_text(out, f.bits[i * f.components + c], f.type);
      }
      out += '\n';
    }
    out += "$EndNodeData\n";
  }
  // Cell data, an entry for every element in the order $Elements lists them
  // (meshio's reader takes the entries in that order, whatever their tags):
  // a tagged face's 0, then each tetrahedron's values.
  for (const OutputField& f : m.cell_fields) {
    if (f.components != 1 && f.components != 3 && f.components != 9) continue;
    out += "$ElementData\n1\n\"" + f.name + "\"\n1\n0\n3\n0\n" + std::to_string(f.components) + "\n" +
           std::to_string(elements) + "\n";
    for (const auto& block : face_blocks)
      for (size_t face : block) {
        append_number(out, t + face + 1);
        for (int k = 0; k < f.components; ++k) out += " 0";
        out += '\n';
      }
    for (const auto& block : blocks)
      for (size_t c : block) {
        append_number(out, c + 1);
        for (int k = 0; k < f.components; ++k) {
          out += ' ';
          append_scalar_text(out, f.bits[c * f.components + k], f.type);
        }
        out += '\n';
      }
    out += "$EndElementData\n";
  }
  return out;
}

}  // namespace dtm
