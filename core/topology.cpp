#include "topology.h"

#include <algorithm>

#include "geometry.h"

namespace dtm {

Csr vertex_neighbors(const TetMesh& mesh, size_t num_vertices) {
  // Every cell names each of its 6 edges from both ends; duplicates (the same
  // edge seen from other cells) are removed per row after sorting.
  std::vector<uint32_t> count(num_vertices + 1, 0);
  for (const auto& c : mesh.cells)
    for (uint32_t v : c) count[v + 1] += 3;
  Csr raw;
  raw.offsets.assign(num_vertices + 1, 0);
  for (size_t v = 0; v < num_vertices; ++v) raw.offsets[v + 1] = raw.offsets[v] + count[v + 1];
  raw.items.resize(raw.offsets.back());
  std::vector<uint32_t> fill(raw.offsets.begin(), raw.offsets.end() - 1);
  for (const auto& c : mesh.cells)
    for (int i = 0; i < 4; ++i)
      for (int j = 0; j < 4; ++j)
        if (i != j) raw.items[fill[c[i]]++] = c[j];

  Csr out;
  out.offsets.assign(num_vertices + 1, 0);
  out.items.reserve(raw.items.size() / 4);
  for (size_t v = 0; v < num_vertices; ++v) {
    auto first = raw.items.begin() + raw.offsets[v], last = raw.items.begin() + raw.offsets[v + 1];
    std::sort(first, last);
    last = std::unique(first, last);
    out.items.insert(out.items.end(), first, last);
    out.offsets[v + 1] = static_cast<uint32_t>(out.items.size());
  }
  return out;
}

Csr vertex_cells(const TetMesh& mesh, size_t num_vertices) {
  Csr out;
  out.offsets.assign(num_vertices + 1, 0);
  for (const auto& c : mesh.cells)
    for (uint32_t v : c) ++out.offsets[v + 1];
  for (size_t v = 0; v < num_vertices; ++v) out.offsets[v + 1] += out.offsets[v];
  out.items.resize(out.offsets.back());
  std::vector<uint32_t> fill(out.offsets.begin(), out.offsets.end() - 1);
  for (uint32_t c = 0; c < mesh.cells.size(); ++c)
    for (uint32_t v : mesh.cells[c]) out.items[fill[v]++] = c;
  return out;
}

std::vector<BoundaryFace> boundary_faces(const TetMesh& mesh, std::span<const uint8_t> in_mesh) {
  std::vector<BoundaryFace> out;
  for (uint32_t c = 0; c < mesh.cells.size(); ++c) {
    if (!in_mesh[c]) continue;
    for (uint8_t i = 0; i < 4; ++i) {
      const int32_t n = mesh.neighbors[c][i];
      if (n < 0 || !in_mesh[n]) out.push_back({c, i});
    }
  }
  return out;
}

std::array<uint32_t, 3> outward_triangle(const TetMesh& mesh, std::span<const GridPoint> points,
                                         const BoundaryFace& f) {
  const auto& c = mesh.cells[f.cell];
  std::array<uint32_t, 3> t;
  int k = 0;
  for (int i = 0; i < 4; ++i)
    if (i != f.opposite) t[k++] = c[i];
  const Vec3 a = to_vec(points[t[0]]), b = to_vec(points[t[1]]), d = to_vec(points[t[2]]);
  const Vec3 normal = cross(b - a, d - a);
  if (dot(normal, to_vec(points[c[f.opposite]]) - a) > 0) std::swap(t[1], t[2]);
  return t;
}

}  // namespace dtm
