#include "core/independent_removal.h"

#include <algorithm>
#include <thread>
#include <tuple>

#include "common/parallel_for.h"
#include "common/threads.h"

namespace dtm {
namespace {

// A face named by its three sorted vertex ids.
struct FaceKey {
  uint32_t a, b, c;
  bool operator==(const FaceKey&) const = default;
  bool operator<(const FaceKey& o) const { return std::tie(a, b, c) < std::tie(o.a, o.b, o.c); }
};

FaceKey face_of(const std::array<uint32_t, 4>& cell, int opposite) {
  std::array<uint32_t, 3> f;
  int k = 0;
  for (int i = 0; i < 4; ++i)
    if (i != opposite) f[k++] = cell[i];
  std::sort(f.begin(), f.end());
  return {f[0], f[1], f[2]};
}

int index_of(const std::array<uint32_t, 4>& cell, uint32_t v) {
  for (int i = 0; i < 4; ++i)
    if (cell[i] == v) return i;
  check_failed(__FILE__, __LINE__, "the removed vertex is a corner of each cell of its star");
}

// The border of a cavity: one face per cell of the removed vertex's star
// (the face opposite it), with what lies beyond.
struct BorderFace {
  FaceKey key;       // in the new numbering
  int32_t outside;   // old cell beyond the face, or -1 (convex hull)
  int outside_face;  // index of the face in the outside cell
};

// A fill cell's face on its cavity's border whose other side was another
// removed vertex's star: it meets that cavity's fill, paired at the end.
struct CrossFace {
  FaceKey key;
  int32_t cell;
  int face;
};

// The cells that survive the removal (those with no removed corner), in
// their order, renumbered, with their neighbours where the other side
// survived too. `cell_map` gets each old cell's new index, or -1.
TetMesh surviving_cells(const TetMesh& dt, std::span<const uint8_t> removed, std::span<const uint32_t> new_id,
                        std::vector<int32_t>& cell_map) {
  const size_t m = dt.cells.size();
  cell_map.assign(m, -1);
  TetMesh out;
  out.cells.reserve(m);
  for (size_t c = 0; c < m; ++c) {
    const auto& cell = dt.cells[c];
    if (removed[cell[0]] || removed[cell[1]] || removed[cell[2]] || removed[cell[3]]) continue;
    cell_map[c] = static_cast<int32_t>(out.cells.size());
    out.cells.push_back({new_id[cell[0]], new_id[cell[1]], new_id[cell[2]], new_id[cell[3]]});
  }
  out.neighbors.assign(out.cells.size(), {-1, -1, -1, -1});
  for (size_t c = 0; c < m; ++c) {
    if (cell_map[c] < 0) continue;
    for (int i = 0; i < 4; ++i) {
      const int32_t nb = dt.neighbors[c][i];
      if (nb >= 0 && cell_map[nb] >= 0) out.neighbors[cell_map[c]][i] = cell_map[nb];
    }
  }
  return out;
}

// The fill of every removed vertex's cavity. The fills are independent of
// each other (disjoint stars, separate small triangulations), so they are
// computed on every core.
std::vector<CavityFill> cavity_fills(std::span<const uint32_t> removed_list, const Csr& neighbors,
                                     std::span<const GridPoint> points, std::span<const uint8_t> removed,
                                     std::span<const uint32_t> new_id) {
  std::vector<CavityFill> fills(removed_list.size());
  std::vector<uint8_t> dependent(removed_list.size(), 0);
  const size_t threads = removed_list.size() < 2048 ? size_t{1} : loop_threads();
  auto compute = [&](size_t t) {
    std::vector<GridPoint> link;
    std::vector<uint32_t> link_ids;
    for (size_t k = t; k < removed_list.size(); k += threads) {
      const uint32_t v = removed_list[k];
      link.clear();
      link_ids.clear();
      for (uint32_t u : neighbors.row(v)) {
        if (removed[u]) dependent[k] = 1;
        link.push_back(points[u]);
        link_ids.push_back(new_id[u]);
      }
      if (!dependent[k]) fills[k] = cavity_fill(link, link_ids, points[v]);
    }
  };
  std::vector<std::thread> workers;
  for (size_t t = 1; t < threads; ++t) workers.emplace_back(compute, t);
  compute(0);
  for (auto& w : workers) w.join();
  // The caller's promise: no two removed vertices share an edge.
  DTM_CHECK(std::find(dependent.begin(), dependent.end(), 1) == dependent.end());
  return fills;
}

// The border of v's cavity: the face of each cell of its star opposite v
// (renamed), with the old cell beyond it.
void cavity_border(const TetMesh& dt, const Csr& cells_of_vertex, uint32_t v,
                   std::span<const uint32_t> new_id, std::vector<BorderFace>& border) {
  border.clear();
  for (uint32_t c : cells_of_vertex.row(v)) {
    const auto& cell = dt.cells[c];
    const int i = index_of(cell, v);
    const std::array<uint32_t, 4> renamed = {new_id[cell[0]], new_id[cell[1]], new_id[cell[2]],
                                             new_id[cell[3]]};
    const int32_t outside = dt.neighbors[c][i];
    int outside_face = -1;
    if (outside >= 0)
      for (int j = 0; j < 4; ++j)
        if (dt.neighbors[outside][j] == static_cast<int32_t>(c)) outside_face = j;
    border.push_back({face_of(renamed, i), outside, outside_face});
  }
}

// Appends a cavity's fill to `out`: its inner faces linked among themselves,
// its border faces to the surviving cell beyond (at once) or, when the cell
// beyond was in another removed star, noted in `cross`.
void stitch(const CavityFill& fill, std::span<const BorderFace> border, std::span<const int32_t> cell_map,
            TetMesh& out, std::vector<CrossFace>& cross) {
  const auto first = static_cast<int32_t>(out.cells.size());
  for (size_t f = 0; f < fill.cells.size(); ++f) {
    out.cells.push_back(fill.cells[f]);
    std::array<int32_t, 4> nb;
    for (int i = 0; i < 4; ++i) nb[i] = fill.neighbors[f][i] < 0 ? -1 : first + fill.neighbors[f][i];
    out.neighbors.push_back(nb);
  }
  for (size_t f = 0; f < fill.cells.size(); ++f)
    for (int i = 0; i < 4; ++i) {
      if (fill.neighbors[f][i] >= 0) continue;
      const int32_t self = first + static_cast<int32_t>(f);
      const FaceKey key = face_of(fill.cells[f], i);
      const auto b =
          std::find_if(border.begin(), border.end(), [&](const BorderFace& x) { return x.key == key; });
      if (b == border.end() || b->outside < 0) continue;  // on the convex hull
      const int32_t beyond = cell_map[b->outside];
      if (beyond >= 0) {
        out.neighbors[self][i] = beyond;
        out.neighbors[beyond][b->outside_face] = self;
      } else {
        cross.push_back({key, self, i});
      }
    }
}

// Links the fill faces that meet across two cavities: each such face was
// noted once from each side.
void pair_cross_faces(std::vector<CrossFace>& cross, TetMesh& out) {
  std::sort(cross.begin(), cross.end(), [](const CrossFace& x, const CrossFace& y) { return x.key < y.key; });
  for (size_t k = 0; k + 1 < cross.size(); ++k)
    if (cross[k].key == cross[k + 1].key) {
      out.neighbors[cross[k].cell][cross[k].face] = cross[k + 1].cell;
      out.neighbors[cross[k + 1].cell][cross[k + 1].face] = cross[k].cell;
      ++k;
    }
}

}  // namespace

TetMesh remove_independent_vertices(const TetMesh& dt, const Csr& cells_of_vertex, const Csr& neighbors,
                                    std::span<const GridPoint> points, std::span<const uint8_t> removed) {
  const size_t n = points.size();
  std::vector<uint32_t> new_id(n, UINT32_MAX), removed_list;
  uint32_t survivors = 0;
  for (uint32_t v = 0; v < n; ++v) {
    if (!removed[v])
      new_id[v] = survivors++;
    else
      removed_list.push_back(v);
  }
  std::vector<int32_t> cell_map;
  TetMesh out = surviving_cells(dt, removed, new_id, cell_map);
  const std::vector<CavityFill> fills = cavity_fills(removed_list, neighbors, points, removed, new_id);
  // Stitched in vertex order, so that the result does not depend on the
  // number of threads.
  std::vector<CrossFace> cross;
  std::vector<BorderFace> border;
  for (size_t k = 0; k < removed_list.size(); ++k) {
    cavity_border(dt, cells_of_vertex, removed_list[k], new_id, border);
    stitch(fills[k], border, cell_map, out, cross);
  }
  pair_cross_faces(cross, out);
  return out;
}

}  // namespace dtm
