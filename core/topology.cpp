#include "topology.h"

#include <algorithm>

#include "geometry.h"

namespace dtm {

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

Csr vertex_neighbors(const TetMesh& mesh, const Csr& cells_of_vertex) {
  // The neighbours of v are the other corners of its cells; a stamp per
  // vertex (the last v that listed it) drops repeats without a hash or a
  // sort of the ~70 corners each vertex sees.
  const size_t n = cells_of_vertex.rows();
  std::vector<uint32_t> stamp(n, UINT32_MAX);
  Csr out;
  out.offsets.assign(n + 1, 0);
  out.items.reserve(mesh.cells.size() * 3);
  for (uint32_t v = 0; v < n; ++v) {
    const size_t first = out.items.size();
    for (uint32_t c : cells_of_vertex.row(v))
      for (uint32_t u : mesh.cells[c])
        if (u != v && stamp[u] != v) {
          stamp[u] = v;
          out.items.push_back(u);
        }
    std::sort(out.items.begin() + first, out.items.end());
    out.offsets[v + 1] = static_cast<uint32_t>(out.items.size());
  }
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

std::vector<uint8_t> boundary_vertices(const TetMesh& mesh, size_t num_vertices,
                                       std::span<const uint8_t> in_mesh) {
  std::vector<uint8_t> out(num_vertices, 0), touched(num_vertices, 0);
  for (size_t c = 0; c < mesh.cells.size(); ++c)
    if (in_mesh[c])
      for (uint32_t v : mesh.cells[c]) touched[v] = 1;
  for (const BoundaryFace& f : boundary_faces(mesh, in_mesh))
    for (int i = 0; i < 4; ++i)
      if (i != f.opposite) out[mesh.cells[f.cell][i]] = 1;
  for (size_t v = 0; v < num_vertices; ++v)
    if (!touched[v]) out[v] = 1;
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
