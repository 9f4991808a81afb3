#include "core/level_build.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <optional>

#include "common/atomic_counts.h"
#include "common/parallel_for.h"
#include "common/parallel_sort.h"
#include "common/release.h"
#include "core/nearest_points.h"
#include "mesh/carving.h"
#include "mesh/delaunay.h"
#include "mesh/geometry.h"
#include "mesh/topology.h"

namespace dtm {
namespace {

using Key = std::array<uint32_t, 3>;

Key sorted_key(std::span<const uint32_t> ids, const std::array<uint32_t, 3>& t) {
  Key k = {ids[t[0]], ids[t[1]], ids[t[2]]};
  std::sort(k.begin(), k.end());
  return k;
}

// Whether `owned` (none: the whole level) owns a place with these corners:
// the box holds the lexicographically smallest one.
template <size_t N>
bool owns(const GridBox* owned, std::span<const GridPoint> points, const std::array<uint32_t, N>& corners) {
  if (!owned) return true;
  GridPoint least = points[corners[0]];
  for (size_t i = 1; i < N; ++i) least = std::min(least, points[corners[i]]);
  return owned->contains(least);
}

// A kept cell whose smallest solid angle is below this (steradians; the
// regular tetrahedron's is 0.55) and that has three or four faces on the
// surface is a fin (see the rounds below).
constexpr double kFinSolidAngle = 0.02;

struct Ball {
  std::array<double, 3> center;
  double radius;
};

// The circumscribed ball of a cell; radius 0 for a flat one (it is in
// conflict with nothing a repair could put back).
Ball circumball(std::span<const GridPoint> points, const std::array<uint32_t, 4>& cell) {
  const Vec3 a = to_vec(points[cell[0]]);
  const Vec3 u = to_vec(points[cell[1]]) - a, v = to_vec(points[cell[2]]) - a,
             w = to_vec(points[cell[3]]) - a;
  const double det = dot(u, cross(v, w));
  if (det == 0) return {{a.x, a.y, a.z}, 0};
  const Vec3 n = cross(v, w) * dot(u, u) + cross(w, u) * dot(v, v) + cross(u, v) * dot(w, w);
  const Vec3 c = a + n * (0.5 / det);
  return {{c.x, c.y, c.z}, norm(n) / (2 * std::abs(det))};
}

// Per cell of the current triangulation: the solid's verdict and, for a
// kept cell, its smallest solid angle. A round keeps the results of the
// cells the previous round's insertions left alone.
struct CellResults {
  std::vector<uint8_t> kept;
  std::vector<double> angle;
  std::vector<uint8_t> region;  // the solid's at the centroid, kept or not (Solid::verdicts)

  Status update(const TetMesh& mesh, std::span<const int32_t> previous, std::span<const GridPoint> points,
                const Solid& solid, double kept_radius) {
    std::vector<uint8_t> new_kept(mesh.cells.size()), new_region(mesh.cells.size());
    std::vector<double> new_angle(mesh.cells.size(), 0);
    std::vector<uint32_t> fresh;
    for (uint32_t c = 0; c < mesh.cells.size(); ++c) {
      const int32_t p = previous[c];
      if (p >= 0) {
        new_kept[c] = kept[static_cast<size_t>(p)];
        new_angle[c] = angle[static_cast<size_t>(p)];
        new_region[c] = region[static_cast<size_t>(p)];
      } else {
        fresh.push_back(c);
      }
    }
    DTM_RETURN_IF_ERROR(settled_pass(solid, [&] {
      parallel_for(
          fresh.size(),
          [&](size_t i) {
            const auto& k = mesh.cells[fresh[i]];
            const uint8_t region =
                solid.region_of_centroid(points[k[0]], points[k[1]], points[k[2]], points[k[3]]);
            const bool in = region != 0 && (kept_radius <= 0 || carving_radius(points, k) <= kept_radius);
            new_kept[fresh[i]] = in ? region : 0;
            new_region[fresh[i]] = region;
            new_angle[fresh[i]] = in ? smallest_solid_angle(points, k) : 0;
          },
          1024);
    }));
    kept = std::move(new_kept);
    angle = std::move(new_angle);
    region = std::move(new_region);
    return Status::Ok();
  }
};

// What the repair puts back: removed vertices of the finer level, found by place.
class RemovedVertices {
 public:
  RemovedVertices(std::span<const GridPoint> fine_points, std::span<const uint8_t> keep) {
    for (uint32_t v = 0; v < fine_points.size(); ++v)
      if (!keep[v]) vertex_.push_back(v);
    chosen_.assign(vertex_.size(), 0);
    index_live(fine_points);
  }
  size_t size() const { return vertex_.size(); }

  // The `count` removed vertices nearest the ball's centre, in it or on its
  // sphere, that are not put back or marked yet (indices of removed
  // vertices; equally near ones by index). On the sphere counts: grid points
  // are often cospherical, and the symbolic perturbation may put such a
  // point in conflict with the cell.
  std::vector<uint32_t> nearest(const Ball& b, size_t count, std::span<const GridPoint> fine_points) const {
    if (b.radius <= 0 || count == 0) return {};
    const double whole = b.radius * (1 + 1e-9) + 1e-9;
    const double whole2 = whole * whole;
    // The search's distances may differ from these in the last bits: it
    // goes on a little past the ball and past the count-th distance, and
    // the answer is sorted on the distances computed here.
    auto beyond = [](double searched, double limit) { return searched > limit * (1 + 1e-12) + 1e-9; };
    std::vector<std::pair<double, uint32_t>> near;
    double count_th = 0;
    index_->visit_nearest(b.center, [&](uint32_t i, double searched) {
      if (beyond(searched, whole2) || (near.size() >= count && beyond(searched, count_th))) return false;
      const uint32_t k = live_[i];
      if (chosen_[k]) return true;
      const GridPoint& p = fine_points[vertex_[k]];
      const double dx = p.x - b.center[0], dy = p.y - b.center[1], dz = p.z - b.center[2];
      const double d2 = dx * dx + dy * dy + dz * dz;
      if (d2 < whole2) {
        near.emplace_back(d2, k);
        if (near.size() == count)
          for (const auto& n : near) count_th = std::max(count_th, n.first);
      }
      return true;
    });
    const size_t taken = std::min(count, near.size());
    std::partial_sort(near.begin(), near.begin() + static_cast<std::ptrdiff_t>(taken), near.end());
    std::vector<uint32_t> out;
    for (size_t i = 0; i < taken; ++i) out.push_back(near[i].second);
    return out;
  }
  // What seek() found for a ball: its nearest as marked then, and whether
  // they are all the ball holds.
  struct Sought {
    std::vector<uint32_t> near;
    bool whole = false;
  };
  // The searches of take_nearest(ball, count) for several balls, made on
  // every core before any of them takes: each ball's count + kSeekMore
  // nearest as marked now. take_sought() then takes as take_nearest()
  // would at its turn: the nearest ones still unmarked are the first of
  // this list still unmarked (those beyond it are farther than all in it),
  // unless the marks between took so many that fewer than `count` are left
  // of a list that was cut short; then it searches again.
  std::vector<Sought> seek(std::span<const Ball> balls, size_t count,
                           std::span<const GridPoint> fine_points) {
    if (stale_ * 2 > live_.size() && live_.size() >= 1024) index_live(fine_points);
    std::vector<Sought> out(balls.size());
    parallel_for(
        balls.size(),
        [&](size_t i) {
          out[i].near = nearest(balls[i], count + kSeekMore, fine_points);
          out[i].whole = out[i].near.size() < count + kSeekMore;
        },
        16);
    return out;
  }
  size_t take_sought(const Sought& sought, const Ball& b, size_t count,
                     std::span<const GridPoint> fine_points) {
    std::vector<uint32_t> left;
    for (uint32_t k : sought.near)
      if (!marked(k) && left.size() < count) left.push_back(k);
    if (left.size() < count && !sought.whole) return take_nearest(b, count, fine_points);
    for (uint32_t k : left) mark(k);
    return left.size();
  }
  size_t take_nearest(const Ball& b, size_t count, std::span<const GridPoint> fine_points) {
    // A search walks past the marked vertices nearer than what it finds:
    // where a round marks most of a region, later searches there (the
    // fallback for far reference vertices, one per vertex) walked past all
    // of them, each (bunny_100k in blocks of 60,000: 770M visits, 90 s, in
    // one level). The index is made again of the unmarked ones once half
    // of it is marked; the answers are the same.
    if (stale_ * 2 > live_.size() && live_.size() >= 1024) index_live(fine_points);
    const std::vector<uint32_t> near = nearest(b, count, fine_points);
    for (uint32_t k : near) mark(k);
    return near.size();
  }
  void mark(uint32_t k) {
    stale_ += chosen_[k] == 0;
    chosen_[k] = 1;
  }
  bool marked(uint32_t k) const { return chosen_[k] != 0; }
  uint32_t vertex(uint32_t k) const { return vertex_[k]; }

  // The fine vertices marked since the last call.
  std::vector<uint32_t> collect() {
    std::vector<uint32_t> out;
    for (size_t k = 0; k < vertex_.size(); ++k)
      if (chosen_[k] == 1) {
        chosen_[k] = 2;
        out.push_back(vertex_[k]);
      }
    return out;
  }

 private:
  // The index of the removed vertices not marked or put back.
  void index_live(std::span<const GridPoint> fine_points) {
    live_.clear();
    std::vector<GridPoint> places;
    for (uint32_t k = 0; k < vertex_.size(); ++k)
      if (!chosen_[k]) {
        live_.push_back(k);
        places.push_back(fine_points[vertex_[k]]);
      }
    index_.reset();
    index_.emplace(places);
    stale_ = 0;
  }

  // How many more than asked seek() finds, for the marks made between.
  static constexpr size_t kSeekMore = 4;
  std::vector<uint32_t> vertex_;  // fine vertex of each removed one
  std::vector<uint8_t> chosen_;   // 0: still removed, 1: marked this round, 2: put back
  std::optional<NearestPoints> index_;
  std::vector<uint32_t> live_;  // the removed vertex at each place of the index
  size_t stale_ = 0;            // of them, marked since the index was made
};

// What inserting p into `mesh` would change, estimated: the cells whose
// circumsphere holds p (in doubles, boundary included), found from `start`
// (one of them) across faces, and the faces around them, each of which makes
// a new cell with p. False when the region reaches the convex hull or
// `start` does not hold p. (An estimate: where p is cospherical with a cell
// CGAL's symbolic perturbation decides; this only ranks candidates, the
// level is measured again after the real insertion.)
bool conflict_region(const TetMesh& mesh, std::span<const GridPoint> points, const GridPoint& p,
                     uint32_t start, std::vector<int32_t>& cells,
                     std::vector<std::array<uint32_t, 3>>& faces) {
  static constexpr int kFace[4][3] = {{1, 2, 3}, {0, 3, 2}, {0, 1, 3}, {0, 2, 1}};
  cells.clear();
  faces.clear();
  auto holds = [&](uint32_t c) {
    const Ball b = circumball(points, mesh.cells[c]);
    const double dx = p.x - b.center[0], dy = p.y - b.center[1], dz = p.z - b.center[2];
    return b.radius > 0 && dx * dx + dy * dy + dz * dz <= b.radius * b.radius * (1 + 1e-9);
  };
  if (!holds(start)) return false;
  cells.push_back(static_cast<int32_t>(start));
  for (size_t at = 0; at < cells.size(); ++at) {
    const auto c = static_cast<uint32_t>(cells[at]);
    for (int i = 0; i < 4; ++i) {
      const int32_t n = mesh.neighbors[c][i];
      if (n < 0) {
        // A hull face: p beyond (or on) its plane is outside the hull, where
        // insertion would also replace infinite cells; otherwise the face
        // bounds the region.
        const auto& k = mesh.cells[c];
        const Vec3 a = to_vec(points[k[kFace[i][0]]]), b = to_vec(points[k[kFace[i][1]]]),
                   d = to_vec(points[k[kFace[i][2]]]);
        const Vec3 normal = cross(b - a, d - a);
        if (dot(normal, to_vec(p) - a) * dot(normal, to_vec(points[k[i]]) - a) <= 0) return false;
        faces.push_back({k[kFace[i][0]], k[kFace[i][1]], k[kFace[i][2]]});
        continue;
      }
      if (std::find(cells.begin(), cells.end(), n) != cells.end()) continue;
      if (holds(static_cast<uint32_t>(n))) {
        cells.push_back(n);
      } else {
        const auto& k = mesh.cells[c];
        faces.push_back({k[kFace[i][0]], k[kFace[i][1]], k[kFace[i][2]]});
      }
    }
    if (cells.size() > 256) return false;  // not a local change
  }
  return true;
}

// The level's surplus over the quality floor: the sum over its carved cells
// of (smallest solid angle - floor); its average meets the floor while the
// surplus is >= 0 (the paper preset's rule, spec §6.4). Puts back, among the
// removed vertices nearest the circumcentres of the worst cells, those whose
// insertion raises the surplus most, each judged (on every core) on what it
// would change (the cells in conflict with it out, its star in), with
// disjoint changes, until the deficit is covered with a fifth to spare.
Status repair_quality(const TetMesh& mesh, const CellResults& cells, std::span<const GridPoint> points,
                      const Solid& solid, double floor, double kept_radius, const GridBox* owned,
                      RemovedVertices& removed) {
  // The cells the level's quality is taken over (a block's own: LevelBounds::owned).
  std::vector<uint8_t> counted(mesh.cells.size(), 1);
  if (owned)
    for (uint32_t c = 0; c < mesh.cells.size(); ++c) counted[c] = owns(owned, points, mesh.cells[c]);
  // The surplus over the floor and the cells below it, on every core: the
  // sums of fixed ranges, added in order, are the same for any number of
  // threads.
  constexpr size_t kRange = 16384;
  std::vector<double> partial((mesh.cells.size() + kRange - 1) / kRange, 0);
  using Scored = std::pair<double, uint32_t>;
  std::vector<Scored> worst =
      collect_in_order<Scored>(mesh.cells.size(), kRange, [&](size_t first, size_t last, auto& out) {
        double sum = 0;
        for (size_t c = first; c < last; ++c) {
          if (!cells.kept[c] || !counted[c]) continue;
          sum += cells.angle[c] - floor;
          if (cells.angle[c] < floor) out.emplace_back(cells.angle[c], static_cast<uint32_t>(c));
        }
        partial[first / kRange] = sum;
      });
  double surplus = 0;
  for (double p : partial) surplus += p;
  if (surplus >= 0) return Status::Ok();
  parallel_sort(worst.begin(), worst.end());  // distinct: by cell
  // Enough of the worst cells (at least 64) to find candidates for several
  // times the deficit.
  size_t searched = 0;
  for (double naive = 0; searched < worst.size() && (searched < 64 || naive < -4 * surplus); ++searched)
    naive += floor - worst[searched].first;
  // Each cell's nearest removed vertices, on every core (nothing is marked
  // while they are sought).
  std::vector<std::vector<uint32_t>> near(searched);
  parallel_for(
      searched,
      [&](size_t i) {
        near[i] = removed.nearest(circumball(points, mesh.cells[worst[i].second]), 3, points);
      },
      64);
  std::vector<std::pair<uint32_t, uint32_t>> candidates;  // (removed vertex, a cell holding it)
  for (size_t i = 0; i < searched; ++i)
    for (uint32_t k : near[i]) candidates.emplace_back(k, worst[i].second);
  release(near);
  parallel_sort(candidates.begin(), candidates.end());
  candidates.erase(std::unique(candidates.begin(), candidates.end(),
                               [](const auto& a, const auto& b) { return a.first == b.first; }),
                   candidates.end());
  struct Option {
    double gain = 0;
    uint32_t k = 0;
    std::vector<int32_t> cells;
  };
  std::vector<Option> options(candidates.size());
  DTM_RETURN_IF_ERROR(settled_pass(solid, [&] {
    parallel_for(
        candidates.size(),
        [&](size_t i) {
          thread_local std::vector<std::array<uint32_t, 3>> faces;
          Option& o = options[i];
          o = Option{};
          o.k = candidates[i].first;
          const uint32_t v = removed.vertex(o.k);
          if (!conflict_region(mesh, points, points[v], candidates[i].second, o.cells, faces)) {
            o.cells.clear();
            return;
          }
          for (int32_t c : o.cells)
            if (cells.kept[static_cast<size_t>(c)] && counted[static_cast<size_t>(c)])
              o.gain -= cells.angle[static_cast<size_t>(c)] - floor;
          for (const auto& f : faces)
            if (solid.contains_centroid(points[v], points[f[0]], points[f[1]], points[f[2]]) &&
                (kept_radius <= 0 || carving_radius(points, {v, f[0], f[1], f[2]}) <= kept_radius) &&
                owns(owned, points, std::array<uint32_t, 4>{v, f[0], f[1], f[2]}))
              o.gain += smallest_solid_angle(points, {v, f[0], f[1], f[2]}) - floor;
        },
        32);
  }));
  std::erase_if(options, [](const Option& o) { return o.cells.empty() || o.gain <= 0; });
  std::stable_sort(options.begin(), options.end(),
                   [](const Option& a, const Option& b) { return a.gain > b.gain; });
  std::vector<uint8_t> touched(mesh.cells.size(), 0);
  const double goal = -0.2 * surplus;
  for (const Option& o : options) {
    if (surplus >= goal) break;
    bool free = !removed.marked(o.k);
    for (int32_t c : o.cells) free = free && !touched[static_cast<size_t>(c)];
    if (!free) continue;
    for (int32_t c : o.cells) touched[static_cast<size_t>(c)] = 1;
    removed.mark(o.k);
    surplus += o.gain;
  }
  return Status::Ok();
}

}  // namespace

CarvedSurface carved_surface(const TetMesh& dt, std::span<const uint8_t> kept,
                             std::span<const GridPoint> points) {
  CarvedSurface s;
  // The boundary faces in cell order, found on every core.
  const std::vector<BoundaryFace> faces =
      collect_in_order<BoundaryFace>(dt.cells.size(), 16384, [&](size_t first, size_t last, auto& out) {
        for (size_t c = first; c < last; ++c) {
          if (!kept[c]) continue;
          for (uint8_t i = 0; i < 4; ++i) {
            const int32_t n = dt.neighbors[c][i];
            if (n < 0 || !kept[static_cast<size_t>(n)]) out.push_back({static_cast<uint32_t>(c), i});
          }
        }
      });
  s.triangles.resize(faces.size());
  s.cells.resize(faces.size());
  parallel_ranges(faces.size(), 8192, [&](size_t first, size_t last) {
    for (size_t i = first; i < last; ++i) {
      const BoundaryFace& f = faces[i];
      s.triangles[i] = outward_triangle(dt, points, f);
      s.cells[i] = {static_cast<int32_t>(f.cell), dt.neighbors[f.cell][f.opposite]};
    }
  });
  // The interfaces between regions, each face once (from its cell of the
  // lower index), are measured as the boundary is. Without regions (no
  // cell's region above 1) there are none: no pass over the cells.
  if (std::none_of(kept.begin(), kept.end(), [](uint8_t r) { return r > 1; })) return s;
  for (uint32_t c = 0; c < dt.cells.size(); ++c) {
    if (!kept[c]) continue;
    for (int i = 0; i < 4; ++i) {
      const int32_t n = dt.neighbors[c][static_cast<size_t>(i)];
      if (n <= static_cast<int32_t>(c) || !kept[static_cast<size_t>(n)] ||
          kept[static_cast<size_t>(n)] == kept[c])
        continue;
      const BoundaryFace f{c, static_cast<uint8_t>(i)};
      s.triangles.push_back(outward_triangle(dt, points, f));
      s.cells.push_back({static_cast<int32_t>(c), n});
    }
  }
  return s;
}

SurfaceRecord record_surface(std::span<const uint32_t> ids,
                             std::span<const std::array<uint32_t, 3>> triangles,
                             const ShapeMeasurement& measured) {
  SurfaceRecord r;
  r.triangles.reserve(triangles.size());
  for (const auto& t : triangles) r.triangles.push_back(sorted_key(ids, t));
  std::sort(r.triangles.begin(), r.triangles.end());
  for (uint32_t v : measured.surface_vertices) r.vertices.push_back(ids[v]);
  std::sort(r.vertices.begin(), r.vertices.end());
  r.reference_squared = measured.reference_squared;
  return r;
}

StatusOr<BuiltLevel> build_coarser_level(std::span<const GridPoint> fine_points,
                                         std::span<const uint32_t> fine_vertices,
                                         const SurfaceRecord& fine_surface, std::span<const uint8_t> keep,
                                         const LevelReference& ref, const LevelBounds& bounds,
                                         const AlphaPolicy& alpha,
                                         const std::function<void(const char*)>& phase) {
  const std::span<const GridPoint> points = fine_points;  // the build names vertices by their fine index
  BuiltLevel out;
  std::vector<uint32_t> chosen;
  for (uint32_t v = 0; v < points.size(); ++v)
    if (keep[v]) chosen.push_back(v);
  out.chosen = chosen.size();
  // The triangulation and the removed vertices' index live through the
  // rounds only: they are gone before the level is analysed.
  auto dt = std::make_unique<IncrementalDelaunay>();
  phase("Delaunay tetrahedralization");
  DTM_RETURN_IF_ERROR(dt->insert(gather(points, chosen), chosen));
  release(chosen);
  if (dt->dimension() < 3)
    return Status{StatusCode::kInvalidInput, "the coarser level does not span three dimensions"};
  auto removed = std::make_unique<RemovedVertices>(points, keep);
  const double dmax2 = bounds.dmax * bounds.dmax;
  const std::span<const GridPoint> reference_points = ref.shape->boundary_points();

  TetMesh mesh;
  CellResults cells;
  CarvedSurface surface;
  for (int round = 0;; ++round) {
    std::vector<int32_t> previous;
    phase(round == 0 ? "carving to the reference" : "carving the repaired places");
    mesh = dt->mesh(mesh, previous);
    DTM_RETURN_IF_ERROR(cells.update(mesh, previous, points, *ref.solid, bounds.kept_radius));
    phase("measuring the shape");
    surface = carved_surface(mesh, cells.kept, points);
    out.shape = ref.shape->measure(points, fine_vertices, surface.triangles);

    double sum = 0;
    uint64_t count = 0;
    for (size_t c = 0; c < mesh.cells.size(); ++c)
      if (cells.kept[c] && owns(bounds.owned, points, mesh.cells[c])) sum += cells.angle[c], ++count;
    out.quality = count ? sum / static_cast<double>(count) : 0;
    out.quality_sum = sum;
    out.quality_cells = count;
    // A block owning no kept cell has no quality of its own to keep.
    out.quality_met =
        bounds.quality_floor <= 0 || (bounds.owned && count == 0) || out.quality >= bounds.quality_floor;

    // The places beyond D_max this level made (not inherited), and what
    // would change them.
    std::vector<uint8_t> far_triangle(surface.triangles.size(), 0);
    std::vector<uint8_t> far_vertex(points.size(), 0);
    for (size_t i = 0; i < out.shape.surface_vertices.size(); ++i)
      if (out.shape.vertex_squared[i] > dmax2) {
        const uint32_t v = out.shape.surface_vertices[i];
        if (!std::binary_search(fine_surface.vertices.begin(), fine_surface.vertices.end(), fine_vertices[v]))
          far_vertex[v] = 1;
      }
    uint64_t broken = 0;
    for (size_t t = 0; t < surface.triangles.size(); ++t) {
      const auto& tri = surface.triangles[t];
      const bool far = out.shape.centroid_squared[t] > dmax2 || far_vertex[tri[0]] || far_vertex[tri[1]] ||
                       far_vertex[tri[2]];
      if (far && owns(bounds.owned, points, tri) &&
          !std::binary_search(fine_surface.triangles.begin(), fine_surface.triangles.end(),
                              sorted_key(fine_vertices, tri)))
        far_triangle[t] = 1, ++broken;
    }
    std::vector<uint32_t> far_reference;
    for (uint32_t i = 0; i < out.shape.reference_squared.size(); ++i) {
      const double d2 = out.shape.reference_squared[i];
      if (d2 > dmax2 && d2 > fine_surface.reference_squared[i] * (1 + 1e-9) + 1e-9 &&
          (!bounds.owned || bounds.owned->contains(reference_points[i])))
        far_reference.push_back(i);
    }
    broken += far_reference.size();
    out.shape_left = broken;
    // Fins and slots: nearly flat cells with three or four faces on the
    // surface, kept (a thin flap) or not (a thin slot into the solid), which
    // a viewer shows as lines even when they lie within D_max. Repaired
    // where something removed is in conflict with them; one that cannot be
    // does not hold the level back.
    std::vector<uint32_t> fins;
    {
      std::vector<uint8_t> inside_faces(mesh.cells.size(), 0), outside_faces(mesh.cells.size(), 0);
      for (const auto& [inside, outside] : surface.cells) {
        ++inside_faces[static_cast<size_t>(inside)];
        if (outside >= 0) ++outside_faces[static_cast<size_t>(outside)];
      }
      fins = collect_in_order<uint32_t>(
          mesh.cells.size(), 16384, [&](size_t first, size_t last, std::vector<uint32_t>& found) {
            for (auto c = static_cast<uint32_t>(first); c < last; ++c)
              if (!owns(bounds.owned, points, mesh.cells[c])) {
                continue;
              } else if ((inside_faces[c] >= 3 && cells.angle[c] < kFinSolidAngle) ||
                         (outside_faces[c] >= 3 &&
                          smallest_solid_angle(points, mesh.cells[c]) < kFinSolidAngle))
                found.push_back(c);
          });
    }
    out.fins_left = fins.size();
    if (broken == 0 && out.quality_met && fins.empty()) break;
    if (round == bounds.repair_rounds) break;

    phase("choosing what to put back");
    // Where a place stays broken round after round, more of what is near it
    // comes back each time: 2, 3, 4, ... vertices per cell at fault.
    const size_t per_place = 2 + static_cast<size_t>(round);
    // The balls whose nearest removed vertices come back, in the order they
    // take them: each fin's; for a far triangle, those of the cells on both
    // sides of it (what they are in conflict with: each vertex put back
    // destroys the cell); for a far reference vertex, those of the cells
    // beside the triangle nearest it (`reference_of` says whose: the balls
    // of one reference vertex follow each other), or if they take nothing,
    // the removed vertex nearest it, however far: progress. Their searches
    // are made on every core first (seek()), the taking in order after.
    std::vector<Ball> balls;
    std::vector<uint32_t> reference_of;
    balls.reserve(fins.size());
    for (uint32_t c : fins) balls.push_back(circumball(points, mesh.cells[c]));
    for (size_t t = 0; t < surface.triangles.size(); ++t) {
      if (!far_triangle[t]) continue;
      for (int32_t c : surface.cells[t])
        if (c >= 0) balls.push_back(circumball(points, mesh.cells[static_cast<size_t>(c)]));
    }
    const size_t before_references = balls.size();
    if (!far_reference.empty()) {
      // The triangle nearest each far reference vertex, by its grid ids.
      std::vector<std::pair<Key, uint32_t>> by_key;
      by_key.reserve(surface.triangles.size());
      for (uint32_t t = 0; t < surface.triangles.size(); ++t)
        by_key.emplace_back(sorted_key(fine_vertices, surface.triangles[t]), t);
      std::sort(by_key.begin(), by_key.end());
      for (uint32_t i : far_reference) {
        const Key key = ref.shape->nearest_triangle(i);
        const auto it = std::lower_bound(by_key.begin(), by_key.end(), std::pair<Key, uint32_t>{key, 0});
        if (it != by_key.end() && it->first == key)
          for (int32_t c : surface.cells[it->second])
            if (c >= 0) {
              balls.push_back(circumball(points, mesh.cells[static_cast<size_t>(c)]));
              reference_of.push_back(i);
            }
      }
    }
    const std::vector<RemovedVertices::Sought> sought = removed->seek(balls, per_place, points);
    for (size_t j = 0; j < before_references; ++j)
      removed->take_sought(sought[j], balls[j], per_place, points);
    for (size_t j = before_references, at = 0; at < far_reference.size(); ++at) {
      const uint32_t i = far_reference[at];
      size_t taken = 0;
      for (; j < balls.size() && reference_of[j - before_references] == i; ++j)
        taken += removed->take_sought(sought[j], balls[j], per_place, points);
      const GridPoint& p = reference_points[i];
      for (double r = 2 * std::sqrt(out.shape.reference_squared[i]); taken == 0 && r < 1e8; r *= 4)
        taken = removed->take_nearest({{double(p.x), double(p.y), double(p.z)}, r}, per_place / 2, points);
    }
    if (!out.quality_met)
      DTM_RETURN_IF_ERROR(repair_quality(mesh, cells, points, *ref.solid, bounds.quality_floor,
                                         bounds.kept_radius, bounds.owned, *removed));
    const std::vector<uint32_t> back = removed->collect();
    if (back.empty()) break;  // nothing left to put back where a bound breaks
    out.put_back += back.size();
    ++out.repair_rounds;
    phase("putting vertices back");
    DTM_RETURN_IF_ERROR(dt->insert(gather(points, back), back));
  }

  dt.reset();
  removed.reset();
  // The level in its own numbering: its vertices in ascending grid order.
  phase("analysing the level");
  std::vector<uint32_t> local(points.size(), UINT32_MAX);
  std::vector<uint32_t> members;
  {
    // Marked on every core (every thread writes the same 1).
    std::vector<uint8_t> in_level(points.size(), 0);
    parallel_ranges(mesh.cells.size(), 16384, [&](size_t first, size_t last) {
      for (size_t c = first; c < last; ++c)
        for (uint32_t v : mesh.cells[c]) atomic_store(in_level[v], 1);
    });
    for (uint32_t v = 0; v < points.size(); ++v)
      if (in_level[v]) {
        local[v] = static_cast<uint32_t>(members.size());
        members.push_back(v);
      }
  }
  parallel_ranges(mesh.cells.size(), 16384, [&](size_t first, size_t last) {
    for (size_t c = first; c < last; ++c)
      for (uint32_t& v : mesh.cells[c]) v = local[v];
  });
  parallel_ranges(surface.triangles.size(), 16384, [&](size_t first, size_t last) {
    for (size_t t = first; t < last; ++t)
      for (uint32_t& v : surface.triangles[t]) v = local[v];
  });
  out.vertices.reserve(members.size());
  for (uint32_t v : members) out.vertices.push_back(fine_vertices[v]);
  if (!bounds.analyze) {
    // In the level's numbering: what a caller may analyse later.
    out.geometry.dt = std::move(mesh);
    out.solid_regions = std::move(cells.region);
    return out;
  }
  for (uint32_t& v : out.shape.surface_vertices) v = local[v];
  out.surface = record_surface(out.vertices, surface.triangles, out.shape);
  DTM_ASSIGN_OR_RETURN(out.geometry,
                       analyze_level(gather(points, members), std::move(mesh), alpha, cells.kept));
  return out;
}

}  // namespace dtm
