// The Abaqus/CalculiX .inp writer (abaqus.h): a mesh for a deck to
// *INCLUDE.
#include <algorithm>
#include <array>
#include <cctype>
#include <map>
#include <set>
#include <string>
#include <vector>

#include "abaqus.h"
#include "abaqus_syntax.h"
#include "face_sides.h"
#include "render_util.h"

namespace dtm {
namespace {

using abaqus::upper;

// An Abaqus label: letters, digits, '_' and '-', starting with a letter,
// at most 80 characters (a '.' would name an instance's set).
std::string abaqus_label(const std::string& name, const std::string& otherwise) {
  std::string out;
  for (char c : name) out += std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '-' ? c : '_';
  if (out.empty()) return otherwise;
  if (!std::isalpha(static_cast<unsigned char>(out[0]))) out = "N_" + out;
  return out.substr(0, 72);  // (room for unique()'s "_k")
}

// Numbers 16 a line (Abaqus's most on a data line).
void append_list(std::string& out, const std::vector<size_t>& numbers) {
  for (size_t i = 0; i < numbers.size(); ++i) {
    append_number(out, numbers[i]);
    out += (i + 1) % 16 == 0 || i + 1 == numbers.size() ? "\n" : ", ";
  }
}

// The labels of the file's element sets (by region), surfaces (by face tag)
// and node sets (by node set field, in the fields' order): each name made an
// Abaqus label, unique among its kind (Abaqus's labels ignore case), the
// later of two that meet with "_2", "_3", ...; `renamed` says each name
// that is not its own label.
struct AbaqusLabels {
  std::map<int32_t, std::string> element_set, surface;
  std::vector<std::string> node_set;
  std::vector<std::string> renamed;
};

AbaqusLabels abaqus_labels(const OutputMesh& m) {
  AbaqusLabels out;
  std::map<char, std::set<std::string>> taken;
  const auto label = [&](char kind, const std::string& what, const std::string* name,
                         const std::string& fallback) {
    std::string l = name ? abaqus_label(*name, fallback) : fallback;
    const std::string base = l;
    for (int k = 2; !taken[kind].insert(upper(l)).second; ++k) l = base + "_" + std::to_string(k);
    if (name && l != *name) out.renamed.push_back(what + " \"" + *name + "\" as " + l);
    return l;
  };
  for (const int32_t region : std::set<int32_t>(m.region.begin(), m.region.end())) {
    const auto name = m.region_names.find(region);
    out.element_set[region] =
        label('e', "region " + std::to_string(region), name != m.region_names.end() ? &name->second : nullptr,
              "REGION_" + std::to_string(region));
  }
  for (const int32_t tag : std::set<int32_t>(m.face_tags.begin(), m.face_tags.end())) {
    const auto name = m.face_tag_names.find(tag);
    out.surface[tag] =
        label('s', "face tag " + std::to_string(tag),
              name != m.face_tag_names.end() ? &name->second : nullptr, "FACES_" + std::to_string(tag));
  }
  for (const OutputField& f : m.fields)
    if (is_node_set_field(f)) {
      const std::string name = f.name.substr(std::string(kNodeSetFieldPrefix).size());
      out.node_set.push_back(label('n', "node set", &name, "NSET"));
    }
  return out;
}

}  // namespace

std::vector<std::string> abaqus_renaming(const OutputMesh& m) { return abaqus_labels(m).renamed; }

std::string render_abaqus(const OutputMesh& m) {
  const AbaqusLabels labels = abaqus_labels(m);
  std::string out = "*HEADING\nwritten by meshdec\n*NODE\n";
  // Each node's number: the input's (22.0, --keep-order), else its rank.
  const auto number = [&](size_t i) {
    return m.node_labels.empty() ? i + 1 : static_cast<size_t>(m.node_labels[i]);
  };
  for (size_t i = 0; i < m.points.size(); ++i) {
    const InputPoint p = m.grid.to_input(m.points[i]);
    append_number(out, number(i));
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
        append_number(out, number(n.nodes[k]));
      }
      out += '\n';
    }
  }
  // A region an element set.
  std::map<int32_t, std::vector<size_t>> regions;
  for (size_t c = 0; c < m.region.size(); ++c) regions[m.region[c]].push_back(c + 1);
  for (const auto& [label, cells] : regions) {
    out += "*ELSET, ELSET=" + labels.element_set.at(label) + "\n";
    append_list(out, cells);
  }
  // A face tag an element-based surface: each face as the face S1..S4 of
  // the cell it faces out of.
  if (!m.faces.empty()) {
    // Abaqus's S1..S4 as the reader takes them (face_slots) list a
    // positively turned cell's faces turned inward: reversed, outward.
    const std::vector<CellSide> sides = tagged_face_sides(m, [&](uint32_t c, uint8_t s) {
      const auto& t = m.cells[c];
      const abaqus::FaceSlots f = abaqus::face_slots(abaqus::Shape::kTetrahedron, s);
      return std::array<uint32_t, 3>{t[static_cast<size_t>(f.slots[2])], t[static_cast<size_t>(f.slots[1])],
                                     t[static_cast<size_t>(f.slots[0])]};
    });
    std::map<int32_t, std::vector<std::pair<uint32_t, uint8_t>>> surfaces;
    for (size_t f = 0; f < m.faces.size(); ++f)
      if (sides[f].cell != CellSide::kNoCell)
        surfaces[m.face_tags[f]].emplace_back(sides[f].cell, sides[f].side);
    for (const auto& [tag, faces] : surfaces) {
      out += "*SURFACE, NAME=" + labels.surface.at(tag) + ", TYPE=ELEMENT\n";
      for (const auto& [c, s] : faces) {
        append_number(out, size_t{c} + 1);
        out += ", S" + std::to_string(s + 1) + "\n";
      }
    }
  }
  // The node set fields, back as node sets.
  size_t node_set = 0;
  for (const OutputField& f : m.fields) {
    if (!is_node_set_field(f)) continue;
    std::vector<size_t> nodes;
    for (size_t i = 0; i < f.bits.size(); ++i)
      if (f.bits[i] != 0) nodes.push_back(number(i));
    out += "*NSET, NSET=" + labels.node_set[node_set++] + "\n";
    append_list(out, nodes);
  }
  return out;
}

bool is_node_set_field(const OutputField& f) {
  return f.components == 1 && f.name.rfind(kNodeSetFieldPrefix, 0) == 0 &&
         (f.type == ScalarType::kUInt8 || f.type == ScalarType::kInt8);
}

}  // namespace dtm
