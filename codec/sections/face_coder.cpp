// A level's surface faces, as encoder and decoder find them (face_coder.h).
#include "codec/sections/face_coder.h"

#include <algorithm>
#include <tuple>
#include <vector>

#include "common/parallel_for.h"
#include "common/release.h"

namespace dtm {
namespace {

constexpr int kFace[4][3] = {{1, 2, 3}, {0, 2, 3}, {0, 1, 3}, {0, 1, 2}};

// Per face, the faces of its group that share one of its edges (a chunk's
// faces, or, without `group`, the level's).
Csr faces_sharing_edges(std::span<const SurfaceFace> faces, std::span<const uint32_t> group) {
  struct Edge {
    uint32_t group, a, b, face;
  };
  std::vector<Edge> edges;
  edges.reserve(3 * faces.size());
  for (uint32_t f = 0; f < faces.size(); ++f) {
    const auto& k = faces[f].key;
    const uint32_t g = group.empty() ? 0 : group[f];
    edges.push_back({g, k[0], k[1], f});
    edges.push_back({g, k[0], k[2], f});
    edges.push_back({g, k[1], k[2], f});
  }
  std::sort(edges.begin(), edges.end(), [](const Edge& x, const Edge& y) {
    return std::tie(x.group, x.a, x.b, x.face) < std::tie(y.group, y.a, y.b, y.face);
  });
  return build_csr(faces.size(), [&](auto&& add) {
    for (size_t a = 0; a < edges.size();) {
      size_t b = a;
      while (b < edges.size() && edges[b].group == edges[a].group && edges[b].a == edges[a].a &&
             edges[b].b == edges[a].b)
        ++b;
      for (size_t i = a; i < b; ++i)
        for (size_t j = a; j < b; ++j)
          if (i != j) add(edges[i].face, edges[j].face);
      a = b;
    }
  });
}

}  // namespace

SurfaceFaces surface_faces(const TetMesh& dt, std::span<const uint8_t> kept) {
  SurfaceFaces s;
  for (uint32_t c = 0; c < dt.cells.size(); ++c) {
    if (!kept[c]) continue;
    for (int i = 0; i < 4; ++i) {
      const int32_t n = dt.neighbors[c][static_cast<size_t>(i)];
      const uint8_t other = n < 0 ? 0 : kept[static_cast<size_t>(n)];
      if (!surface_takes_face(kept[c], other)) continue;
      SurfaceFace f;
      f.cell = c;
      f.opposite = static_cast<uint8_t>(i);
      for (int k = 0; k < 3; ++k)
        f.key[static_cast<size_t>(k)] = dt.cells[c][static_cast<size_t>(kFace[i][k])];
      std::sort(f.key.begin(), f.key.end());
      s.faces.push_back(f);
    }
  }
  std::sort(s.faces.begin(), s.faces.end(),
            [](const SurfaceFace& a, const SurfaceFace& b) { return a.key < b.key; });
  s.neighbours = faces_sharing_edges(s.faces, {});
  return s;
}

ChunkFaces chunk_faces(const TetMesh& dt, const ChunkCells& chunks, std::span<const uint32_t> chunk_of_cell,
                       std::span<const uint8_t> kept, std::span<const uint32_t> vertex_rank) {
  const size_t count = chunks.first.empty() ? 0 : chunks.first.size() - 1;
  // Each chunk's faces on its own, on every core, then one after another.
  std::vector<std::vector<SurfaceFace>> per_chunk(count);
  parallel_for(
      count,
      [&](size_t i) {
        std::vector<SurfaceFace>& out = per_chunk[i];
        for (size_t at = chunks.first[i]; at < chunks.first[i + 1]; ++at) {
          const uint32_t c = chunks.cells[at];
          if (!kept[c]) continue;
          for (int k = 0; k < 4; ++k) {
            const int32_t n = dt.neighbors[c][static_cast<size_t>(k)];
            // Inside the chunk's kept cells, or an interface it codes from
            // the other side.
            if (n >= 0 && chunk_of_cell[static_cast<size_t>(n)] == i &&
                !surface_takes_face(kept[c], kept[static_cast<size_t>(n)]))
              continue;
            SurfaceFace f;
            f.cell = c;
            f.opposite = static_cast<uint8_t>(k);
            for (int j = 0; j < 3; ++j)
              f.key[static_cast<size_t>(j)] = vertex_rank[dt.cells[c][static_cast<size_t>(kFace[k][j])]];
            std::sort(f.key.begin(), f.key.end());
            out.push_back(f);
          }
        }
        std::sort(out.begin(), out.end(),
                  [](const SurfaceFace& a, const SurfaceFace& b) { return a.key < b.key; });
      },
      2);
  ChunkFaces out;
  out.first.assign(count + 1, 0);
  for (size_t i = 0; i < count; ++i)
    out.first[i + 1] = out.first[i] + static_cast<uint32_t>(per_chunk[i].size());
  out.faces.reserve(out.first[count]);
  std::vector<uint32_t> group;
  group.reserve(out.first[count]);
  for (size_t i = 0; i < count; ++i) {
    out.faces.insert(out.faces.end(), per_chunk[i].begin(), per_chunk[i].end());
    group.insert(group.end(), per_chunk[i].size(), static_cast<uint32_t>(i));
    release(per_chunk[i]);
  }
  out.neighbours = faces_sharing_edges(out.faces, group);
  return out;
}

}  // namespace dtm
