// The project's only door to CGAL's Delaunay tetrahedralization. CGAL is
// slow to compile, so it stays inside delaunay.cpp; everything else works on
// the plain arrays of TetMesh.
//
// Uniqueness (docs/ARCHITECTURE.md §3.2): CGAL's Delaunay_triangulation_3 with exact
// predicates breaks cospherical ties by a symbolic perturbation that depends
// only on the coordinates, so the cell set is a function of the point set,
// whatever the insertion order, batching or removals. The tests prove it on
// degenerate grid input.
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include "common/grid.h"
#include "common/status.h"

namespace dtm {

// A tetrahedralization detached from CGAL. Vertex indices are the caller's
// ids; cells are positively oriented. Those this file exports are in the
// canonical order (mesh/topology.h: by sorted vertex ids), each cell's
// corners in one rotation (the smallest id first), whatever order the
// insertions left them in, unless asked for as built: what is computed from
// an exported mesh is then the same on every run and any number of threads.
struct TetMesh {
  std::vector<std::array<uint32_t, 4>> cells;
  // neighbors[c][i]: the cell sharing the face of c opposite its vertex i,
  // or -1 when that face is on the convex hull.
  std::vector<std::array<int32_t, 4>> neighbors;
};

// A Delaunay tetrahedralization of n points can have O(n^2) cells (points on
// two skew lines); a mesh's has about 6.5 n. Insertion stops with
// kLimitExceeded past this many per vertex, so that hostile input costs
// memory and time linear in its vertices.
inline constexpr size_t kMaxCellsPerVertex = 64;

// Delaunay tetrahedralization of `points`; vertex i is points[i]. Large
// batches are inserted on every core (CGAL's Parallel_tag, where TBB is
// linked; the cells are the same, docs/ARCHITECTURE.md §5). kInvalidInput if the points
// are not distinct or are coplanar (or fewer than 4); kLimitExceeded if the
// cells exceed kMaxCellsPerVertex per vertex.
StatusOr<TetMesh> delaunay_tetrahedralize(std::span<const GridPoint> points);

// True when batch insertions use several threads (a native build with TBB).
bool parallel_delaunay_available();

// A Delaunay tetrahedralization that is edited in place: batch insertion
// (what the decoder does level by level, and the encoder's local repairs)
// and vertex removal.
class IncrementalDelaunay {
 public:
  IncrementalDelaunay();
  ~IncrementalDelaunay();
  IncrementalDelaunay(const IncrementalDelaunay&) = delete;
  IncrementalDelaunay& operator=(const IncrementalDelaunay&) = delete;

  // Inserts points[i] with id ids[i]. A batch is spatially sorted first and,
  // when large, inserted on every core, a slice at a time with the cell
  // check between slices. Both insertions fail with kLimitExceeded as
  // delaunay_tetrahedralize does (the triangulation is then unusable).
  Status insert(std::span<const GridPoint> points, std::span<const uint32_t> ids);
  // Inserts one point at a time, in the given order (no spatial sort).
  Status insert_one_by_one(std::span<const GridPoint> points, std::span<const uint32_t> ids);
  // Removes the vertices at these positions; kInvalidInput if one is absent.
  Status remove(std::span<const GridPoint> points);

  int dimension() const;
  size_t number_of_vertices() const;
  // Whether its batches may be inserted on several threads: made where the
  // work had more than one (common/threads.h), and TBB linked. Made on one
  // thread it is CGAL's sequential type (no locks, no concurrent
  // container), and stays so.
  bool parallel() const;
  // The current finite cells, vertices named by their ids: in the canonical
  // order, or as the triangulation holds them (cheaper; after a parallel
  // insertion the order varies from run to run).
  // `spare`: room for that fraction more cells in the arrays, for a caller
  // that will add some (reserved: no memory is touched until it is used).
  enum class CellOrder { kCanonical, kAsBuilt };
  TetMesh mesh(CellOrder order = CellOrder::kCanonical, double spare = 0) const;
  // Only the finite cells' vertex ids, as built: the cheapest export, for
  // what depends on the cell set alone (format 7.0's candidates).
  std::vector<std::array<uint32_t, 4>> finite_cells() const;
  // The same, and per cell its index in the mesh the previous export (either
  // function) returned, or -1 for a cell made since (by insertions or
  // removals): what a caller needs to keep its per-cell results for the
  // cells a local change left alone. On the first call every cell is new.
  TetMesh mesh(std::vector<int32_t>& previous_index);
  // The same, given `before`: what the previous export returned, unchanged
  // (empty: there was none). Only the cells made since are read from the
  // triangulation and sorted, the rest are copied: after a few local
  // insertions, a pass over the arrays instead of a whole export.
  TetMesh mesh(const TetMesh& before, std::vector<int32_t>& previous_index);

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

// The cells that refill the star of `apex` when it is removed from a
// Delaunay tetrahedralization in which `link` are its neighbours: the cells
// of DT(link) in conflict with apex (whose circumsphere contains it, under the
// same symbolic perturbation). These are exactly the cells the Delaunay
// tetrahedralization without apex has in that region.
struct CavityFill {
  std::vector<std::array<uint32_t, 4>> cells;  // named by link_ids, positively oriented
  // neighbors[c][i]: the fill cell across the face opposite vertex i, or -1
  // when that face is on the cavity's border (or on the new convex hull).
  std::vector<std::array<int32_t, 4>> neighbors;
};

// Empty when the link does not span three dimensions (apex was the tip of a
// flat hull region). `apex` must not be a link point.
CavityFill cavity_fill(std::span<const GridPoint> link, std::span<const uint32_t> link_ids,
                       const GridPoint& apex);

}  // namespace dtm
