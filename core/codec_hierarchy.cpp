#include "core/codec_hierarchy.h"

#include <optional>
#include <string>

#include "common/parallel_for.h"
#include "common/release.h"
#include "core/coarsening.h"
#include "core/level_build.h"
#include "core/reference_shape.h"
#include "core/reference_solid.h"
#include "core/region_solid.h"
#include "mesh/delaunay.h"

namespace dtm {
namespace {

// Levels smaller than this are kept until the next one is accepted, so that
// a failed try can be made again removing fewer (a larger level is handed on
// as soon as the next one's vertices are chosen: memory).
constexpr size_t kRetriedBelow = 100'000;

// The level as the hierarchy hands it on, but for its tetrahedralization
// (hand_over()): its vertices (grid ids) and its figures.
Level describe(const LevelGeometry& L, std::span<const uint32_t> vertices, int index,
               const ShapeMeasurement& shape) {
  Level out;
  out.vertices.assign(vertices.begin(), vertices.end());
  out.alpha = L.alpha;
  LevelStats& s = out.stats;
  s.level = index;
  s.vertices = L.size();
  const MeshQuality q = mesh_quality(L);
  s.boundary_vertices = q.boundary_vertices;
  s.alpha = L.alpha;
  s.tetrahedra = L.mesh_cells;
  s.avg_min_solid_angle = q.avg_min_solid_angle;
  s.min_solid_angle = q.min_solid_angle;
  // The boundary error is measured from the reference's boundary vertices
  // (level 0's boundary, when level 0's carving is the reference).
  s.max_boundary_error = shape.to_level.max;
  s.mean_boundary_error = shape.to_level.mean;
  s.reference_shape =
      ShapeFigures{shape.to_level, shape.to_reference, shape.both, shape.reference_squared.size()};
  return out;
}

// The working level's tetrahedralization and carving move into the level
// handed on (grid ids): one copy of a level's cells, never two.
void hand_over(Level& out, LevelGeometry& L) {
  out.delaunay = std::move(L.dt);
  for (auto& c : out.delaunay.cells)
    for (uint32_t& v : c) v = out.vertices[v];
  out.kept = std::move(L.in_mesh);
}

// The analysis the codec's builder does not read again (the paper preset's
// importance and refills use them): freed, a level being large.
void drop_unused(LevelGeometry& L) {
  L.cells_of_vertex = {};
  release(L.solid_angle_sum);
  release(L.mesh_volume6);
}

}  // namespace

StatusOr<Hierarchy> build_codec_hierarchy(std::span<const GridPoint> points, const HierarchyOptions& opt,
                                          const LevelCallback& on_level) {
  if (opt.quality_guard > 0 || opt.quality_ratio > 0)
    return Status{StatusCode::kInvalidInput,
                  "the per-removal quality rules (quality guard, quality ratio) belong to the paper preset's "
                  "independent sets; the codec preset keeps the average quality floor"};
  Hierarchy h;
  std::vector<uint32_t> vertices(points.size());
  for (uint32_t i = 0; i < vertices.size(); ++i) vertices[i] = i;

  // Level 0 and the reference: the input's tetrahedra, the solid given (a
  // scan's voxels), or level 0's alpha carving. Without tetrahedra, level
  // 0's carved surface is the shape the levels are held to.
  const auto phase = [&](int level, const char* what) {
    report_phase(opt.on_phase, "level " + std::to_string(level) + ": " + what);
  };
  phase(0, "Delaunay tetrahedralization");
  DTM_ASSIGN_OR_RETURN(TetMesh dt0, delaunay_tetrahedralize(points));
  std::optional<ReferenceShape> shape;
  std::optional<ReferenceSolid> solid;
  std::optional<RegionSolid> regions;  // a reference of several regions
  const Solid* carving = nullptr;      // what every level is carved to
  std::vector<std::array<uint32_t, 4>> level0_cells;
  std::vector<int32_t> match;  // per level-0 cell, the reference tetrahedron it is
  std::optional<LevelGeometry> L;
  if (!opt.reference_cells.empty()) {
    phase(0, "the reference solid");
    const std::span<const uint8_t> region = opt.reference_regions;
    if (!region.empty() && region.size() != opt.reference_cells.size())
      return Status{StatusCode::kInvalidInput, "a region is needed for every reference tetrahedron"};
    if (region.empty()) {
      shape.emplace(points, opt.reference_cells);
      carving = &solid.emplace(points, opt.reference_cells, shape->boundary_triangles());
    } else {
      shape.emplace(points, opt.reference_cells, region);
      carving = &regions.emplace(points, opt.reference_cells, region);
    }
    std::vector<uint8_t> verdicts;
    phase(0, "carving to the reference");
    {
      // A Delaunay cell that is one of the solid's own tetrahedra holds its
      // centroid: no test needed (the most of level 0's cells).
      match = matching_tetrahedra(dt0, points.size(), opt.reference_cells);
      verdicts.resize(dt0.cells.size());
      parallel_for((dt0.cells.size() + 4095) / 4096,
                   [&](size_t block) {
                     for (size_t c = block * 4096; c < std::min(dt0.cells.size(), block * 4096 + 4096); ++c) {
                       const auto& k = dt0.cells[c];
                       const int32_t t = match[c];
                       verdicts[c] = t < 0 ? carving->region_of_centroid(points[k[0]], points[k[1]],
                                                                         points[k[2]], points[k[3]])
                                     : region.empty() ? 1
                                                      : region[static_cast<size_t>(t)];
                     }
                   },
                   2);
    }
    phase(0, "analysing the level");
    DTM_ASSIGN_OR_RETURN(L, analyze_level(gather(points, vertices), std::move(dt0), opt.alpha, verdicts));
  } else if (opt.reference_solid) {
    phase(0, "carving to the reference");
    const std::vector<uint8_t> verdicts = opt.reference_solid->verdicts(dt0, points);
    phase(0, "analysing the level");
    DTM_ASSIGN_OR_RETURN(L, analyze_level(gather(points, vertices), std::move(dt0), opt.alpha, verdicts));
    carving = opt.reference_solid;
    level0_cells = carved_cells(*L, vertices);
    phase(0, "the reference shape");
    shape.emplace(points, level0_cells);
  } else {
    phase(0, "analysing the level");
    DTM_ASSIGN_OR_RETURN(L, analyze_level(gather(points, vertices), std::move(dt0), opt.alpha));
    level0_cells = carved_cells(*L, vertices);
    phase(0, "the reference solid");
    shape.emplace(points, level0_cells);
    carving = &solid.emplace(points, level0_cells, shape->boundary_triangles());
  }
  drop_unused(*L);
  const LevelReference reference{carving, &*shape};
  h.reference_boundary_vertices = shape->boundary_vertices();

  phase(0, "measuring the shape");
  const CarvedSurface surface0 = carved_surface(L->dt, L->in_mesh, L->points);
  const ShapeMeasurement shape0 = shape->measure(L->points, vertices, surface0.triangles);
  SurfaceRecord record = record_surface(vertices, surface0.triangles, shape0);
  if (!match.empty()) {
    phase(0, "its solid against the reference");
    h.level0_difference = carved_difference(points, L->dt, L->in_mesh, opt.reference_cells, *carving, match);
    release(match);
  }
  h.levels.push_back(describe(*L, vertices, 0, shape0));

  LevelBounds bounds;
  bounds.dmax = opt.dmax;
  bounds.quality_floor = opt.average_quality_floor * h.levels.front().stats.avg_min_solid_angle;
  if (opt.quality_floor_cap > 0) bounds.quality_floor = std::min(bounds.quality_floor, opt.quality_floor_cap);
  const double share = opt.removal_share > 0 ? opt.removal_share : kDefaultRemovalShare;
  double beta = kFirstBetaGuess;  // the spacing factor of the last choice: where the next search starts
  // A level is handed on, tetrahedralization and all, once the next one's
  // vertices are chosen (the choice is the last to read it), or at the end.
  auto complete_last = [&] {
    hand_over(h.levels.back(), *L);
    L.reset();
    if (on_level) on_level(h.levels.back());
  };
  for (int level = 1;; ++level) {
    if (opt.max_levels > 0 && level > opt.max_levels) break;
    const size_t finer = vertices.size();
    // The finer level's build freed more than the coarser one will need.
    give_back_free_heap();
    // A level that breaks a bound (or comes out thin) is tried once more
    // choosing fewer to remove (kRetryShare of the share): coarse levels,
    // where the boundary dominates, often hold the bounds that way. The second try needs the finer level,
    // which small levels keep until then; large ones are handed on at once.
    std::optional<BuiltLevel> accepted;
    std::vector<uint8_t> fine_boundary;
    for (const double attempt : {share, kRetryShare * share}) {
      if (!L) break;
      phase(level, attempt == share ? "choosing the vertices" : "choosing again, fewer");
      const Coarsening choice = choose_coarser(*L, level_surface(*L), {1 - attempt, opt.dmax, beta});
      if (attempt == share) beta = choice.beta;
      // What the build needs of the finer level: its points, and which were
      // on its boundary (for the figures).
      std::vector<GridPoint> fine_points = L->points;
      fine_boundary = L->boundary;
      if (finer >= kRetriedBelow) complete_last();
      StatusOr<BuiltLevel> built =
          build_coarser_level(fine_points, vertices, record, choice.keep, reference, bounds, opt.alpha,
                              [&](const char* what) { phase(level, what); });
      // The coarser set would be flat: the current one is the coarsest.
      if (built.status().code() == StatusCode::kInvalidInput) break;
      if (!built.ok()) return built.status();
      const size_t coarser = built->vertices.size();
      if (coarser < opt.min_base_vertices) break;
      if (static_cast<double>(finer - coarser) < kThinLevelShare * share * static_cast<double>(finer) ||
          !built->quality_met || built->shape_left > 0)
        continue;
      accepted = std::move(built).value();
      break;
    }
    if (L) complete_last();
    if (!accepted) break;  // the finer level is the coarsest
    BuiltLevel* built = &*accepted;
    const size_t coarser = built->vertices.size();

    uint64_t removed_boundary = 0;
    {
      size_t k = 0;
      for (uint32_t v = 0; v < finer; ++v) {
        const bool kept = k < coarser && built->vertices[k] == vertices[v];
        if (kept)
          ++k;
        else
          removed_boundary += fine_boundary[v];
      }
    }
    Level out = describe(built->geometry, built->vertices, level, built->shape);
    out.stats.removed_boundary = removed_boundary;
    out.stats.removed_interior = finer - coarser - removed_boundary;
    out.stats.passes = 1;
    out.stats.chosen = built->chosen;
    out.stats.put_back = built->put_back;
    out.stats.repair_rounds = built->repair_rounds;
    h.levels.push_back(std::move(out));

    vertices = std::move(built->vertices);
    record = std::move(built->surface);
    L = std::move(built->geometry);
    drop_unused(*L);
    if (opt.stop_when_boundary_is_final && removed_boundary == 0) break;
  }
  if (L) complete_last();
  return h;
}

}  // namespace dtm
