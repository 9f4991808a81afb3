#include "codec/blocks/block_levels.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <numeric>

#include "codec/bricks/bricks.h"
#include "codec/sections/carving_coder.h"
#include "codec/sections/cell_value_coder.h"
#include "codec/sections/face_coder.h"
#include "codec/sections/region_coder.h"
#include "codec/stream/format.h"
#include "common/parallel_for.h"
#include "common/parallel_sort.h"
#include "common/release.h"
#include "mesh/carving.h"
#include "mesh/geometry.h"
#include "mesh/topology.h"

namespace dtm {
namespace {

// The Morton ranges of the bricks covering `box`, at a depth where there
// are at most about 8 of them along each axis.
std::vector<std::pair<MortonCode, MortonCode>> ranges_covering(const GridBox& box, int qbits) {
  const GridBox clipped = box.grown(0, qbits);
  std::vector<std::pair<MortonCode, MortonCode>> out;
  if (clipped.empty()) return out;
  int64_t extent = 1;
  for (int a = 0; a < 3; ++a) extent = std::max(extent, clipped.hi[a] - clipped.lo[a] + 1);
  int depth = qbits;
  while (depth > 0 && (extent >> (qbits - depth)) > 8) --depth;
  const int shift = 3 * (qbits - depth);
  for (uint64_t brick : bricks_meeting(clipped, qbits, depth)) {
    const MortonCode first = MortonCode{brick} << shift;
    if (!out.empty() && out.back().second == first)
      out.back().second = MortonCode{brick + 1} << shift;  // adjacent bricks: one range
    else
      out.emplace_back(first, MortonCode{brick + 1} << shift);
  }
  return out;
}

// Stretches [begin, end) of a sorted array, seen as one run of positions
// 0 .. size(): what a scan of several ranges hands out to every core.
class Stretches {
 public:
  void add(size_t begin, size_t end) {
    if (begin >= end) return;
    stretches_.emplace_back(begin, end);
    before_.push_back(before_.back() + (end - begin));
  }
  size_t size() const { return before_.back(); }
  // f(array position) for the run's positions [first, last), in order.
  template <class F>
  void for_each(size_t first, size_t last, const F& f) const {
    size_t s =
        static_cast<size_t>(std::upper_bound(before_.begin(), before_.end(), first) - before_.begin()) - 1;
    for (size_t k = first; k < last; ++k) {
      while (k >= before_[s + 1]) ++s;
      f(stretches_[s].first + (k - before_[s]));
    }
  }

 private:
  std::vector<std::pair<size_t, size_t>> stretches_;
  std::vector<size_t> before_{0};  // positions in the run before each stretch
};

// Items a thread scans at a time.
constexpr size_t kScan = 16384;

template <size_t N>
bool owns(const GridBox& owned, std::span<const GridPoint> points, const std::array<uint32_t, N>& corners) {
  GridPoint least = points[corners[0]];
  for (size_t i = 1; i < N; ++i) least = std::min(least, points[corners[i]]);
  return owned.contains(least);
}

}  // namespace

MortonIndex::MortonIndex(std::span<const GridPoint> points, int qbits) : qbits_(qbits), points_(points) {
  // The codes for the sort only, in 8 bytes where they fit (3 qbits of 64:
  // a code takes 16), 4 bytes a point after.
  ids_.resize(points.size());
  std::iota(ids_.begin(), ids_.end(), 0u);
  const auto sort_by = [&](auto code_type) {
    using Code = decltype(code_type);
    std::vector<Code> codes(points.size());
    for (uint32_t i = 0; i < points.size(); ++i)
      codes[i] = static_cast<Code>(morton_encode(points[i], qbits));
    std::sort(ids_.begin(), ids_.end(),
              [&](uint32_t a, uint32_t b) { return codes[a] != codes[b] ? codes[a] < codes[b] : a < b; });
  };
  if (3 * qbits <= 64)
    sort_by(uint64_t{});
  else
    sort_by(MortonCode{});
}

size_t MortonIndex::first_at(MortonCode code) const {
  return static_cast<size_t>(std::lower_bound(ids_.begin(), ids_.end(), code,
                                              [&](uint32_t id, MortonCode c) { return code_of(id) < c; }) -
                             ids_.begin());
}

std::vector<uint32_t> MortonIndex::inside(const GridBox& box, std::span<const uint8_t> level_of,
                                          int level) const {
  // The index's stretches the box's bricks cover, each found by two binary
  // searches (a code made a step, not a point: a code made for every point
  // scanned was a second of one thread at bunny_1m's level 0).
  Stretches stretches;
  for (const auto& [first, last] : ranges_covering(box, qbits_)) {
    stretches.add(first_at(first), first_at(last));
  }
  std::vector<uint32_t> out = collect_in_order<uint32_t>(
      stretches.size(), kScan, [&](size_t first, size_t last, std::vector<uint32_t>& part) {
        stretches.for_each(first, last, [&](size_t i) {
          const uint32_t id = ids_[i];
          if (level_of[id] >= level && box.contains(points_[id])) part.push_back(id);
        });
      });
  parallel_sort(out.begin(), out.end());
  return out;
}

void MortonIndex::between(MortonCode first, MortonCode last, std::span<const uint8_t> level_of, int level,
                          std::vector<MortonCode>& codes, std::vector<uint32_t>* ids) const {
  codes.clear();
  if (ids) ids->clear();
  for (size_t i = first_at(first), end = first_at(last); i < end; ++i)
    if (const uint32_t id = ids_[i]; level_of[id] >= level) {
      codes.push_back(code_of(id));
      if (ids) ids->push_back(id);
    }
}

void MortonIndex::level(std::span<const uint8_t> level_of, int level, std::vector<MortonCode>& codes,
                        std::vector<uint32_t>* ids) const {
  codes.clear();
  if (ids) ids->clear();
  // Made to size: grown by doubling, level 0's codes (16 bytes a point)
  // would be held up to three times over while copied.
  const size_t count = count_at(level_of, level);
  codes.reserve(count);
  if (ids) ids->reserve(count);
  for (uint32_t id : ids_)
    if (level_of[id] >= level) {
      codes.push_back(code_of(id));
      if (ids) ids->push_back(id);
    }
}

size_t MortonIndex::count_at(std::span<const uint8_t> level_of, int level) const {
  size_t count = 0;
  for (uint32_t id : ids_) count += level_of[id] >= level;
  return count;
}

std::vector<uint32_t> MortonIndex::level_ids(std::span<const uint8_t> level_of, int level) const {
  std::vector<uint32_t> ids;
  ids.reserve(count_at(level_of, level));
  for (uint32_t id : ids_)
    if (level_of[id] >= level) ids.push_back(id);
  return ids;
}

namespace {

template <size_t N>
GridBox box_of(std::span<const GridPoint> points, const std::array<uint32_t, N>& corners) {
  GridBox b{{INT64_MAX, INT64_MAX, INT64_MAX}, {INT64_MIN, INT64_MIN, INT64_MIN}};
  for (uint32_t v : corners) {
    const int64_t c[3] = {points[v].x, points[v].y, points[v].z};
    for (int a = 0; a < 3; ++a) b.lo[a] = std::min(b.lo[a], c[a]), b.hi[a] = std::max(b.hi[a], c[a]);
  }
  return b;
}

}  // namespace

TriangleIndex::TriangleIndex(std::span<const GridPoint> points,
                             std::vector<std::array<uint32_t, 3>> triangles, int qbits)
    : points_(points), qbits_(qbits) {
  std::vector<std::pair<MortonCode, uint32_t>> by_anchor(triangles.size());
  for (uint32_t k = 0; k < triangles.size(); ++k) {
    const GridBox b = box_of(points, triangles[k]);
    for (int a = 0; a < 3; ++a) extent_[a] = std::max(extent_[a], b.hi[a] - b.lo[a]);
    by_anchor[k] = {morton_encode({static_cast<int32_t>(b.lo[0]), static_cast<int32_t>(b.lo[1]),
                                   static_cast<int32_t>(b.lo[2])},
                                  qbits),
                    k};
  }
  std::sort(by_anchor.begin(), by_anchor.end());
  triangles_.reserve(triangles.size());
  for (const auto& [code, k] : by_anchor) triangles_.push_back(triangles[k]);
}

MortonCode TriangleIndex::anchor_of(size_t k) const {
  const GridBox b = box_of(points_, triangles_[k]);
  return morton_encode(
      {static_cast<int32_t>(b.lo[0]), static_cast<int32_t>(b.lo[1]), static_cast<int32_t>(b.lo[2])}, qbits_);
}

size_t TriangleIndex::first_at(MortonCode code) const {
  size_t lo = 0, hi = triangles_.size();
  while (lo < hi) {
    const size_t mid = lo + (hi - lo) / 2;
    if (anchor_of(mid) < code)
      lo = mid + 1;
    else
      hi = mid;
  }
  return lo;
}

std::vector<std::array<uint32_t, 3>> TriangleIndex::meeting(const GridBox& box) const {
  // A triangle meeting the box has its box's low corner in the box grown
  // down by the largest extent.
  GridBox anchors = box;
  for (int a = 0; a < 3; ++a) anchors.lo[a] -= extent_[a];
  Stretches stretches;
  for (const auto& [first, last] : ranges_covering(anchors, qbits_))
    stretches.add(first_at(first), first_at(last));
  std::vector<uint32_t> found = collect_in_order<uint32_t>(
      stretches.size(), kScan, [&](size_t first, size_t last, std::vector<uint32_t>& part) {
        stretches.for_each(first, last, [&](size_t k) {
          if (box_of(points_, triangles_[k]).meets(box)) part.push_back(static_cast<uint32_t>(k));
        });
      });
  parallel_sort(found.begin(), found.end());  // one order whatever the ranges
  std::vector<std::array<uint32_t, 3>> out(found.size());
  parallel_ranges(found.size(), kScan, [&](size_t first, size_t last) {
    for (size_t i = first; i < last; ++i) out[i] = triangles_[found[i]];
  });
  return out;
}

void DistanceSums::add(double squared) {
  const double d = std::sqrt(squared);
  max = std::max(max, d);
  sum += d;
  ++count;
}

void DistanceSums::add(const DistanceSums& o) {
  max = std::max(max, o.max);
  sum += o.sum;
  count += o.count;
}

namespace {

// The distance from a cell's corner to the plane of the face across, the
// least of the four: the cell's thickness.
double smallest_height(std::span<const GridPoint> points, const std::array<uint32_t, 4>& cell) {
  const Vec3 a = to_vec(points[cell[0]]), b = to_vec(points[cell[1]]), c = to_vec(points[cell[2]]),
             d = to_vec(points[cell[3]]);
  const double six_volume = std::abs(dot(b - a, cross(c - a, d - a)));
  const double largest = std::max({norm(cross(c - b, d - b)), norm(cross(c - a, d - a)),
                                   norm(cross(b - a, d - a)), norm(cross(b - a, c - a))});
  return largest > 0 ? six_volume / largest : 0;
}

// The bricks of the layer whose cells the block codes (those whose corner
// it owns), each cell's chunk among them (§3.5's owner; kNoCarvingChunk:
// none of them), the vertices' Morton ranks and each chunk's cells in
// their coding order.
struct BlockBricks {
  std::vector<uint64_t> bricks;
  std::vector<uint32_t> chunk_of_cell;
  std::vector<uint32_t> ranks;
  ChunkCells cells;
};
BlockBricks block_bricks(const LevelGeometry& L, const BlockRegion& block, const BlockAnalysisOptions& o) {
  const std::span<const GridPoint> points = L.points;
  const size_t n = points.size();
  BlockBricks out;
  std::vector<MortonCode> codes(n);
  parallel_ranges(n, kScan, [&](size_t first, size_t last) {
    for (size_t v = first; v < last; ++v) codes[v] = morton_encode(points[v], o.qbits);
  });
  const std::vector<uint64_t> owner =
      carving_bricks_of_cells(L.dt, points, codes, o.qbits, o.brick_depth, o.kept_radius);
  // The bricks the cells name, each once (each range of cells' own first,
  // on every core: a copy of a brick a cell would be 8 bytes a cell more
  // at the block's peak), then those whose corner the block owns.
  std::vector<uint64_t>& bricks = out.bricks;
  bricks = collect_in_order<uint64_t>(
      owner.size(), kScan, [&](size_t first, size_t last, std::vector<uint64_t>& part) {
        std::vector<uint64_t> range(owner.begin() + static_cast<std::ptrdiff_t>(first),
                                    owner.begin() + static_cast<std::ptrdiff_t>(last));
        std::sort(range.begin(), range.end());
        part.assign(range.begin(), std::unique(range.begin(), range.end()));  // kept: the few distinct
      });
  std::sort(bricks.begin(), bricks.end());
  bricks.erase(std::unique(bricks.begin(), bricks.end()), bricks.end());
  std::erase_if(bricks, [&](uint64_t b) {
    return b == kNoBrick ||
           !block.owned.contains(morton_decode(MortonCode{b} << (3 * (o.qbits - o.brick_depth)), o.qbits));
  });
  out.chunk_of_cell.assign(owner.size(), kNoCarvingChunk);
  parallel_ranges(owner.size(), kScan, [&](size_t first, size_t last) {
    for (size_t c = first; c < last; ++c) {
      const auto it = std::lower_bound(bricks.begin(), bricks.end(), owner[c]);
      if (owner[c] != kNoBrick && it != bricks.end() && *it == owner[c])
        out.chunk_of_cell[c] = static_cast<uint32_t>(it - bricks.begin());
    }
  });
  out.ranks = morton_ranks(codes);
  out.cells = chunk_cells(L.dt, out.chunk_of_cell, bricks.size(), out.ranks);
  return out;
}

// The face sections of the block's bricks (17.0): a face the level's
// surface takes from its cell (the cell across not kept, or of a higher
// region) gets the tagger's label, any other 1. The cell across must be
// the level's (the block's region reaching far enough: the options' note).
void tag_faces(const LevelGeometry& L, std::span<const uint32_t> ids, const BlockBricks& b,
               const BlockAnalysisOptions& o, BlockAnalysis& out) {
  const ChunkFaces faces = chunk_faces(L.dt, b.cells, b.chunk_of_cell, L.in_mesh, b.ranks);
  std::vector<uint8_t> label(faces.faces.size(), 1);
  std::vector<uint32_t> surface;  // the faces the surface takes from their cell
  std::vector<std::array<uint32_t, 3>> by_grid_id;
  for (uint32_t k = 0; k < faces.faces.size(); ++k) {
    const SurfaceFace& face = faces.faces[k];
    const int32_t n = L.dt.neighbors[face.cell][face.opposite];
    if (n >= 0 && !surface_takes_face(L.in_mesh[face.cell], L.in_mesh[static_cast<size_t>(n)])) continue;
    std::array<uint32_t, 3> g{};
    for (int j = 0, at = 0; j < 4; ++j)
      if (j != face.opposite)
        g[static_cast<size_t>(at++)] = ids[L.dt.cells[face.cell][static_cast<size_t>(j)]];
    surface.push_back(k);
    by_grid_id.push_back(g);
  }
  const std::vector<uint8_t> tags = o.faces->labels(by_grid_id);
  for (size_t i = 0; i < surface.size(); ++i) label[surface[i]] = tags[i];
  out.figures.tagged_faces_kept += o.faces->tagged_among(by_grid_id);
  std::vector<std::vector<uint8_t>> sections = encode_face_chunks(faces, label, o.face_tags);
  for (size_t i = 0; i < b.bricks.size(); ++i)
    if (!sections[i].empty()) out.faces.emplace_back(b.bricks[i], std::move(sections[i]));
}

}  // namespace

StatusOr<BlockAnalysis> analyse_block(const BlockRegion& block, BlockReference* reference,
                                      const BlockAnalysisOptions& o, MadeMesh* made) {
  BlockAnalysis out;
  const size_t n = block.points.size();
  TetMesh dt;
  std::vector<uint8_t> verdicts;
  if (made && reference) {
    dt = std::move(made->dt);
    verdicts = std::move(made->regions);
  } else {
    DTM_ASSIGN_OR_RETURN(dt, delaunay_tetrahedralize(block.points));
  }
  if (reference && verdicts.empty()) {
    DTM_RETURN_IF_ERROR(
        settled_pass(*reference->solid, [&] { verdicts = reference->solid->verdicts(dt, block.points); }));
  }
  AlphaPolicy policy;
  policy.kind = AlphaKind::kFixed;
  policy.fixed_value = o.alpha;
  policy.kept_radius = o.kept_radius;
  DTM_ASSIGN_OR_RETURN(LevelGeometry L, analyze_level(block.points, std::move(dt), policy, verdicts));
  const std::span<const GridPoint> points = L.points;
  const std::span<const uint32_t> ids = block.ids;
  if (o.faces_only) {
    if (o.faces && o.brick_depth >= 0) tag_faces(L, ids, block_bricks(L, block, o), o, out);
    return out;
  }

  BlockFigures& f = out.figures;
  // The cells the solid holds that the kept radius drops (in the solid, not
  // in the level), thicker than D_max: few, so each one's shape is taken
  // only when dropped.
  for (size_t c = 0; c < verdicts.size(); ++c)
    if (verdicts[c] != 0 && !L.in_mesh[c] && owns(block.owned, points, L.dt.cells[c]) &&
        smallest_height(points, L.dt.cells[c]) > o.dmax) {
      ++f.dropped_thick;
      f.dropped_thick_radius = std::max(f.dropped_thick_radius, carving_radius(points, L.dt.cells[c]));
    }
  release(verdicts);
  for (uint32_t v = 0; v < n; ++v)
    if (block.owned.contains(points[v])) {
      ++f.vertices;
      if (L.boundary[v]) ++f.boundary_vertices, out.boundary.push_back(ids[v]);
    }
  // The cells the block owns, found on every core; their figures added in
  // cell order, as one loop would (the sums are the stream's figures).
  const std::vector<uint32_t> owned = collect_in_order<uint32_t>(
      L.dt.cells.size(), kScan, [&](size_t first, size_t last, std::vector<uint32_t>& part) {
        for (size_t c = first; c < last; ++c)
          if (L.in_mesh[c] && owns(block.owned, points, L.dt.cells[c]))
            part.push_back(static_cast<uint32_t>(c));
      });
  std::vector<std::array<uint32_t, 4>> owned_cells(owned.size());
  parallel_ranges(owned.size(), kScan, [&](size_t first, size_t last) {
    for (size_t i = first; i < last; ++i) owned_cells[i] = L.dt.cells[owned[i]];
  });
  for (uint32_t c : owned) {
    ++f.cells;
    f.quality_sum += L.cell_min_solid_angle[c];
    f.quality_min = std::min(f.quality_min, L.cell_min_solid_angle[c]);
  }
  f.cell_hash = cell_hash_sum(points, owned_cells);
  if (o.collect_cells) {
    out.carved = std::move(owned_cells);
    for (auto& c : out.carved)
      for (uint32_t& v : c) v = ids[v];
  }
  release(owned_cells);

  // The surface: what the block owns of it, and its distance to the reference.
  const LevelSurface surface = level_surface(L);
  std::vector<uint8_t> on_surface(n, 0);
  for (const auto& t : surface.triangles)
    for (uint32_t v : t) on_surface[v] = 1;
  out.surface_triangles = collect_in_order<std::array<uint32_t, 3>>(
      surface.triangles.size(), kScan,
      [&](size_t first, size_t last, std::vector<std::array<uint32_t, 3>>& part) {
        for (size_t k = first; k < last; ++k) {
          const auto& t = surface.triangles[k];
          if (!owns(block.owned, points, t)) continue;
          std::array<uint32_t, 3> key = {ids[t[0]], ids[t[1]], ids[t[2]]};
          std::sort(key.begin(), key.end());
          part.push_back(key);
        }
      });
  parallel_sort(out.surface_triangles.begin(), out.surface_triangles.end());
  for (uint32_t v = 0; v < n; ++v)
    if (on_surface[v] && block.owned.contains(points[v])) out.surface_vertices.push_back(ids[v]);
  if (reference && reference->shape) {
    ReferenceShape& shape = *reference->shape;
    const ShapeMeasurement m = shape.measure(points, ids, surface.triangles);
    const auto reference_points = shape.boundary_points();
    const auto reference_ids = shape.boundary_ids();
    for (size_t i = 0; i < reference_points.size(); ++i)
      if (block.owned.contains(reference_points[i])) {
        f.to_level.add(m.reference_squared[i]);
        out.reference_squared.emplace_back(reference_ids[i], m.reference_squared[i]);
      }
    for (size_t i = 0; i < m.surface_vertices.size(); ++i)
      if (block.owned.contains(points[m.surface_vertices[i]])) f.to_reference.add(m.vertex_squared[i]);
    for (size_t t = 0; t < surface.triangles.size(); ++t)
      if (owns(block.owned, points, surface.triangles[t])) f.to_reference.add(m.centroid_squared[t]);
  }

  // The carving sections of the layer's bricks inside the block, their
  // cells coded in the order of their vertices' Morton codes (§3.5).
  if (o.brick_depth >= 0) {
    const BlockBricks b = block_bricks(L, block, o);
    const std::vector<uint64_t>& bricks = b.bricks;
    const std::vector<uint32_t>& chunk_of_cell = b.chunk_of_cell;
    const ChunkCells& cells = b.cells;
    std::vector<std::vector<uint8_t>> sections =
        encode_carving_chunks(L.dt, points, o.alpha, L.in_mesh, chunk_of_cell, cells);
    for (size_t i = 0; i < bricks.size(); ++i)
      if (!sections[i].empty()) out.carving.emplace_back(bricks[i], std::move(sections[i]));
    // The kept cells' regions (in_mesh holds them: Solid::verdicts), in
    // the carving sections' order.
    if (o.region_count >= 2) {
      sections = encode_region_chunks(L.dt, cells, chunk_of_cell, L.in_mesh, o.region_count);
      for (size_t i = 0; i < bricks.size(); ++i)
        if (!sections[i].empty()) out.regions.emplace_back(bricks[i], std::move(sections[i]));
    }
    if (o.faces) tag_faces(L, ids, b, o, out);
    // Level 0's kept cells' values (16.0), in the same order, each cell's
    // from the input tetrahedron it stands for.
    if (o.cell_values && o.cell_sources) {
      std::vector<uint8_t> found(L.dt.cells.size(), 0);  // 1 + CellSourceIndex::Found
      sections = encode_cell_value_chunks(
          *o.cell_values, L.dt, points, cells, L.in_mesh,
          [&](uint32_t c) {
            const auto& cell = L.dt.cells[c];
            CellSourceIndex::Found how{};
            const uint32_t t =
                o.cell_sources->source({ids[cell[0]], ids[cell[1]], ids[cell[2]], ids[cell[3]]}, how);
            found[c] = static_cast<uint8_t>(1 + static_cast<int>(how));
            return t;
          },
          out.cell_field_bytes);
      for (size_t i = 0; i < bricks.size(); ++i)
        if (!sections[i].empty()) out.cell_values.emplace_back(bricks[i], std::move(sections[i]));
      for (uint8_t how : found) {
        f.cells_from_input += how == 1 + static_cast<int>(CellSourceIndex::Found::kExact);
        f.cells_from_nearest += how == 1 + static_cast<int>(CellSourceIndex::Found::kNearest);
      }
    }
  }

  if (o.choice) {
    const Coarsening c = choose_coarser(L, surface, *o.choice);
    for (uint32_t v = 0; v < n; ++v)
      if (c.keep[v] && block.owned.contains(points[v])) out.chosen.push_back(ids[v]);
  }
  return out;
}

StatusOr<BlockBuild> build_block(const BlockRegion& fine, std::span<const uint8_t> keep,
                                 const SurfaceRecord& record,
                                 std::span<const std::pair<uint32_t, double>> reference_squared,
                                 BlockReference& reference, const LevelBounds& bounds) {
  const auto in_region = [&](uint32_t id) {
    return std::binary_search(fine.ids.begin(), fine.ids.end(), id);
  };
  // The finer level's record where the block can see it.
  // (The whole level's record, searched on every core.)
  SurfaceRecord local;
  local.triangles = collect_in_order<std::array<uint32_t, 3>>(
      record.triangles.size(), kScan,
      [&](size_t first, size_t last, std::vector<std::array<uint32_t, 3>>& part) {
        for (size_t k = first; k < last; ++k) {
          const auto& t = record.triangles[k];
          if (in_region(t[0]) && in_region(t[1]) && in_region(t[2])) part.push_back(t);
        }
      });
  local.vertices = collect_in_order<uint32_t>(record.vertices.size(), kScan,
                                              [&](size_t first, size_t last, std::vector<uint32_t>& part) {
                                                for (size_t k = first; k < last; ++k)
                                                  if (in_region(record.vertices[k]))
                                                    part.push_back(record.vertices[k]);
                                              });
  const std::span<const uint32_t> boundary_ids = reference.shape->boundary_ids();
  local.reference_squared.resize(boundary_ids.size());
  parallel_ranges(boundary_ids.size(), kScan, [&](size_t first, size_t last) {
    for (size_t k = first; k < last; ++k) {
      const uint32_t id = boundary_ids[k];
      const auto it = std::lower_bound(reference_squared.begin(), reference_squared.end(),
                                       std::pair<uint32_t, double>{id, -INFINITY});
      local.reference_squared[k] = it != reference_squared.end() && it->first == id ? it->second : 0.0;
    }
  });
  LevelBounds b = bounds;
  b.owned = &fine.owned;
  b.analyze = false;
  DTM_ASSIGN_OR_RETURN(BuiltLevel built, build_coarser_level(fine.points, fine.ids, local, keep,
                                                             {reference.solid, &*reference.shape}, b,
                                                             AlphaPolicy{}, [](const char*) {}));
  BlockBuild out;
  out.vertices = std::move(built.vertices);
  out.mesh.dt = std::move(built.geometry.dt);
  out.mesh.regions = std::move(built.solid_regions);
  out.broken = built.shape_left;
  out.quality_met = built.quality_met;
  out.rounds = built.repair_rounds;
  out.clean = built.shape_left == 0 && built.fins_left == 0 && built.quality_met;
  out.quality_sum = built.quality_sum;
  out.quality_cells = built.quality_cells;
  return out;
}

StatusOr<PartCheck> check_part(const BlockRegion& part, std::span<const uint8_t> before,
                               std::span<const uint8_t> now, const SurfaceRecord& record,
                               std::span<const std::pair<uint32_t, double>> reference_squared,
                               BlockReference& reference, const LevelBounds& bounds) {
  // One check each, no repair; the quality is judged over the whole box by
  // the caller.
  LevelBounds b = bounds;
  b.repair_rounds = 0;
  b.quality_floor = 0;
  PartCheck out;
  DTM_ASSIGN_OR_RETURN(BlockBuild built, build_block(part, now, record, reference_squared, reference, b));
  out.clean = built.clean;
  out.quality_sum_now = built.quality_sum;
  out.quality_cells_now = built.quality_cells;
  if (!out.clean) return out;  // the block is built again: its sums before are not needed
  DTM_ASSIGN_OR_RETURN(BlockBuild then, build_block(part, before, record, reference_squared, reference, b));
  out.quality_sum_before = then.quality_sum;
  out.quality_cells_before = then.quality_cells;
  return out;
}

std::vector<GridBox> parts_near(std::span<const uint32_t> points, std::span<const GridPoint> all,
                                const GridBox& box, int64_t reach, int qbits) {
  std::vector<GridBox> cubes;
  for (uint32_t id : points) {
    const GridPoint& p = all[id];
    GridBox c;
    c.lo = c.hi = {p.x, p.y, p.z};
    c = c.grown(reach, qbits);
    if (c.meets(box)) cubes.push_back(c);
  }
  // Merged while two meet (few points: the seams' put-backs).
  for (bool merged = true; merged;) {
    merged = false;
    for (size_t i = 0; i < cubes.size(); ++i)
      for (size_t j = i + 1; j < cubes.size(); ++j) {
        if (!cubes[i].meets(cubes[j])) continue;
        for (int a = 0; a < 3; ++a) {
          cubes[i].lo[a] = std::min(cubes[i].lo[a], cubes[j].lo[a]);
          cubes[i].hi[a] = std::max(cubes[i].hi[a], cubes[j].hi[a]);
        }
        cubes[j] = cubes.back();
        cubes.pop_back();
        merged = true;
        --j;
      }
  }
  for (GridBox& c : cubes)
    for (int a = 0; a < 3; ++a)
      c.lo[a] = std::max(c.lo[a], box.lo[a]), c.hi[a] = std::min(c.hi[a], box.hi[a]);
  return cubes;
}

}  // namespace dtm
