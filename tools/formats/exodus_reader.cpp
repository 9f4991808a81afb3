// The Exodus II reader (exodus.h): element blocks as regions or tagged
// faces, side sets as tagged faces, node sets and variables as fields.
#include <exodusII.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <span>
#include <sstream>
#include <string>
#include <vector>

#include "abaqus.h"  // kNodeSetFieldPrefix
#include "cell_split.h"
#include "exodus.h"
#include "exodus_file.h"
#include "format_error.h"
#include "node_labels.h"
#include "second_order.h"
#include "tagged_faces.h"

namespace dtm {
namespace {

using exodus::ElementType;
using exodus::Shape;

// A stream holds 32 fields, each named in 64 bytes.
constexpr size_t kMaxFields = 32, kMaxFieldName = 64;

std::string joined(const std::vector<std::string>& names) {
  std::string out;
  const size_t shown = std::min<size_t>(names.size(), 8);
  for (size_t i = 0; i < shown; ++i) out += (i ? ", " : "") + names[i];
  if (names.size() > shown) out += " and " + std::to_string(names.size() - shown) + " more";
  return out;
}

// `name`, or where one of `fields` has it already, name_2, name_3, ...
// (two node sets of one name, a scalar X beside a vector X_x X_y X_z).
std::string unique_name(const std::vector<VertexField>& fields, const std::string& name) {
  const auto taken = [&](const std::string& n) {
    return std::any_of(fields.begin(), fields.end(), [&](const VertexField& f) { return f.name == n; });
  };
  std::string out = name;
  for (int k = 2; taken(out); ++k) out = name + "_" + std::to_string(k);
  return out;
}

// An element block as read: what the side sets and element variables refer to.
struct Block {
  int64_t id = 0;
  std::string name;
  std::string type;
  ElementType shape;
  int64_t count = 0, nodes_per = 0;
  int64_t first = 0;                // its first element's 0-based number in the file
  std::vector<uint32_t> nodes;      // 0-based, nodes_per an element (the blocks the codec reads)
  std::vector<uint64_t> made;       // per element: the first tetrahedron or face it made
  std::vector<uint8_t> made_count;  // and how many
  bool solid() const {
    return shape.shape == Shape::kTetrahedron || shape.shape == Shape::kPyramid ||
           shape.shape == Shape::kWedge || shape.shape == Shape::kHexahedron;
  }
  bool face() const { return shape.shape == Shape::kTriangle || shape.shape == Shape::kQuadrilateral; }
  std::string shown() const {
    return "element block " + std::to_string(id) + (name.empty() ? "" : " '" + name + "'");
  }
};

class Reader {
 public:
  Reader(const std::string& path, int time_step)
      : path_(path), file_(exodus::File::open(path)), time_step_(time_step) {
    // What a count may claim: the file's bytes, or 1100 times them where
    // netCDF-4 may have compressed them (zlib's most).
    std::ifstream in(path, std::ios::binary);
    char magic[4] = {};
    in.read(magic, 4);
    const uint64_t size = std::filesystem::file_size(path);
    budget_ = (std::memcmp(magic + 1, "HDF", 3) == 0 ? 1100 : 1) * size + 4096;
    objects_budget_ = size + 4096;
  }

  InputMesh read() {
    ex_init_params p{};
    file_.check(ex_get_init_ext(file_.id(), &p), "its sizes");
    if (p.num_dim != 3)
      throw FormatError(path_ + ": a " + std::to_string(p.num_dim) +
                        "D mesh (num_dim): the codec holds solids in 3D");
    read_nodes(p.num_nodes);
    read_blocks(p.num_elem_blk);
    read_side_sets(p.num_side_sets);
    read_variables();
    read_node_sets(p.num_node_sets);
    name_the_rest(p);
    return std::move(out_);
  }

 private:
  // Throws unless `count` items of `bytes` each could be in the file.
  // Throws unless `count` blocks, sets or variables could be in the file:
  // each takes 64 bytes of its header at least (its dimensions' and
  // variables' names and shapes, which netCDF-4 does not compress either),
  // and costs a name's buffer (256 bytes) here.
  size_t counted_objects(int64_t count, const std::string& what) const {
    if (count < 0 || static_cast<uint64_t>(count) > objects_budget_ / 64)
      throw FormatError(path_ + ": " + what + ": " + std::to_string(count) +
                        " claimed, more than the file can hold");
    return static_cast<size_t>(count);
  }

  size_t counted(int64_t count, size_t bytes, const std::string& what) const {
    if (count < 0 || static_cast<uint64_t>(count) > budget_ / bytes)
      throw FormatError(path_ + ": " + what + ": " + std::to_string(count) +
                        " claimed, more than the file can hold");
    return static_cast<size_t>(count);
  }

  std::vector<int64_t> ids(ex_entity_type type, int64_t count, const std::string& what) {
    std::vector<int64_t> out(counted_objects(count, what));
    if (!out.empty()) file_.require(ex_get_ids(file_.id(), type, out.data()), what + "' ids");
    return out;
  }

  // `count` names as libexodusii's `get` fills their buffers, trailing
  // blanks trimmed.
  template <class Get>
  static std::vector<std::string> names_from(size_t count, const Get& get) {
    std::vector<std::vector<char>> buffers(count, std::vector<char>(exodus::kNameLength + 1, '\0'));
    std::vector<char*> pointers;
    pointers.reserve(count);
    for (auto& b : buffers) pointers.push_back(b.data());
    if (count > 0) get(pointers.data());
    std::vector<std::string> out;
    out.reserve(count);
    for (auto& b : buffers) {
      b.back() = '\0';
      std::string s = b.data();
      while (!s.empty() && s.back() == ' ') s.pop_back();
      out.push_back(std::move(s));
    }
    return out;
  }

  std::vector<std::string> names(ex_entity_type type, size_t count, const std::string& what) {
    return names_from(count,
                      [&](char** p) { file_.check(ex_get_names(file_.id(), type, p), what + "' names"); });
  }

  int32_t label(int64_t id, const std::string& what) const {
    if (id < INT32_MIN || id > INT32_MAX)
      throw FormatError(path_ + ": " + what + " has the id " + std::to_string(id) +
                        ", beyond the 32-bit labels a stream holds");
    return static_cast<int32_t>(id);
  }

  void read_nodes(int64_t count) {
    const size_t n = counted(count, 12, "nodes");  // (3 floats at least)
    std::vector<double> x(n), y(n), z(n);
    if (n > 0)
      file_.require(ex_get_coord(file_.id(), x.data(), y.data(), z.data()), "the nodes' coordinates");
    out_.points.resize(n);
    for (size_t i = 0; i < n; ++i) {
      if (!std::isfinite(x[i]) || !std::isfinite(y[i]) || !std::isfinite(z[i]))
        throw FormatError(path_ + ": node " + std::to_string(i + 1) + " is not finite");
      out_.points[i] = {x[i], y[i], z[i]};
    }
  }

  void read_blocks(int64_t count) {
    const std::vector<int64_t> block_ids = ids(EX_ELEM_BLOCK, count, "element blocks");
    const std::vector<std::string> block_names = names(EX_ELEM_BLOCK, block_ids.size(), "element blocks");
    int64_t first = 0;
    blocks_.reserve(block_ids.size());  // (face_blocks_ points into it)
    for (size_t b = 0; b < block_ids.size(); ++b) {
      Block& k = blocks_.emplace_back();
      k.id = block_ids[b];
      k.name = block_names[b];
      char type[MAX_STR_LENGTH + 1] = {};
      int64_t edges = 0, faces = 0, attributes = 0;
      file_.require(ex_get_block(file_.id(), EX_ELEM_BLOCK, k.id, type, &k.count, &k.nodes_per, &edges,
                                 &faces, &attributes),
                    k.shown());
      type[MAX_STR_LENGTH] = '\0';
      k.type = type;
      k.first = first;
      first += static_cast<int64_t>(counted(k.count, 1, k.shown() + "'s elements"));
      k.shape = exodus::element_type(k.type, k.nodes_per);
      if (attributes > 0) attributed_.push_back(k.shown());
      if (k.count == 0) continue;
      if (k.shape.shape == Shape::kOther) {
        other_blocks_.push_back(k.shown() + " (" + std::to_string(k.count) + " " + k.type + ")");
        continue;
      }
      if (k.nodes_per > 64)
        throw FormatError(path_ + ": " + k.shown() + ": " + std::to_string(k.nodes_per) +
                          " nodes an element " + k.type);
      std::vector<int64_t> conn(counted(k.count, static_cast<size_t>(k.nodes_per) * 4, k.shown()) *
                                static_cast<size_t>(k.nodes_per));
      file_.require(ex_get_conn(file_.id(), EX_ELEM_BLOCK, k.id, conn.data(), nullptr, nullptr),
                    k.shown() + "'s connectivity");
      k.nodes.resize(conn.size());
      for (size_t i = 0; i < conn.size(); ++i) {
        if (conn[i] < 1 || static_cast<uint64_t>(conn[i]) > out_.points.size())
          throw FormatError(path_ + ": " + k.shown() + ": element " + std::to_string(i / k.nodes_per + 1) +
                            " names node " + std::to_string(conn[i]) + " of " +
                            std::to_string(out_.points.size()));
        k.nodes[i] = static_cast<uint32_t>(conn[i] - 1);
      }
      add_elements(k);
    }
  }

  // The block's elements as tetrahedra (regions: the block's id) or faces.
  void add_elements(Block& k) {
    const size_t per = static_cast<size_t>(k.nodes_per);
    k.made.resize(static_cast<size_t>(k.count));
    k.made_count.resize(static_cast<size_t>(k.count));
    if (k.solid()) {
      const int32_t region = label(k.id, k.shown());
      if (!k.name.empty()) out_.region_names[region] = k.name;
      if (k.shape.shape != Shape::kTetrahedron) split_[static_cast<size_t>(k.shape.corners)] += k.count;
    } else {
      face_blocks_.push_back(&k);
    }
    for (size_t e = 0; e < static_cast<size_t>(k.count); ++e) {
      const std::span<const uint32_t> nodes(k.nodes.data() + e * per, per);
      k.made[e] = k.solid() ? out_.tets.size() : out_.tagged_faces.size();
      size_t added = 0;
      if (k.shape.shape == Shape::kTetrahedron) {
        out_.tets.push_back({nodes[0], nodes[1], nodes[2], nodes[3]});
        added = 1;
        if (per == 10) {
          std::array<uint32_t, 6> edge{};
          for (size_t s = 0; s < 6; ++s) edge[s] = nodes[static_cast<size_t>(exodus::kTet10EdgeSlots[s])];
          add_tet_edge_nodes(out_, edge);  // (counted there as a second-order tetrahedron)
        } else if (per > 4) {
          out_.other_edge_nodes.insert(out_.other_edge_nodes.end(), nodes.begin() + 4, nodes.end());
          ++out_.second_order_cells;
        }
      } else if (k.shape.shape == Shape::kTriangle) {
        out_.tagged_faces.push_back({nodes[0], nodes[1], nodes[2]});
        out_.other_edge_nodes.insert(out_.other_edge_nodes.end(), nodes.begin() + 3, nodes.end());
        added = 1;
      } else {
        added = add_split_cell(nodes, static_cast<size_t>(k.shape.corners), out_);
      }
      k.made_count[e] = static_cast<uint8_t>(added);
      if (k.solid()) out_.tet_regions.resize(out_.tets.size(), label(k.id, k.shown()));
    }
    // (The faces' tags come with the side sets', read_side_sets().)
    if (k.face())
      face_block_tags_.resize(out_.tagged_faces.size(), static_cast<int32_t>(face_blocks_.size() - 1));
  }

  const Block* block_of(int64_t element) const {
    const auto it = std::upper_bound(blocks_.begin(), blocks_.end(), element,
                                     [](int64_t e, const Block& b) { return e < b.first; });
    if (it == blocks_.begin()) return nullptr;
    const Block& b = *std::prev(it);
    return element < b.first + b.count ? &b : nullptr;
  }

  // Side sets first (their ids the tags), then the face blocks (their ids,
  // moved past the side sets' where two meet); a face tagged twice keeps
  // its first tag.
  void read_side_sets(int64_t count) {
    const std::vector<int64_t> set_ids = ids(EX_SIDE_SET, count, "side sets");
    const std::vector<std::string> set_names = names(EX_SIDE_SET, set_ids.size(), "side sets");
    std::vector<std::array<uint32_t, 3>> faces;
    std::vector<int32_t> tags;
    uint64_t edge_sides = 0, other_sides = 0, factors = 0;
    int32_t largest = 0;
    std::set<int32_t> used;
    for (size_t s = 0; s < set_ids.size(); ++s) {
      const std::string shown =
          "side set " + std::to_string(set_ids[s]) + (set_names[s].empty() ? "" : " '" + set_names[s] + "'");
      const int32_t tag = label(set_ids[s], shown);
      used.insert(tag);
      largest = std::max(largest, tag);
      if (!set_names[s].empty()) out_.face_tag_names[tag] = set_names[s];
      int64_t n = 0, df = 0;
      file_.require(ex_get_set_param(file_.id(), EX_SIDE_SET, set_ids[s], &n, &df), shown);
      factors += df > 0;
      std::vector<int64_t> elements(counted(n, 8, shown)), sides(elements.size());
      if (elements.empty()) continue;
      file_.require(ex_get_set(file_.id(), EX_SIDE_SET, set_ids[s], elements.data(), sides.data()), shown);
      for (size_t i = 0; i < elements.size(); ++i) {
        const Block* b = elements[i] >= 1 ? block_of(elements[i] - 1) : nullptr;
        if (!b)
          throw FormatError(path_ + ": " + shown + " names element " + std::to_string(elements[i]) +
                            ", which the file does not define");
        if (b->nodes.empty()) {
          ++other_sides;
          continue;
        }
        // (A QUAD's sides are its edges.)
        const exodus::Side side = b->face() && !b->shape.faces_are_sides
                                      ? exodus::Side{}
                                      : exodus::side_of(b->shape.shape, sides[i]);
        if (side.count == 0) {
          const int64_t first_edge = b->shape.faces_are_sides ? 3 : 1;
          if (b->face() && sides[i] >= first_edge && sides[i] < first_edge + b->shape.corners) {
            ++edge_sides;
            continue;
          }
          throw FormatError(path_ + ": " + shown + ": element " + std::to_string(elements[i]) + " (" +
                            b->type + ") has no side " + std::to_string(sides[i]));
        }
        const size_t e = static_cast<size_t>(elements[i] - 1 - b->first);
        const uint32_t* nodes = b->nodes.data() + e * static_cast<size_t>(b->nodes_per);
        std::array<uint32_t, 4> c{};
        for (int k = 0; k < side.count; ++k)
          c[static_cast<size_t>(k)] = nodes[side.slots[static_cast<size_t>(k)]];
        if (side.count == 3) {
          faces.push_back({c[0], c[1], c[2]}), tags.push_back(tag);
        } else {
          for (const auto& half : split_quad(c)) faces.push_back(half), tags.push_back(tag);
        }
      }
    }
    if (edge_sides)
      notes_.push_back(std::to_string(edge_sides) + " sides of 2D elements that are their edges");
    if (other_sides)
      notes_.push_back(std::to_string(other_sides) + " sides of elements other than solids and shells");
    if (factors) notes_.push_back("the distribution factors of " + std::to_string(factors) + " side sets");
    // The face blocks' faces, tagged by their blocks' ids.
    bool meet = false;
    for (const Block* b : face_blocks_) meet |= used.count(label(b->id, b->shown())) > 0;
    const int32_t shift = meet ? largest : 0;
    if (meet)
      notes_.push_back("the face blocks' ids as tags: each is moved by " + std::to_string(shift) +
                       ", past the side sets' ids");
    for (size_t f = 0; f < out_.tagged_faces.size(); ++f) {
      const Block* b = face_blocks_[static_cast<size_t>(face_block_tags_[f])];
      const int32_t tag = label(int64_t{label(b->id, b->shown())} + shift, b->shown());
      faces.push_back(out_.tagged_faces[f]), tags.push_back(tag);
      if (!b->name.empty()) out_.face_tag_names.emplace(tag, b->name);
    }
    out_.tagged_faces.clear();
    if (std::string note = add_tagged_faces_once(out_, faces, tags); !note.empty())
      notes_.push_back(std::move(note));
    if (!out_.tagged_faces.empty()) out_.face_tag_source = "side sets and face blocks";
  }

  // The nodal and element variables at the time step asked (the last
  // without --time-step).
  void read_variables() {
    const int64_t steps = ex_inquire_int(file_.id(), EX_INQ_TIME);
    int nodal = 0, element = 0, global = 0;
    file_.check(ex_get_variable_param(file_.id(), EX_NODAL, &nodal), "its nodal variables");
    file_.check(ex_get_variable_param(file_.id(), EX_ELEM_BLOCK, &element), "its element variables");
    file_.check(ex_get_variable_param(file_.id(), EX_GLOBAL, &global), "its global variables");
    counted_objects(int64_t{nodal} + element, "variables");
    if (global > 0) notes_.push_back(std::to_string(global) + " global variables");
    if (time_step_ > 0 && time_step_ > steps)
      throw FormatError(path_ + ": time step " + std::to_string(time_step_) + " asked, the file has " +
                        std::to_string(std::max<int64_t>(steps, 0)));
    if (nodal + element == 0) return;
    if (steps <= 0) {
      notes_.push_back("its variables' names (no time step holds values)");
      return;
    }
    const int step = time_step_ > 0 ? time_step_ : static_cast<int>(std::min<int64_t>(steps, INT32_MAX));
    double time = 0;
    file_.require(ex_get_time(file_.id(), step, &time), "its time step " + std::to_string(step));
    std::ostringstream read;
    read << time;
    if (steps > 1)
      notes_.push_back("the variables at its " + std::to_string(steps - 1) + " other time steps (time step " +
                       std::to_string(step) + " of " + std::to_string(steps) + ", time " + read.str() +
                       ", is read; --time-step chooses)");
    else if (time != 0)
      notes_.push_back("the time of its one time step, " + read.str());
    const ScalarType type = file_.io_word_size() == 4 ? ScalarType::kFloat32 : ScalarType::kFloat64;
    // Nodal variables, X_x X_y X_z as one vector.
    const std::vector<std::string> nodal_names = var_names(EX_NODAL, nodal);
    const size_t n = out_.points.size();
    std::vector<std::string> unkept;
    for (size_t j = 0; j < nodal_names.size();) {
      const std::string vector = vector_at(nodal_names, j);
      const size_t components = vector.empty() ? 1 : 3;
      VertexField f;
      f.name = unique_name(out_.fields, vector.empty() ? nodal_names[j] : vector);
      f.components = static_cast<int>(components);
      f.type = type;
      if (out_.fields.size() >= kMaxFields || f.name.size() > kMaxFieldName || f.name.empty()) {
        unkept.push_back("'" + nodal_names[j] + "'");
        j += components;
        continue;
      }
      f.values.resize(n * components);
      std::vector<double> v(n);
      bool found = true;
      for (size_t c = 0; c < components && found; ++c) {
        const int rc = n == 0 ? 0
                              : ex_get_var(file_.id(), step, EX_NODAL, static_cast<int>(j + c + 1), 1,
                                           static_cast<int64_t>(n), v.data());
        file_.check(rc, "nodal variable '" + nodal_names[j + c] + "'");
        found = rc == 0;
        for (size_t i = 0; i < n; ++i) f.values[i * components + c] = v[i];
      }
      if (found) {
        out_.fields.push_back(std::move(f));
      } else {
        unfound_.push_back("'" + nodal_names[j] + "'");
      }
      j += components;
    }
    if (!unkept.empty())
      notes_.push_back("nodal variables " + joined(unkept) +
                       " (a stream holds 32 fields, each named in 64 bytes)");
    read_element_variables(step, element, type);
  }

  // The name of a vector whose components are named X_x, X_y, X_z or Xx,
  // Xy, Xz (either case; ParaView writes "uX") at j, j + 1, j + 2: X; empty
  // for none.
  static std::string vector_at(const std::vector<std::string>& v, size_t j) {
    if (j + 2 >= v.size()) return {};
    const std::string stem = v[j].substr(0, v[j].size() - 1);
    for (size_t c = 0; c < 3; ++c) {
      const std::string& s = v[j + c];
      if (s.size() < 2 || std::tolower(static_cast<unsigned char>(s.back())) != "xyz"[c] ||
          s.compare(0, s.size() - 1, stem) != 0 || s.size() - 1 != stem.size())
        return {};
    }
    std::string name = stem;
    if (!name.empty() && name.back() == '_') name.pop_back();
    return name;
  }

  std::vector<std::string> var_names(ex_entity_type type, int count) {
    std::vector<std::string> out = names_from(static_cast<size_t>(std::max(count, 0)), [&](char** p) {
      file_.check(ex_get_variable_names(file_.id(), type, count, p), "variable names");
    });
    for (size_t i = 0; i < out.size(); ++i)
      if (out[i].empty()) out[i] = "variable_" + std::to_string(i + 1);
    return out;
  }

  // An element variable on every solid block is cell data: each tetrahedron
  // its element's value.
  void read_element_variables(int step, int count, ScalarType type) {
    if (count <= 0) return;
    const std::vector<std::string> var = var_names(EX_ELEM_BLOCK, count);
    if (!blocks_.empty() && static_cast<uint64_t>(count) > budget_ / 4 / blocks_.size())
      throw FormatError(path_ + ": the element variables' truth table: " + std::to_string(blocks_.size()) +
                        " by " + std::to_string(count) + " claimed, more than the file can hold");
    std::vector<int> truth(blocks_.size() * static_cast<size_t>(count), 1);
    if (!blocks_.empty())
      file_.check(ex_get_truth_table(file_.id(), EX_ELEM_BLOCK, static_cast<int>(blocks_.size()), count,
                                     truth.data()),
                  "the element variables' truth table");
    std::vector<std::string> partial, on_faces, unkept;
    const auto defined_on_every_solid = [&](size_t j) {
      bool everywhere = true;
      for (size_t b = 0; b < blocks_.size(); ++b)
        if (blocks_[b].solid() && blocks_[b].count > 0) everywhere &= truth[b * var.size() + j] != 0;
      return everywhere && !out_.tets.empty();
    };
    for (size_t j = 0; j < var.size(); ++j)
      for (size_t b = 0; b < blocks_.size(); ++b)
        if (blocks_[b].face() && blocks_[b].count > 0 && truth[b * var.size() + j] != 0) {
          on_faces.push_back("'" + var[j] + "'");
          break;
        }
    for (size_t j = 0; j < var.size();) {
      // (X_x X_y X_z as one vector, where all three are on every solid.)
      const std::string vector = vector_at(var, j);
      const size_t components =
          !vector.empty() && defined_on_every_solid(j + 1) && defined_on_every_solid(j + 2) ? 3 : 1;
      if (!defined_on_every_solid(j)) {
        partial.push_back("'" + var[j] + "'");
        ++j;
        continue;
      }
      VertexField f;
      f.name = unique_name(out_.cell_fields, components == 3 ? vector : var[j]);
      if (out_.cell_fields.size() >= kMaxFields || f.name.size() > kMaxFieldName || f.name.empty()) {
        unkept.push_back("'" + var[j] + "'");
        j += components;
        continue;
      }
      f.components = static_cast<int>(components);
      f.type = type;
      f.values.resize(out_.tets.size() * components);
      bool found = true;
      for (size_t c = 0; c < components; ++c)
        for (size_t b = 0; b < blocks_.size(); ++b) {
          const Block& k = blocks_[b];
          if (!k.solid() || k.count == 0) continue;
          std::vector<double> v(static_cast<size_t>(k.count));
          const int rc = ex_get_var(file_.id(), step, EX_ELEM_BLOCK, static_cast<int>(j + c + 1), k.id,
                                    k.count, v.data());
          file_.check(rc, "element variable '" + var[j + c] + "' on " + k.shown());
          found &= rc == 0;
          for (size_t e = 0; e < v.size(); ++e)
            for (size_t t = 0; t < k.made_count[e]; ++t) f.values[(k.made[e] + t) * components + c] = v[e];
        }
      if (found) {
        out_.cell_fields.push_back(std::move(f));
      } else {
        unfound_.push_back("'" + var[j] + "'");
      }
      j += components;
    }
    if (!partial.empty())
      notes_.push_back("element variables " + joined(partial) +
                       " (not on every solid block: the stream holds cell data on every cell)");
    if (!on_faces.empty()) notes_.push_back("element variables " + joined(on_faces) + " on the face blocks");
    if (!unkept.empty())
      notes_.push_back("element variables " + joined(unkept) +
                       " (a stream holds 32 cell arrays, each named in 64 bytes)");
  }

  // Each node set a 0/1 field, as many as the stream holds.
  void read_node_sets(int64_t count) {
    const std::vector<int64_t> set_ids = ids(EX_NODE_SET, count, "node sets");
    const std::vector<std::string> set_names = names(EX_NODE_SET, set_ids.size(), "node sets");
    std::vector<std::string> unkept;
    uint64_t factors = 0;
    // The ids the sets kept get again in meshdec's .e: an unnamed set's is
    // its name, a named set's the next free one.
    std::vector<int64_t> labels;
    std::vector<size_t> kept;
    for (size_t s = 0; s < set_ids.size(); ++s) {
      const std::string shown =
          "node set " + std::to_string(set_ids[s]) + (set_names[s].empty() ? "" : " '" + set_names[s] + "'");
      const std::string name =
          unique_name(out_.fields, kNodeSetFieldPrefix +
                                       (set_names[s].empty() ? std::to_string(set_ids[s]) : set_names[s]));
      if (out_.fields.size() >= kMaxFields || name.size() > kMaxFieldName) {
        unkept.push_back(set_names[s].empty() ? std::to_string(set_ids[s]) : set_names[s]);
        continue;
      }
      int64_t n = 0, df = 0;
      file_.require(ex_get_set_param(file_.id(), EX_NODE_SET, set_ids[s], &n, &df), shown);
      factors += df > 0;
      std::vector<int64_t> nodes(counted(n, 4, shown));
      if (!nodes.empty())
        file_.require(ex_get_set(file_.id(), EX_NODE_SET, set_ids[s], nodes.data(), nullptr), shown);
      VertexField f;
      f.name = name;
      f.type = ScalarType::kUInt8;
      f.values.assign(out_.points.size(), 0.0);
      for (int64_t v : nodes) {
        if (v < 1 || static_cast<uint64_t>(v) > out_.points.size())
          throw FormatError(path_ + ": " + shown + " names node " + std::to_string(v) + " of " +
                            std::to_string(out_.points.size()));
        f.values[static_cast<size_t>(v - 1)] = 1;
      }
      out_.fields.push_back(std::move(f));
      // (As render_exodus() reads the name back: a number is the id.)
      const std::string after = name.substr(std::string(kNodeSetFieldPrefix).size());
      const bool number =
          !after.empty() && after.size() < 10 && std::all_of(after.begin(), after.end(), ::isdigit);
      labels.push_back(number ? std::stoll(after) : 0);
      kept.push_back(s);
    }
    const std::vector<int64_t> again = exodus_ids(labels);
    std::vector<std::string> renumbered;
    for (size_t k = 0; k < kept.size(); ++k)
      if (again[k] != set_ids[kept[k]])
        renumbered.push_back(std::to_string(set_ids[kept[k]]) +
                             (set_names[kept[k]].empty() ? "" : " '" + set_names[kept[k]] + "'") + " as " +
                             std::to_string(again[k]));
    if (!renumbered.empty())
      notes_.push_back("the ids of node sets " + joined(renumbered) +
                       " (the stream keeps a node set's name, or its id where it has none)");
    if (!unkept.empty())
      notes_.push_back("node sets " + joined(unkept) +
                       " (a stream holds 32 fields, each named in 64 bytes: nset:NAME)");
    if (factors) notes_.push_back("the distribution factors of " + std::to_string(factors) + " node sets");
  }

  void name_the_rest(const ex_init_params& p) {
    if (!out_.tets.empty() && !blocks_.empty()) out_.region_source = "element blocks";
    if (const std::string note = split_cells_note(split_); !note.empty()) out_.left_out.push_back(note);
    if (!other_blocks_.empty()) out_.left_out.push_back(joined(other_blocks_));
    if (!attributed_.empty()) out_.left_out.push_back("the element attributes of " + joined(attributed_));
    const auto some = [&](int64_t n, const char* what) {
      if (n > 0) out_.left_out.push_back(std::to_string(n) + " " + what);
    };
    some(p.num_edge_blk, "edge blocks");
    some(p.num_face_blk, "face blocks (Exodus's, of faces apart from elements)");
    some(p.num_elem_sets, "element sets");
    some(p.num_edge_sets, "edge sets");
    some(p.num_face_sets, "face sets");
    some(p.num_node_maps + p.num_elem_maps + p.num_edge_maps + p.num_face_maps, "number maps");
    // (The node ids are kept with --keep-order, node_labels.h.)
    if (std::vector<int64_t> map = id_map(EX_NODE_MAP, p.num_nodes); !map.empty())
      set_node_labels(out_, std::move(map));
    if (!id_map(EX_ELEM_MAP, p.num_elem).empty())
      out_.left_out.emplace_back("the element ids (its element number map; the mesh is numbered 1..n)");
    int vars = 0;
    for (const auto type : {EX_NODE_SET, EX_SIDE_SET})
      if (ex_get_variable_param(file_.id(), type, &vars) >= 0 && vars > 0)
        out_.left_out.push_back(std::to_string(vars) + (type == EX_NODE_SET ? " node set" : " side set") +
                                " variables");
    // (Each has its id as its first property.)
    int64_t properties = 0;
    for (const auto inquiry : {EX_INQ_EB_PROP, EX_INQ_NS_PROP, EX_INQ_SS_PROP})
      properties += std::max<int64_t>(ex_inquire_int(file_.id(), inquiry) - 1, 0);
    if (properties > 0)
      out_.left_out.push_back(std::to_string(properties) +
                              " properties of the element blocks, node sets and side sets besides their ids");
    const int64_t qa = ex_inquire_int(file_.id(), EX_INQ_QA), info = ex_inquire_int(file_.id(), EX_INQ_INFO);
    if (qa > 0 || info > 0)
      out_.left_out.push_back(std::to_string(std::max<int64_t>(qa, 0)) + " QA records and " +
                              std::to_string(std::max<int64_t>(info, 0)) + " information records");
    if (!unfound_.empty())
      out_.left_out.push_back("variables " + joined(unfound_) +
                              ": named, but libexodusii 6.02 finds no values (a file that stores one "
                              "variable an array without Exodus's file_size attribute, as meshio writes "
                              "them: read it through Python, docs/FORMATS.md)");
    for (std::string& n : notes_) out_.left_out.push_back(std::move(n));
  }

  // A number map, or empty where it is 1..n (as a file without one has it).
  std::vector<int64_t> id_map(ex_entity_type type, int64_t count) {
    std::vector<int64_t> map(counted(count, 4, "a number map"));
    if (map.empty() || ex_get_id_map(file_.id(), type, map.data()) < 0) return {};
    for (size_t i = 0; i < map.size(); ++i)
      if (map[i] != static_cast<int64_t>(i + 1)) return map;
    return {};
  }

  std::string path_;
  exodus::File file_;
  int time_step_ = 0;  // asked for; 0: the last
  uint64_t budget_ = 0, objects_budget_ = 0;
  InputMesh out_;
  std::vector<Block> blocks_;
  std::vector<const Block*> face_blocks_;
  std::vector<int32_t> face_block_tags_;  // per face of out_.tagged_faces as read, its face_blocks_ index
  std::map<size_t, uint64_t> split_;
  std::vector<std::string> other_blocks_, attributed_, notes_, unfound_;
};

}  // namespace

InputMesh read_exodus(const std::string& path, int time_step) { return Reader(path, time_step).read(); }

}  // namespace dtm
