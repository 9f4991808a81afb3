// The solid every codec level is carved to (docs/ARCHITECTURE.md §3.3, spec/HIERARCHY.md
// §2.1): a set of tetrahedra over grid points (the input's own, or level 0's
// alpha carving when the input has none). A cell of a level's Delaunay
// tetrahedralization is kept when its centroid lies in the closed union of
// these tetrahedra. The test is exact: centroids are compared at four times
// the grid's scale, with integer orientation determinants.
//
// Held compactly and answered mostly by one lookup: a uniform grid over the
// solid's box whose cells are classified once. A cell that no boundary
// triangle meets (its box, then its plane: exact integer tests) lies wholly
// inside or wholly outside (the solid's boundary is in those triangles), and
// so does every run of such cells along a grid row: each run is classified
// by one exact test (rows on every core). Only the cells the boundary meets
// ("mixed") keep a list of the tetrahedra that may meet them (box and face
// planes), tested exactly. Only those tetrahedra are kept (a copy, near the
// boundary: at 1M vertices a quarter of them), so that the caller may free its
// own; the points are the caller's (a span): they must outlive the solid.
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <span>
#include <vector>

#include "common/csr.h"
#include "common/exchange.h"
#include "common/grid.h"
#include "core/solid.h"
#include "mesh/delaunay.h"

namespace dtm {

class ReferenceSolid : public Solid {
 public:
  // `cells` index `points`; flat cells hold no volume and are ignored.
  // `boundary`: the faces of exactly one of `cells` (boundary_triangles());
  // computed here when not given.
  ReferenceSolid(std::span<const GridPoint> points, std::span<const std::array<uint32_t, 4>> cells,
                 std::span<const std::array<uint32_t, 3>> boundary);
  ReferenceSolid(std::span<const GridPoint> points, std::span<const std::array<uint32_t, 4>> cells);

  // Made in parts (an MPI rank holding a share of the cells,
  // codec/blocks/reference_share.h): the box and count of all the cells, which
  // frame the grid of every part as the whole's.
  struct Extent {
    std::array<int64_t, 3> lo{}, hi{};  // the cells' corners' box, at four times the grid's scale
    uint64_t tetrahedra = 0;
    bool any = false;  // lo and hi hold a corner
    // The box of `cells`, of which `owned` are counted.
    static Extent of(std::span<const GridPoint> points, std::span<const std::array<uint32_t, 4>> cells,
                     uint64_t owned);
    void add(const Extent& o);
  };
  // Those of `cells` (`mine` of them) that the solid of the whole keeps:
  // every cell that may meet a grid cell the boundary meets.
  static std::vector<std::array<uint32_t, 4>> near_boundary(
      std::span<const GridPoint> points, std::span<const std::array<uint32_t, 4>> cells,
      std::span<const std::array<uint32_t, 3>> boundary, const Extent& whole,
      const std::function<bool(const std::array<uint32_t, 4>&)>& mine);

  // A part of the whole's solid, on one rank of a run, so that no rank holds
  // all the cells near the boundary: `held`, this rank's (every such cell
  // held by some rank, and `owns` exactly one rank's own), `boundary` and
  // `whole` the whole's. Every rank makes its part at once (they exchange
  // what classifies the grid). A part knows which grid cells lie inside as
  // the whole does; in a cell the boundary meets it answers when one of its
  // cells holds the point, or when it holds every cell meeting that grid
  // cell, and else does not know: then whether any rank's part holds the
  // point (holds4(), OR-ed over the ranks) is the whole's answer.
  ReferenceSolid(std::span<const GridPoint> points, std::span<const std::array<uint32_t, 4>> held,
                 const std::function<bool(const std::array<uint32_t, 4>&)>& owns,
                 std::span<const std::array<uint32_t, 3>> boundary, const Extent& whole,
                 RankExchange& exchange);
  enum class Answer : uint8_t { kOutside, kInside, kUnknown };
  // p at four times the grid's scale (as contains_point4()).
  Answer answer4(const std::array<int64_t, 3>& p) const;
  // Whether one of this part's cells holds p (any rank's, for the whole).
  bool holds4(const std::array<int64_t, 3>& p) const;

  // Of a part: inside only where it knows (the encoder asks the ranks the rest).
  bool contains_point4(const std::array<int64_t, 3>& p) const override {
    return part_ ? answer4(p) == Answer::kInside : contains4(p);
  }

  size_t tetrahedra() const { return tetrahedra_; }

  // The grid's figures, for tests and benchmarks: cells along each axis, and
  // how many are mixed, how many tetrahedra their lists hold, and how many
  // distinct tetrahedra the solid keeps.
  struct Layout {
    std::array<int64_t, 3> dims;
    uint64_t mixed_cells, listed, kept;
  };
  Layout layout() const;

 private:
  using Point4 = std::array<int64_t, 3>;

  explicit ReferenceSolid(std::span<const GridPoint> points) : points_(points) {}
  // `exchange`: made in parts (each rank's cells), runs classified by all.
  void build(std::span<const std::array<uint32_t, 4>> cells,
             std::span<const std::array<uint32_t, 3>> boundary, const Extent& whole,
             RankExchange* exchange = nullptr);
  // Of a part: which mixed cells list every cell that meets them.
  void mark_complete(std::span<const std::array<uint32_t, 4>> cells,
                     const std::function<bool(const std::array<uint32_t, 4>&)>& owns, RankExchange& exchange);
  // The grid cells [c0, c1] a closed box [bl, bh] meets: those whose closed
  // extent overlaps it (a box on a cell's face meets both cells).
  void cell_range(const Point4& bl, const Point4& bh, std::array<int64_t, 3>& c0,
                  std::array<int64_t, 3>& c1) const;
  void box_of(std::span<const uint32_t> corners, Point4& bl, Point4& bh) const;
  // f(cell, its closed extent's low and high corners) for the cells [c0, c1].
  template <class F>
  void for_each_cell_box(const std::array<int64_t, 3>& c0, const std::array<int64_t, 3>& c1, F&& f) const;
  // The grid over the whole's box; false when it has no corner.
  bool frame(const Extent& whole);
  void orient(std::span<const std::array<uint32_t, 4>> cells);
  // Sets mixed_cells_ (the grid cells the boundary meets) and mixed_before_.
  void mark_mixed(std::span<const std::array<uint32_t, 3>> boundary);
  // take(pairs) per block of cells, in order: (mixed row, cell) for each
  // mixed grid cell each cell may meet (box and face planes), of the cells
  // `mine` takes (all when null).
  void for_each_meeting(
      std::span<const std::array<uint32_t, 4>> cells,
      const std::function<bool(const std::array<uint32_t, 4>&)>* mine,
      const std::function<void(std::span<const std::pair<uint32_t, uint32_t>>)>& take) const;
  // Keeps the listed tetrahedra only, renumbered in their order.
  void keep_listed(std::span<const std::array<uint32_t, 4>> cells);
  bool contains4(const Point4& p) const;
  // The exact test of p against tetrahedron t of the given orientation (a
  // flat one contains nothing).
  bool in_tetrahedron(const Point4& p, const std::array<uint32_t, 4>& t, uint8_t orientation) const;
  size_t cell_of(const Point4& p) const;
  // A mixed cell's row in mixed_.
  uint32_t mixed_row(size_t cell) const;

  std::span<const GridPoint> points_;
  // The tetrahedra the mixed cells list (mixed_ numbers them).
  std::vector<std::array<uint32_t, 4>> kept_;
  size_t tetrahedra_ = 0;
  // Per tetrahedron (while building, the caller's; then kept_'s): 0 flat,
  // 1 positively oriented, 2 negatively.
  std::vector<uint8_t> orientation_;
  Point4 lo_{}, hi_{};
  int64_t step_ = 2;  // grid cell edge at four times the grid scale (even: cell centres are integral)
  std::array<int64_t, 3> dims_{1, 1, 1};
  // Per grid cell, one bit each: whether the boundary meets it (mixed),
  // else whether it is inside; and per 64 cells, the mixed cells before.
  std::vector<uint64_t> mixed_cells_, inside_;
  std::vector<uint32_t> mixed_before_;
  Csr mixed_;  // per mixed cell, the tetrahedra whose boxes meet it
  // Every coordinate (x4) under 2^18: orientations fit in 64-bit integers.
  bool small_ = false;
  // A part: per mixed cell, one bit: its list holds every cell meeting it.
  bool part_ = false;
  std::vector<uint64_t> complete_;
};

}  // namespace dtm
