#include "core/level.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "mesh/geometry.h"

namespace dtm {

StatusOr<LevelGeometry> analyze_level(std::vector<GridPoint> points, const AlphaPolicy& policy) {
  DTM_ASSIGN_OR_RETURN(TetMesh dt, delaunay_tetrahedralize(points));
  return analyze_level(std::move(points), std::move(dt), policy);
}

StatusOr<LevelGeometry> analyze_level(std::vector<GridPoint> points, TetMesh dt, const AlphaPolicy& policy,
                                      std::span<const uint8_t> verdicts) {
  LevelGeometry L;
  L.points = std::move(points);
  L.dt = std::move(dt);
  if (!verdicts.empty() && verdicts.size() != L.dt.cells.size())
    return Status{StatusCode::kInternal, "analyze_level: a verdict per cell expected"};
  if (L.dt.cells.empty())
    return Status{StatusCode::kInvalidInput,
                  "the " + std::to_string(L.points.size()) + " points do not span three dimensions"};
  const size_t n = L.points.size(), m = L.dt.cells.size();
  L.cells_of_vertex = vertex_cells(L.dt, n);
  L.neighbors = vertex_neighbors(L.dt, L.cells_of_vertex);

  double length_sum = 0;
  for (uint32_t v = 0; v < n; ++v) {
    const Vec3 p = to_vec(L.points[v]);
    for (uint32_t u : L.neighbors.row(v)) {
      if (u <= v) continue;
      length_sum += norm(to_vec(L.points[u]) - p);
      ++L.finite_edges;
    }
  }
  L.mean_edge_length = L.finite_edges ? length_sum / L.finite_edges : 0;
  switch (policy.kind) {
    case AlphaPolicy::Kind::kPaper:
      L.alpha = L.mean_edge_length;
      break;
    case AlphaPolicy::Kind::kFixed:
      L.alpha = policy.fixed_value;
      break;
    case AlphaPolicy::Kind::kConvexHull:
      L.alpha = INFINITY;
      break;
  }

  L.in_mesh.assign(m, 0);
  L.cell_min_solid_angle.assign(m, 0);
  L.solid_angle_sum.assign(n, 0);
  L.mesh_volume6.assign(n, 0);
  for (size_t c = 0; c < m; ++c) {
    const bool kept = verdicts.empty() ? kept_by_alpha(L.points, L.dt.cells[c], L.alpha) : verdicts[c] != 0;
    if (!kept) continue;
    // Corners in lexicographic order of their coordinates, as the carving
    // takes them: the angles and volumes are then the same function of the
    // four points whatever order a triangulation lists them in.
    std::array<uint32_t, 4> cell = L.dt.cells[c];
    std::sort(cell.begin(), cell.end(), [&](uint32_t a, uint32_t b) { return L.points[a] < L.points[b]; });
    const std::array<Vec3, 4> t = {to_vec(L.points[cell[0]]), to_vec(L.points[cell[1]]),
                                   to_vec(L.points[cell[2]]), to_vec(L.points[cell[3]])};
    L.in_mesh[c] = 1;
    ++L.mesh_cells;
    const auto angles = solid_angles(t);
    L.cell_min_solid_angle[c] = std::min({angles[0], angles[1], angles[2], angles[3]});
    const Int128 volume6 =
        abs_six_volume(L.points[cell[0]], L.points[cell[1]], L.points[cell[2]], L.points[cell[3]]);
    for (int i = 0; i < 4; ++i) {
      L.solid_angle_sum[cell[i]] += angles[i];
      L.mesh_volume6[cell[i]] += volume6;
    }
  }
  L.boundary.assign(n, 0);
  for (size_t v = 0; v < n; ++v)
    L.boundary[v] = L.solid_angle_sum[v] < kFullSolidAngle - kSolidAngleTolerance;
  return L;
}

LevelSurface level_surface(const LevelGeometry& L) {
  LevelSurface s;
  for (const BoundaryFace& f : boundary_faces(L.dt, L.in_mesh))
    s.triangles.push_back(outward_triangle(L.dt, L.points, f));
  s.around = build_csr(L.size(), [&](auto&& emit) {
    for (uint32_t i = 0; i < s.triangles.size(); ++i)
      for (uint32_t u : s.triangles[i]) emit(u, i);
  });
  return s;
}

MeshQuality mesh_quality(const LevelGeometry& L) {
  MeshQuality q;
  double sum = 0, lowest = INFINITY;
  for (size_t c = 0; c < L.dt.cells.size(); ++c) {
    if (!L.in_mesh[c]) continue;
    sum += L.cell_min_solid_angle[c];
    lowest = std::min(lowest, L.cell_min_solid_angle[c]);
  }
  q.avg_min_solid_angle = L.mesh_cells ? sum / L.mesh_cells : 0;
  q.min_solid_angle = L.mesh_cells ? lowest : 0;
  for (uint8_t b : L.boundary) q.boundary_vertices += b;
  return q;
}

std::vector<uint8_t> topological_boundary(const LevelGeometry& L) {
  return boundary_vertices(L.dt, L.size(), L.in_mesh);
}

}  // namespace dtm
