#include "mesh/topology.h"

#include <algorithm>

#include "mesh/geometry.h"

namespace dtm {

Csr vertex_cells(const TetMesh& mesh, size_t num_vertices) {
  return build_csr(num_vertices, [&](auto&& emit) {
    for (uint32_t c = 0; c < mesh.cells.size(); ++c)
      for (uint32_t v : mesh.cells[c]) emit(v, c);
  });
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

std::vector<std::array<uint32_t, 3>> boundary_triangles(std::span<const std::array<uint32_t, 4>> cells) {
  // Outward faces of a positively oriented (a, b, c, d): d lies on the
  // right-hand normal side of (a, b, c), so that face turns the other way.
  static constexpr int kFaces[4][3] = {{1, 2, 3}, {0, 3, 2}, {0, 1, 3}, {0, 2, 1}};
  if (cells.empty()) return {};
  // Each face's sorted vertices are its key. Faces are bucketed by their
  // smallest vertex, then each small bucket is sorted: the two sides of an
  // inner face meet in one bucket. The output is in ascending key order, as
  // one global sort would give, at a fraction of its cost (this runs once
  // per level in meshenc).
  std::vector<std::array<uint32_t, 3>> keys(4 * cells.size());
  uint32_t top = 0;
  for (size_t c = 0; c < cells.size(); ++c)
    for (int f = 0; f < 4; ++f) {
      auto& key = keys[4 * c + f];
      key = {cells[c][kFaces[f][0]], cells[c][kFaces[f][1]], cells[c][kFaces[f][2]]};
      std::sort(key.begin(), key.end());
      top = std::max(top, key[2]);
    }
  Csr buckets = build_csr(static_cast<size_t>(top) + 1, [&](auto&& emit) {
    for (uint32_t i = 0; i < keys.size(); ++i) emit(keys[i][0], i);
  });
  std::vector<std::array<uint32_t, 3>> out;
  for (size_t v = 0; v < buckets.rows(); ++v) {
    const auto begin = buckets.items.begin() + buckets.offsets[v];
    const auto end = buckets.items.begin() + buckets.offsets[v + 1];
    std::sort(begin, end, [&](uint32_t a, uint32_t b) { return keys[a] < keys[b]; });
    for (auto i = begin; i != end;) {
      auto j = i;
      while (j != end && keys[*j] == keys[*i]) ++j;
      if (j - i == 1) {
        const auto& cell = cells[*i / 4];
        const int* f = kFaces[*i % 4];
        out.push_back({cell[f[0]], cell[f[1]], cell[f[2]]});
      }
      i = j;
    }
  }
  return out;
}

}  // namespace dtm
