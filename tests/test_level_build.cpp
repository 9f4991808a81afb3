// One codec level's build (spec/HIERARCHY.md §6.2): the chosen subset in one
// batch, checked against the bounds, repaired where one breaks.
#include <gtest/gtest.h>

#include <algorithm>
#include <numeric>

#include "core/level_build.h"
#include "core/reference_shape.h"
#include "core/reference_solid.h"
#include "mesh/carving.h"
#include "mesh/delaunay.h"

namespace dtm {
namespace {

using Cell = std::array<uint32_t, 4>;

// A block of lattice points (0..28, step 4) with a thin spike on top: a
// chain of triangular prisms from z = 28 up to z = 96 (triangles of side ~5
// every 4 units) ending in an apex at z = 100. The reference solid is the
// block's Delaunay cells and the spike's prisms, three tetrahedra each.
struct SpikedBlock {
  std::vector<GridPoint> points;
  std::vector<Cell> tets;
  std::vector<uint8_t> spike;  // per point: part of the spike above the block
  uint32_t apex = 0;

  SpikedBlock() {
    for (int z = 0; z <= 28; z += 4)
      for (int y = 0; y <= 28; y += 4)
        for (int x = 0; x <= 28; x += 4) points.push_back({x, y, z});
    const size_t block = points.size();
    const TetMesh dt = delaunay_tetrahedralize(points).value();
    tets = dt.cells;
    // The spike's base triangle lies on the block's top face (between its lattice points).
    std::vector<std::array<uint32_t, 3>> rings;
    for (int z = 28; z <= 96; z += 4) {
      const auto add = [&](int x, int y) {
        points.push_back({x, y, z});
        return static_cast<uint32_t>(points.size() - 1);
      };
      rings.push_back({add(13, 13), add(18, 13), add(15, 18)});
    }
    points.push_back({15, 15, 100});
    apex = static_cast<uint32_t>(points.size() - 1);
    for (size_t r = 0; r + 1 < rings.size(); ++r) {
      const auto& a = rings[r];
      const auto& b = rings[r + 1];
      tets.push_back({a[0], a[1], a[2], b[0]});
      tets.push_back({a[1], a[2], b[0], b[1]});
      tets.push_back({a[2], b[0], b[1], b[2]});
    }
    tets.push_back({rings.back()[0], rings.back()[1], rings.back()[2], apex});
    spike.assign(points.size(), 0);
    for (size_t p = block; p < points.size(); ++p) spike[p] = points[p].z > 28;
  }
};

TEST(LevelBuild, TheRepairPutsBackWhatABrokenBoundNeeds) {
  const SpikedBlock s;
  std::vector<uint32_t> ids(s.points.size());
  std::iota(ids.begin(), ids.end(), 0u);
  // Level 0 carved to the reference, as the codec's builder makes it.
  ReferenceShape shape(s.points, s.tets);
  const ReferenceSolid solid(s.points, s.tets, shape.boundary_triangles());
  TetMesh dt0 = delaunay_tetrahedralize(s.points).value();
  const std::vector<uint8_t> verdicts = solid.verdicts(dt0, s.points);
  StatusOr<LevelGeometry> analysed = analyze_level(s.points, std::move(dt0), {}, verdicts);
  ASSERT_TRUE(analysed.ok()) << analysed.status().message();
  const LevelGeometry& fine = *analysed;
  const CarvedSurface surface0 = carved_surface(fine.dt, fine.in_mesh, fine.points);
  const ShapeMeasurement measured0 = shape.measure(fine.points, ids, surface0.triangles);
  ASSERT_EQ(measured0.to_level.max, 0) << "level 0 has the spike: its apex is on its surface";
  const SurfaceRecord record = record_surface(ids, surface0.triangles, measured0);

  // A choice that keeps the block and drops the whole spike: the apex alone
  // would be 70 units from the level's surface.
  std::vector<uint8_t> keep(s.points.size(), 1);
  for (size_t p = 0; p < s.points.size(); ++p) keep[p] = !s.spike[p];
  LevelBounds bounds;
  bounds.dmax = 3;
  const BuiltLevel built =
      build_coarser_level(s.points, ids, record, keep, {&solid, &shape}, bounds, {}, [](const char*) {
      }).value();
  EXPECT_GT(built.put_back, 0u);
  EXPECT_GT(built.repair_rounds, 0);
  EXPECT_EQ(built.shape_left, 0u);
  // The spike is back as far as D_max needs: the apex is in the level and
  // every reference boundary vertex is within D_max of its surface.
  EXPECT_TRUE(std::binary_search(built.vertices.begin(), built.vertices.end(), s.apex));
  EXPECT_LE(built.shape.to_level.max, bounds.dmax);
  EXPECT_LE(built.shape.to_reference.max, bounds.dmax);
}

}  // namespace
}  // namespace dtm
