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

}  // namespace

std::string render_abaqus(const OutputMesh& m) {
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
  // (Element sets, surfaces and node sets are named apart, as Abaqus's.)
  std::map<char, std::set<std::string>> labels;
  const auto unique = [&](char kind, std::string label) {
    const std::string base = label;
    for (int k = 2; !labels[kind].insert(upper(label)).second; ++k) label = base + "_" + std::to_string(k);
    return label;
  };
  // A region an element set.
  std::map<int32_t, std::vector<size_t>> regions;
  for (size_t c = 0; c < m.region.size(); ++c) regions[m.region[c]].push_back(c + 1);
  for (const auto& [label, cells] : regions) {
    const auto name = m.region_names.find(label);
    const std::string fallback = "REGION_" + std::to_string(label);
    out += "*ELSET, ELSET=" +
           unique('e', name != m.region_names.end() ? abaqus_label(name->second, fallback) : fallback) + "\n";
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
      const auto name = m.face_tag_names.find(tag);
      const std::string fallback = "FACES_" + std::to_string(tag);
      out += "*SURFACE, NAME=" +
             unique('s', name != m.face_tag_names.end() ? abaqus_label(name->second, fallback) : fallback) +
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
      if (f.bits[i] != 0) nodes.push_back(number(i));
    out += "*NSET, NSET=" +
           unique('n', abaqus_label(f.name.substr(std::string(kNodeSetFieldPrefix).size()), "NSET")) + "\n";
    append_list(out, nodes);
  }
  return out;
}

bool is_node_set_field(const OutputField& f) {
  return f.components == 1 && f.name.rfind(kNodeSetFieldPrefix, 0) == 0 &&
         (f.type == ScalarType::kUInt8 || f.type == ScalarType::kInt8);
}

}  // namespace dtm
