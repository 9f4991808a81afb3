// Distance from points to a triangulated surface, for the shape error of a
// level (largest distance from the level-0 boundary vertices to the level's
// boundary surface). A measurement, so inexact arithmetic is fine; CGAL's
// AABB tree does the work and stays inside surface_distance.cpp.
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include "common/grid.h"

namespace dtm {

struct DistanceSummary {
  double max = 0;  // grid units; +infinity when there is no surface
  double mean = 0;
};

DistanceSummary distance_to_surface(std::span<const GridPoint> vertices,
                                    std::span<const std::array<uint32_t, 3>> triangles,
                                    std::span<const GridPoint> queries);

// Max and mean of the square roots, summed in order (the mean does not depend
// on how the distances were computed in parallel).
DistanceSummary summarize_squared(std::span<const double> squared);

// One fixed surface asked about many times: its search structure (CGAL's
// AABB tree) is built once. No triangle: every distance is +infinity.
// (Where only distances are asked of a surface held long, as the
// reference's boundary, core/triangle_distance_tree.h holds it in a
// quarter of the memory.)
class FixedSurface {
 public:
  FixedSurface(std::span<const GridPoint> vertices, std::span<const std::array<uint32_t, 3>> triangles);
  ~FixedSurface();
  FixedSurface(FixedSurface&&) noexcept;
  FixedSurface& operator=(FixedSurface&&) noexcept;

  // Squared distance of each query, computed on every core.
  std::vector<double> squared_distances(std::span<const GridPoint> queries) const;
  // The same for points between grid points (triangle centroids).
  std::vector<double> squared_distances(std::span<const std::array<double, 3>> queries) const;
  // One query, on the calling thread.
  double squared_distance(const GridPoint& query) const;
  // Each query's nearest triangle (its index in the triangles given), on
  // every core; empty without triangles.
  std::vector<uint32_t> nearest_triangles(std::span<const std::array<double, 3>> queries) const;

 private:
  struct State;
  std::unique_ptr<State> state_;
};

// The same measurement for fixed queries against a sequence of surfaces that
// differ a little from one to the next (the levels of a hierarchy, where a
// level changes the surface only around the boundary vertices it removes).
// A query whose nearest triangle is still there can only come closer to a
// new triangle, so it is checked against the new triangles alone; only the
// queries whose nearest triangle is gone are searched again in full. The
// results equal distance_to_surface's on every surface (tested).
class SurfaceDistanceTracker {
 public:
  // `query_ids`, if given, names each query as measure()'s `ids` name the
  // surface's points: a query that is a vertex of the surface is at
  // distance 0 without a search. Both are the caller's, read in place
  // (a reference boundary's vertices and their ids: not held twice), and
  // must outlive the tracker.
  explicit SurfaceDistanceTracker(std::span<const GridPoint> queries,
                                  std::span<const uint32_t> query_ids = {});
  ~SurfaceDistanceTracker();
  SurfaceDistanceTracker(SurfaceDistanceTracker&&) noexcept;
  SurfaceDistanceTracker& operator=(SurfaceDistanceTracker&&) noexcept;

  // `ids` names each of `vertices` across calls (grid-point indices; empty:
  // the vertex indices are the names): a triangle is the same one from call
  // to call when its three names are.
  DistanceSummary measure(std::span<const GridPoint> vertices, std::span<const uint32_t> ids,
                          std::span<const std::array<uint32_t, 3>> triangles);
  // Each query's squared distance as the last measure() found it
  // (+infinity when that surface had no triangle).
  std::vector<double> squared() const;
  // Each query's nearest triangle then, by its ids (sorted).
  std::vector<std::array<uint32_t, 3>> nearest_triangles() const;
  std::array<uint32_t, 3> nearest_triangle(size_t query) const;

 private:
  struct State;
  std::unique_ptr<State> state_;
};

}  // namespace dtm
