#include "core/hierarchy.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>

#include "common/parallel_for.h"
#include "core/boundary_simplification.h"
#include "core/codec_hierarchy.h"
#include "core/importance.h"
#include "core/independent_removal.h"
#include "core/refill.h"
#include "core/surface_distance.h"
#include "mesh/delaunay.h"
#include "mesh/geometry.h"

namespace dtm {
namespace {

// With several passes per level, a level that removes less than this share
// of what removal_share asks is not built.
constexpr double kThinLevelShare = 0.4;
// The paper preset stops after a level that removed less than this share of
// the finer level's vertices (spec/HIERARCHY.md §7).
constexpr double kStalledLevelShare = 0.01;

// Each original (level-0) boundary point is represented by one vertex of the
// current level: itself until it is removed, then the neighbour it was handed
// to. The boundary test checks these points, so the error bound holds
// against the original surface, not just against the previous level.
struct Representation {
  std::vector<GridPoint> originals;
  std::vector<uint32_t> owner;  // grid-point index of the representing vertex

  Csr rows_for(std::span<const uint32_t> level_vertices, size_t grid_points) const {
    std::vector<uint32_t> local(grid_points, UINT32_MAX);
    for (uint32_t i = 0; i < level_vertices.size(); ++i) local[level_vertices[i]] = i;
    return build_csr(level_vertices.size(), [&](auto&& emit) {
      for (uint32_t k = 0; k < owner.size(); ++k) emit(local[owner[k]], k);
    });
  }
};

// `ids`: the grid-point index of each vertex of L; `error` measures the
// distance from the level-0 boundary vertices, level after level.
LevelStats measure(const LevelGeometry& L, std::span<const uint32_t> ids, SurfaceDistanceTracker* error) {
  LevelStats s;
  s.vertices = L.size();
  const MeshQuality q = mesh_quality(L);
  s.boundary_vertices = q.boundary_vertices;
  s.alpha = L.alpha;
  s.tetrahedra = L.mesh_cells;
  s.avg_min_solid_angle = q.avg_min_solid_angle;
  s.min_solid_angle = q.min_solid_angle;
  if (!error) return s;
  std::vector<std::array<uint32_t, 3>> surface;
  for (const BoundaryFace& f : boundary_faces(L.dt, L.in_mesh))
    surface.push_back(outward_triangle(L.dt, L.points, f));
  const DistanceSummary d = error->measure(L.points, ids, surface);
  s.max_boundary_error = d.max;
  s.mean_boundary_error = d.mean;
  return s;
}

// The quality guards' verdict on removing vertex v of level L, refilled by
// `fill`: its kept cells' smallest solid angle against the star's.
bool quality_allows(const LevelGeometry& L, uint32_t v, const Refill& fill, const HierarchyOptions& opt) {
  double star_min = std::numeric_limits<double>::infinity();
  for (uint32_t c : L.cells_of_vertex.row(v))
    if (L.in_mesh[c]) star_min = std::min(star_min, L.cell_min_solid_angle[c]);
  // No refill at all (a flat hull tip) is rejected: it removes volume.
  double fill_min = fill.cells.empty() ? 0.0 : std::numeric_limits<double>::infinity();
  for (size_t k = 0; k < fill.cells.size(); ++k) {
    if (!fill.kept[k]) continue;
    const auto& c = fill.cells[k];
    const std::array<Vec3, 4> t = {to_vec(L.points[c[0]]), to_vec(L.points[c[1]]), to_vec(L.points[c[2]]),
                                   to_vec(L.points[c[3]])};
    for (double a : solid_angles(t)) fill_min = std::min(fill_min, a);
  }
  if (opt.quality_guard > 0 && fill_min < std::min(opt.quality_guard, star_min)) return false;
  if (opt.quality_ratio > 0 && fill_min < opt.quality_ratio * star_min) return false;
  return true;
}

// The smallest solid angles of some cells, less the floor, summed: the
// level's average stays >= the floor while its cells' sum stays >= 0.
double surplus_of_star(const LevelGeometry& L, uint32_t v, double floor) {
  double s = 0;
  for (uint32_t c : L.cells_of_vertex.row(v))
    if (L.in_mesh[c]) s += L.cell_min_solid_angle[c] - floor;
  return s;
}

double surplus_of_fill(const LevelGeometry& L, const Refill& fill, double floor) {
  double s = 0;
  for (size_t k = 0; k < fill.cells.size(); ++k) {
    if (!fill.kept[k]) continue;
    const auto& c = fill.cells[k];
    const std::array<Vec3, 4> t = {to_vec(L.points[c[0]]), to_vec(L.points[c[1]]), to_vec(L.points[c[2]]),
                                   to_vec(L.points[c[3]])};
    const auto angles = solid_angles(t);
    s += *std::min_element(angles.begin(), angles.end()) - floor;
  }
  return s;
}

struct Removal {
  std::vector<uint8_t> removed;  // per local vertex
  uint64_t boundary = 0, interior = 0, rejected_by_quality = 0;
};

// Greedy independent set (the paper preset, alpha carving): boundary
// candidates by ascending error, then interior vertices by ascending
// importance; a removed vertex locks its Delaunay neighbours.
Removal select_removal(const LevelGeometry& L, const Csr& represented, const Representation& rep,
                       const HierarchyOptions& opt, double quality_floor) {
  Removal r;
  // With a quality floor: the level's surplus (see surplus_of_star) and the
  // removals that would spend some of it, which wait for the end of the pass.
  const bool hold_average = quality_floor > 0;
  double surplus = 0;
  if (hold_average)
    for (size_t c = 0; c < L.dt.cells.size(); ++c)
      if (L.in_mesh[c]) surplus += L.cell_min_solid_angle[c] - quality_floor;
  std::vector<std::pair<double, uint32_t>> waiting;  // (change of the surplus, vertex)
  r.removed.assign(L.size(), 0);
  std::vector<uint8_t> locked(L.size(), 0);
  const LevelSurface surface = level_surface(L);  // for the boundary candidates
  auto accept = [&](uint32_t v) {
    r.removed[v] = 1;
    locked[v] = 1;
    for (uint32_t u : L.neighbors.row(v)) locked[u] = 1;
  };
  auto free_to_take = [&](uint32_t v) { return !locked[v]; };
  // A candidate's verdict depends on the level as the pass found it, not on
  // what the pass takes before it: only whether it is still free does. So
  // candidates are judged a chunk at a time on every core, and the verdicts
  // applied in order.
  struct Verdict {
    enum Kind : uint8_t { kQuality, kWait, kTake } kind = kTake;
    double change = 0;  // of the surplus, with a quality floor
  };
  const bool quality_guarded = opt.quality_guard > 0 || opt.quality_ratio > 0 || hold_average;
  auto judge = [&](uint32_t v) -> Verdict {
    if (!quality_guarded) return {Verdict::kTake};
    const Refill fill = refill_of(L, v);
    if (!quality_allows(L, v, fill, opt)) return {Verdict::kQuality};
    if (!hold_average) return {Verdict::kTake};
    const double change = surplus_of_fill(L, fill, quality_floor) - surplus_of_star(L, v, quality_floor);
    return {change < 0 ? Verdict::kWait : Verdict::kTake, change};
  };
  auto apply = [&](uint32_t v, const Verdict& d) {
    switch (d.kind) {
      case Verdict::kQuality:
        ++r.rejected_by_quality;
        return false;
      case Verdict::kWait:
        waiting.emplace_back(d.change, v);
        return false;
      case Verdict::kTake:
        surplus += d.change;
        accept(v);
        return true;
    }
    return false;
  };
  // Takes what passes in `order`; returns how many.
  auto take_in_order = [&](std::span<const uint32_t> order) {
    constexpr size_t kChunk = 256;
    uint64_t taken = 0;
    std::vector<uint32_t> free;
    std::vector<Verdict> verdicts;
    for (size_t at = 0; at < order.size(); at += kChunk) {
      free.clear();
      for (size_t i = at; i < std::min(order.size(), at + kChunk); ++i)
        if (free_to_take(order[i])) free.push_back(order[i]);
      verdicts.assign(free.size(), {});
      parallel_for(
          free.size(), [&](size_t i) { verdicts[i] = judge(free[i]); }, 16);
      for (size_t i = 0; i < free.size(); ++i)
        if (free_to_take(free[i])) taken += apply(free[i], verdicts[i]);
    }
    return taken;
  };

  auto candidates = boundary_candidates(L, surface, represented, rep.originals, opt.dmax);
  std::sort(candidates.begin(), candidates.end(), [](const auto& a, const auto& b) {
    return a.error != b.error ? a.error < b.error : a.vertex < b.vertex;
  });
  std::vector<uint32_t> order;
  order.reserve(L.size());
  for (const auto& c : candidates) order.push_back(c.vertex);
  r.boundary += take_in_order(order);

  std::vector<std::pair<double, uint32_t>> interior;
  for (uint32_t v = 0; v < L.size(); ++v)
    if (!L.boundary[v]) interior.emplace_back(importance(L, v), v);
  std::sort(interior.begin(), interior.end());
  order.clear();
  for (const auto& [ip, v] : interior) order.push_back(v);
  r.interior += take_in_order(order);

  // Least damaging first, while the surplus lasts. A waiting vertex whose
  // neighbour was taken since is locked; otherwise its refill and verdicts
  // are as computed.
  std::stable_sort(waiting.begin(), waiting.end(),
                   [](const auto& a, const auto& b) { return a.first > b.first; });
  for (const auto& [change, v] : waiting) {
    if (!free_to_take(v)) continue;
    if (surplus + change < 0) {
      ++r.rejected_by_quality;
      continue;
    }
    surplus += change;
    accept(v);
    ++(L.boundary[v] ? r.boundary : r.interior);
  }
  return r;
}

// Hands the original points represented by removed vertices to their nearest
// surviving Delaunay neighbour (all neighbours survive: the set is independent).
void hand_over(Representation& rep, const LevelGeometry& L, std::span<const uint32_t> vertices,
               const Removal& r, const Csr& rows) {
  for (uint32_t v = 0; v < L.size(); ++v) {
    if (!r.removed[v]) continue;
    for (uint32_t k : rows.row(v)) {
      const Vec3 p = to_vec(rep.originals[k]);
      uint32_t best = UINT32_MAX;
      double best_d = std::numeric_limits<double>::infinity();
      for (uint32_t u : L.neighbors.row(v)) {
        const Vec3 e = to_vec(L.points[u]) - p;
        const double d = dot(e, e);
        if (d < best_d) best_d = d, best = u;
      }
      rep.owner[k] = vertices[best];
    }
  }
}

}  // namespace

StatusOr<Hierarchy> build_hierarchy(std::span<const GridPoint> points, const HierarchyOptions& opt,
                                    const LevelCallback& on_level) {
  if (opt.carve_to_reference) return build_codec_hierarchy(points, opt, on_level);
  // The paper preset: alpha carves, independent sets are removed by refill.
  Hierarchy h;
  std::vector<uint32_t> vertices(points.size());
  for (uint32_t i = 0; i < vertices.size(); ++i) vertices[i] = i;
  DTM_ASSIGN_OR_RETURN(TetMesh dt0, delaunay_tetrahedralize(points));
  DTM_ASSIGN_OR_RETURN(LevelGeometry L, analyze_level(gather(points, vertices), std::move(dt0), opt.alpha));

  Representation rep;
  for (uint32_t v = 0; v < L.size(); ++v)
    if (L.boundary[v]) {
      rep.originals.push_back(L.points[v]);
      rep.owner.push_back(vertices[v]);
    }

  // The tracker reads rep.originals in place: they never change (a
  // removal hands over their owners only, and a level undone below takes
  // back its owners, not their buffer).
  std::optional<SurfaceDistanceTracker> error;
  if (opt.measure_boundary_error) error.emplace(rep.originals);

  Removal made;  // what the passes that produced the current level removed
  int passes = 0;
  for (int level = 0;; ++level) {
    Level out;
    out.vertices = vertices;
    out.alpha = L.alpha;
    out.mesh = carved_cells(L, vertices);
    out.stats = measure(L, vertices, error ? &*error : nullptr);
    out.stats.level = level;
    out.stats.removed_boundary = made.boundary;
    out.stats.removed_interior = made.interior;
    out.stats.rejected_by_quality = made.rejected_by_quality;
    out.stats.passes = passes;
    h.levels.push_back(std::move(out));
    if (on_level) on_level(h.levels.back());

    if (opt.max_levels > 0 && level >= opt.max_levels) break;
    if (level > 0 && opt.stop_when_boundary_is_final && made.boundary == 0) break;
    // A stalled level (the quality floor lets almost nothing go) is not worth
    // another whole-level pass and layer: on bunny_1m the paper's rule alone
    // ran on for 120 levels of 0.05% each.
    if (level > 0 && opt.stop_when_boundary_is_final &&
        static_cast<double>(made.boundary + made.interior) <
            kStalledLevelShare * static_cast<double>(h.levels[level - 1].vertices.size()))
      break;

    // The passes that make the next level.
    made = {};
    passes = 0;
    const size_t finer = vertices.size();
    // A level that removes too little costs more bits than it is worth: it is
    // undone and the current level is the coarsest (see removal_share).
    struct Saved {
      LevelGeometry level;
      std::vector<uint32_t> vertices;
      Representation rep;
    };
    std::optional<Saved> before;
    if (opt.removal_share > 0) before = Saved{L, vertices, rep};
    do {
      const Csr represented = rep.rows_for(vertices, points.size());
      Removal next = select_removal(L, represented, rep, opt,
                                    opt.average_quality_floor * h.levels.front().stats.avg_min_solid_angle);
      const uint64_t removed = next.boundary + next.interior;
      if (removed == 0 || vertices.size() - removed < opt.min_base_vertices) break;

      std::vector<uint32_t> kept;
      kept.reserve(vertices.size() - removed);
      for (uint32_t v = 0; v < L.size(); ++v)
        if (!next.removed[v]) kept.push_back(vertices[v]);
      StatusOr<LevelGeometry> coarser = analyze_level(
          gather(points, kept),
          remove_independent_vertices(L.dt, L.cells_of_vertex, L.neighbors, L.points, next.removed),
          opt.alpha);
      // The coarser set would be flat: the current one is the coarsest.
      if (coarser.status().code() == StatusCode::kInvalidInput) break;
      if (!coarser.ok()) return coarser.status();
      hand_over(rep, L, vertices, next, represented);
      vertices = std::move(kept);
      L = std::move(coarser).value();
      made.boundary += next.boundary;
      made.interior += next.interior;
      made.rejected_by_quality += next.rejected_by_quality;
      ++passes;
    } while (static_cast<double>(finer - vertices.size()) < opt.removal_share * static_cast<double>(finer));
    if (passes == 0) break;
    if (before && static_cast<double>(finer - vertices.size()) <
                      kThinLevelShare * opt.removal_share * static_cast<double>(finer)) {
      L = std::move(before->level);
      vertices = std::move(before->vertices);
      rep.owner = std::move(before->rep.owner);
      break;
    }
  }
  return h;
}

std::vector<std::array<uint32_t, 4>> Level::carved_cells() const {
  if (kept.empty()) return mesh;
  std::vector<std::array<uint32_t, 4>> out;
  out.reserve(stats.tetrahedra);
  for (size_t c = 0; c < delaunay.cells.size(); ++c)
    if (kept[c]) out.push_back(delaunay.cells[c]);
  return out;
}

std::vector<std::array<uint32_t, 4>> canonical_cells(std::vector<std::array<uint32_t, 4>> cells) {
  for (auto& c : cells) std::sort(c.begin(), c.end());
  std::sort(cells.begin(), cells.end());
  return cells;
}

}  // namespace dtm
