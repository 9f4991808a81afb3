#include "core/reference_shape.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "common/parallel_for.h"
#include "common/parallel_sort.h"
#include "common/release.h"
#include "common/status.h"
#include "core/region_solid.h"
#include "mesh/topology.h"

namespace dtm {
namespace {

std::vector<uint32_t> vertex_ids_of(std::span<const std::array<uint32_t, 3>> triangles) {
  std::vector<uint32_t> ids;
  for (const auto& t : triangles) ids.insert(ids.end(), t.begin(), t.end());
  parallel_sort(ids.begin(), ids.end());
  ids.erase(std::unique(ids.begin(), ids.end()), ids.end());
  return ids;
}

}  // namespace

std::vector<std::array<uint32_t, 4>> grid_tetrahedra(std::span<const std::array<uint32_t, 4>> tets,
                                                     const QuantizedPoints& q) {
  std::vector<std::array<uint32_t, 4>> out(tets.begin(), tets.end());
  grid_tetrahedra_in_place(out, q);
  return out;
}

void grid_tetrahedra_in_place(std::vector<std::array<uint32_t, 4>>& tets, const QuantizedPoints& q,
                              std::vector<int32_t>* labels) {
  using Tet = std::array<uint32_t, 4>;
  const auto collapsed = [](Tet t) {
    std::sort(t.begin(), t.end());
    return std::adjacent_find(t.begin(), t.end()) != t.end();
  };
  // On the grid (on every core), then those quantization collapsed dropped
  // (when there are any: in order, on one thread).
  constexpr size_t kRange = size_t{1} << 16;
  std::vector<uint8_t> range_collapsed((tets.size() + kRange - 1) / kRange, 0);
  parallel_ranges(tets.size(), kRange, [&](size_t first, size_t last) {
    for (size_t i = first; i < last; ++i) {
      Tet& t = tets[i];
      t = {q.input_to_point[t[0]], q.input_to_point[t[1]], q.input_to_point[t[2]], q.input_to_point[t[3]]};
      if (collapsed(t)) range_collapsed[first / kRange] = 1;
    }
  });
  size_t kept = tets.size();
  if (std::find(range_collapsed.begin(), range_collapsed.end(), 1) != range_collapsed.end()) {
    kept = 0;
    for (size_t i = 0; i < tets.size(); ++i) {
      if (collapsed(tets[i])) continue;
      if (labels) (*labels)[kept] = (*labels)[i];
      tets[kept++] = tets[i];
    }
    tets.resize(kept);
  }
  auto smallest = [](const Tet& t) { return std::min({t[0], t[1], t[2], t[3]}); };
  if (labels) {
    // With labels, a permutation sorted once, on every core (its order is
    // total, so whatever the sort): the same order as below, in twice the
    // memory of the tetrahedra.
    labels->resize(kept);
    std::vector<uint32_t> order(kept);
    for (uint32_t i = 0; i < kept; ++i) order[i] = i;
    parallel_sort(order.begin(), order.end(), [&](uint32_t a, uint32_t b) {
      const uint32_t sa = smallest(tets[a]), sb = smallest(tets[b]);
      return sa != sb ? sa < sb : (tets[a] != tets[b] ? tets[a] < tets[b] : a < b);
    });
    std::vector<Tet> sorted(kept);
    std::vector<int32_t> sorted_labels(kept);
    parallel_ranges(kept, size_t{1} << 16, [&](size_t first, size_t last) {
      for (size_t i = first; i < last; ++i)
        sorted[i] = tets[order[i]], sorted_labels[i] = (*labels)[order[i]];
    });
    tets = std::move(sorted);
    *labels = std::move(sorted_labels);
    return;
  }
  // Ordered by smallest vertex, in two passes that each touch memory in
  // order: an in-place distribution into partitions of consecutive vertex
  // ids (each partition's next free place stays in cache), then each
  // partition sorted where it lies (on every core). A mesher's output order
  // is its refinement's, scattered over space at 10M vertices; in this
  // order every pass over the tetrahedra reads their corners in order
  // (bunny_10m's reference shape and solid went from 37 s to 13 s). Ties
  // are ordered by their corners, so the order is the tetrahedra's, not
  // the input's; nothing built from them depends on it.
  int shift = 0;
  while ((q.points.size() >> shift) >= 1024) ++shift;
  const size_t partitions = (q.points.size() >> shift) + 1;
  // The partitions' sizes counted range by range on every core, added in order.
  std::vector<std::vector<size_t>> counts((tets.size() + kRange - 1) / kRange);
  parallel_ranges(tets.size(), kRange, [&](size_t first, size_t last) {
    std::vector<size_t>& count = counts[first / kRange];
    count.assign(partitions, 0);
    for (size_t i = first; i < last; ++i) ++count[smallest(tets[i]) >> shift];
  });
  std::vector<size_t> start(partitions + 1, 0);
  for (const auto& count : counts)
    for (size_t p = 0; p < partitions; ++p) start[p + 1] += count[p];
  release(counts);
  for (size_t p = 0; p < partitions; ++p) start[p + 1] += start[p];
  std::vector<size_t> next(start.begin(), start.end() - 1);
  for (size_t p = 0; p < partitions; ++p)
    while (next[p] < start[p + 1]) {
      // Carry the tetrahedron at p's next place to its partition's, until
      // one that belongs here comes back.
      Tet moving = tets[next[p]];
      for (size_t home = smallest(moving) >> shift; home != p; home = smallest(moving) >> shift)
        std::swap(moving, tets[next[home]++]);
      tets[next[p]++] = moving;
    }
  parallel_for(partitions, [&](size_t p) {
    std::sort(tets.begin() + static_cast<std::ptrdiff_t>(start[p]),
              tets.begin() + static_cast<std::ptrdiff_t>(start[p + 1]), [&](const Tet& a, const Tet& b) {
                const uint32_t sa = smallest(a), sb = smallest(b);
                return sa != sb ? sa < sb : a < b;
              });
  });
}

// Orientation does not matter for distances: no need to fix the input's.
ReferenceShape::ReferenceShape(std::span<const GridPoint> points,
                               std::span<const std::array<uint32_t, 4>> tets)
    : ReferenceShape(points, dtm::boundary_triangles(tets), true) {}

ReferenceShape::ReferenceShape(std::span<const GridPoint> points,
                               std::span<const std::array<uint32_t, 4>> tets, std::span<const uint8_t> region)
    : ReferenceShape(points, region_surface_triangles(tets, region), true) {}

ReferenceShape ReferenceShape::from_boundary(std::span<const GridPoint> points,
                                             std::vector<std::array<uint32_t, 3>> boundary) {
  return ReferenceShape(points, std::move(boundary), false);
}

ReferenceBoundary::ReferenceBoundary(std::span<const GridPoint> grid,
                                     std::vector<std::array<uint32_t, 3>> boundary, bool keep_triangles)
    : triangles(std::move(boundary)),
      keys(triangles),
      ids(vertex_ids_of(triangles)),
      surface(grid, triangles) {
  DTM_CHECK(surface.corners().size() == ids.size());
  for (auto& k : keys) std::sort(k.begin(), k.end());
  parallel_sort(keys.begin(), keys.end());
  if (!keep_triangles) release(triangles);
}

ReferenceShape::ReferenceShape(std::span<const GridPoint> points,
                               std::vector<std::array<uint32_t, 3>> boundary, bool keep_triangles)
    : ReferenceShape(std::make_shared<const ReferenceBoundary>(points, std::move(boundary), keep_triangles)) {
}

ReferenceShape::ReferenceShape(std::shared_ptr<const ReferenceBoundary> boundary)
    : boundary_(std::move(boundary)), to_level_(boundary_->points(), boundary_->ids) {}

std::optional<double> ReferenceShape::known_squared(uint32_t id) const {
  // The reference's own vertices are on its surface (their ids sorted: not
  // a map entry each, 28 MiB for bunny_10m's whole boundary on each rank
  // building a level of one block).
  if (std::binary_search(boundary_->ids.begin(), boundary_->ids.end(), id)) return 0.0;
  const auto it = to_reference_.find(id);
  if (it == to_reference_.end()) return std::nullopt;
  return it->second;
}

ShapeMeasurement ReferenceShape::measure(std::span<const GridPoint> points, std::span<const uint32_t> ids,
                                         std::span<const std::array<uint32_t, 3>> triangles) {
  ShapeMeasurement m;
  m.to_level = boundary_->points().empty() ? DistanceSummary{} : to_level_.measure(points, ids, triangles);
  m.reference_squared = to_level_.squared();
  {
    // The triangles' corners, ascending and each once (vertex_ids_of's
    // answer, by a mark per point instead of a sort).
    std::vector<uint8_t> corner(points.size(), 0);
    for (const auto& t : triangles)
      for (uint32_t v : t) corner[v] = 1;
    for (uint32_t v = 0; v < corner.size(); ++v)
      if (corner[v]) m.surface_vertices.push_back(v);
  }
  // Grid points not measured before, on every core.
  std::vector<uint32_t> unmeasured;
  for (uint32_t v : m.surface_vertices) {
    if (!known_squared(ids.empty() ? v : ids[v])) unmeasured.push_back(v);
  }
  const std::vector<double> fresh = boundary_->surface.squared_distances(gather(points, unmeasured));
  for (size_t i = 0; i < unmeasured.size(); ++i)
    to_reference_[ids.empty() ? unmeasured[i] : ids[unmeasured[i]]] = fresh[i];
  m.vertex_squared.reserve(m.surface_vertices.size());
  for (uint32_t v : m.surface_vertices)
    m.vertex_squared.push_back(known_squared(ids.empty() ? v : ids[v]).value());
  // A point inside each triangle too: a flat triangle between two surface
  // vertices can cut across a concavity its corners do not see.
  // (A triangle of the reference's surface is at distance 0.) Each one is
  // measured once: a repair round's surface is mostly the one before it,
  // whose figures are kept by the triangle's ids.
  using Measured = std::pair<std::array<uint32_t, 3>, double>;
  // Per triangle, on every core: its key, and whether it is the
  // reference's (0), measured before (1: the figure is in centroid_squared)
  // or to be searched (2).
  const size_t n = triangles.size();
  std::vector<std::array<uint32_t, 3>> keys(n);
  std::vector<uint8_t> kind(n);
  m.centroid_squared.assign(n, 0);
  parallel_ranges(n, 8192, [&](size_t first, size_t last) {
    for (size_t i = first; i < last; ++i) {
      const auto& t = triangles[i];
      std::array<uint32_t, 3> key =
          ids.empty() ? t : std::array<uint32_t, 3>{ids[t[0]], ids[t[1]], ids[t[2]]};
      std::sort(key.begin(), key.end());
      keys[i] = key;
      if (std::binary_search(boundary_->keys.begin(), boundary_->keys.end(), key)) {
        kind[i] = 0;
        continue;
      }
      const auto known =
          std::lower_bound(centroid_squared_.begin(), centroid_squared_.end(), Measured{key, -1.0});
      kind[i] = known != centroid_squared_.end() && known->first == key ? 1 : 2;
      if (kind[i] == 1) m.centroid_squared[i] = known->second;
    }
  });
  // The triangles searched, their centroids, and the figures kept for the
  // next call (kinds 1 and 2), each on every core.
  const auto triangles_where = [&](auto&& wanted) {
    return collect_in_order<uint32_t>(n, 8192, [&](size_t first, size_t last, std::vector<uint32_t>& out) {
      for (size_t i = first; i < last; ++i)
        if (wanted(kind[i])) out.push_back(static_cast<uint32_t>(i));
    });
  };
  const std::vector<uint32_t> searched = triangles_where([](uint8_t k) { return k == 2; });
  std::vector<std::array<double, 3>> centroids(searched.size());
  parallel_ranges(searched.size(), 8192, [&](size_t first, size_t last) {
    for (size_t j = first; j < last; ++j) {
      const auto& t = triangles[searched[j]];
      const GridPoint &a = points[t[0]], &b = points[t[1]], &c = points[t[2]];
      centroids[j] = {(double{1} * a.x + b.x + c.x) / 3, (double{1} * a.y + b.y + c.y) / 3,
                      (double{1} * a.z + b.z + c.z) / 3};
    }
  });
  const std::vector<double> found = boundary_->surface.squared_distances(centroids);
  parallel_ranges(searched.size(), 8192, [&](size_t first, size_t last) {
    for (size_t j = first; j < last; ++j) m.centroid_squared[searched[j]] = found[j];
  });
  const std::vector<uint32_t> kept = triangles_where([](uint8_t k) { return k != 0; });
  std::vector<Measured> measured(kept.size());
  parallel_ranges(kept.size(), 8192, [&](size_t first, size_t last) {
    for (size_t j = first; j < last; ++j) measured[j] = {keys[kept[j]], m.centroid_squared[kept[j]]};
  });
  parallel_sort(measured.begin(), measured.end());  // distinct keys
  centroid_squared_ = std::move(measured);
  std::vector<double> squared = m.vertex_squared;
  squared.insert(squared.end(), m.centroid_squared.begin(), m.centroid_squared.end());
  m.to_reference = summarize_squared(squared);
  const double n_level = static_cast<double>(squared.size());
  const double n_reference = static_cast<double>(boundary_->points().size());
  m.both.max = std::max(m.to_level.max, m.to_reference.max);
  m.both.mean = n_level + n_reference > 0 ? (m.to_level.mean * n_reference + m.to_reference.mean * n_level) /
                                                (n_level + n_reference)
                                          : 0;
  return m;
}

ShapeMeasurement ReferenceShape::distance(std::span<const std::array<uint32_t, 4>> cells,
                                          std::span<const GridPoint> points) {
  return measure(points, {}, dtm::boundary_triangles(cells));
}

}  // namespace dtm
