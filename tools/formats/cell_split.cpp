#include "cell_split.h"

#include <algorithm>
#include <utility>

namespace dtm {
namespace {

// A cell's faces as cycles of its corners (-1 after a triangle's third).
using Face = std::array<int, 4>;
constexpr std::array<Face, 5> kPyramid = {
    {{0, 1, 2, 3}, {0, 1, 4, -1}, {1, 2, 4, -1}, {2, 3, 4, -1}, {3, 0, 4, -1}}};
constexpr std::array<Face, 5> kPrism = {
    {{0, 1, 2, -1}, {3, 4, 5, -1}, {0, 1, 4, 3}, {1, 2, 5, 4}, {2, 0, 3, 5}}};
constexpr std::array<Face, 6> kHexahedron = {
    {{0, 1, 2, 3}, {4, 5, 6, 7}, {0, 1, 5, 4}, {1, 2, 6, 5}, {2, 3, 7, 6}, {3, 0, 4, 7}}};

// Coning from the least corner to the faces that do not hold it.
void cone(std::span<const uint32_t> c, std::span<const Face> faces,
          std::vector<std::array<uint32_t, 4>>& out) {
  const uint32_t apex = *std::min_element(c.begin(), c.end());
  // (A cell with a corner repeated, as a prism or pyramid stored as a
  // collapsed hexahedron: its tetrahedra with a repeated corner are
  // dropped, the others still fill it.)
  const auto add = [&](const std::array<uint32_t, 4>& t) {
    for (size_t i = 0; i < 4; ++i)
      for (size_t j = i + 1; j < 4; ++j)
        if (t[i] == t[j]) return;
    out.push_back(t);
  };
  for (const Face& f : faces) {
    const bool quad = f[3] >= 0;
    bool holds_apex = false;
    for (int k = 0; k < (quad ? 4 : 3); ++k) holds_apex |= c[static_cast<size_t>(f[k])] == apex;
    if (holds_apex) continue;
    if (!quad) {
      add({apex, c[static_cast<size_t>(f[0])], c[static_cast<size_t>(f[1])], c[static_cast<size_t>(f[2])]});
      continue;
    }
    for (const auto& t : split_quad({c[static_cast<size_t>(f[0])], c[static_cast<size_t>(f[1])],
                                     c[static_cast<size_t>(f[2])], c[static_cast<size_t>(f[3])]}))
      add({apex, t[0], t[1], t[2]});
  }
}

}  // namespace

void split_cell(std::span<const uint32_t> corners, std::span<const InputPoint> points,
                std::vector<std::array<uint32_t, 4>>& out) {
  const size_t first = out.size();
  switch (corners.size()) {
    case 5:
      cone(corners, kPyramid, out);
      break;
    case 6:
      cone(corners, kPrism, out);
      break;
    case 8:
      cone(corners, kHexahedron, out);
      break;
    default:
      return;
  }
  // (In doubles: a cell flat enough for that to err is flat on any grid.)
  for (size_t k = first; k < out.size(); ++k) {
    auto& t = out[k];
    const InputPoint &a = points[t[0]], &b = points[t[1]], &c = points[t[2]], &d = points[t[3]];
    const double u[3] = {b.x - a.x, b.y - a.y, b.z - a.z}, v[3] = {c.x - a.x, c.y - a.y, c.z - a.z},
                 w[3] = {d.x - a.x, d.y - a.y, d.z - a.z};
    const double volume = u[0] * (v[1] * w[2] - v[2] * w[1]) - u[1] * (v[0] * w[2] - v[2] * w[0]) +
                          u[2] * (v[0] * w[1] - v[1] * w[0]);
    if (volume < 0) std::swap(t[2], t[3]);
  }
}

size_t add_split_cell(std::span<const uint32_t> nodes, size_t corners, InputMesh& mesh) {
  mesh.other_edge_nodes.insert(mesh.other_edge_nodes.end(),
                               nodes.begin() + static_cast<std::ptrdiff_t>(corners), nodes.end());
  if (corners == 4) {
    for (const auto& half : split_quad({nodes[0], nodes[1], nodes[2], nodes[3]}))
      mesh.tagged_faces.push_back(half);
    return 2;
  }
  mesh.second_order_cells += nodes.size() > corners;
  const size_t before = mesh.tets.size();
  split_cell(nodes.first(corners), mesh.points, mesh.tets);
  return mesh.tets.size() - before;
}

std::string split_cells_note(const std::map<size_t, uint64_t>& cells_by_corners) {
  std::string cells;
  for (const auto& [corners, count] : cells_by_corners)
    cells += (cells.empty() ? "" : ", ") + std::to_string(count) +
             (corners == 8   ? " hexahedra"
              : corners == 6 ? " prisms"
                             : " pyramids");
  if (cells.empty()) return cells;
  return "the shapes of its " + cells +
         ": each is read as the tetrahedra that split it (its quadrilaterals by their diagonals through "
         "their least node)";
}

std::array<std::array<uint32_t, 3>, 2> split_quad(const std::array<uint32_t, 4>& q) {
  const size_t i = static_cast<size_t>(std::min_element(q.begin(), q.end()) - q.begin());
  const uint32_t a = q[i], b = q[(i + 1) % 4], c = q[(i + 2) % 4], d = q[(i + 3) % 4];
  return {{{a, b, c}, {a, c, d}}};
}

}  // namespace dtm
