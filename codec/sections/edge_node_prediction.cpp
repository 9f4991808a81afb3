// Where a curved surface's edge nodes are expected (format 19.0,
// spec/FORMAT.md §3.11): each surface edge's node predicted from its
// corners' normals as a curved (PN) triangle's edge passes halfway, in
// exact integer arithmetic, so that every decoder predicts the same offsets.
#include <algorithm>

#include "codec/sections/edge_node_coder.h"
#include "codec/sections/face_coder.h"
#include "mesh/geometry.h"

namespace dtm {
namespace {

using Vec = std::array<int64_t, 3>;
using Wide = std::array<Int128, 3>;

Vec minus(const GridPoint& a, const GridPoint& b) {
  return {int64_t{a.x} - b.x, int64_t{a.y} - b.y, int64_t{a.z} - b.z};
}

// Floor of n / d for d > 0.
Int128 floor_div(Int128 n, Int128 d) {
  const Int128 q = n / d;
  return (n % d != 0 && n < 0) ? q - 1 : q;
}

}  // namespace

std::vector<std::array<int64_t, 3>> predicted_edge_offsets(const TetMesh& mesh, std::span<const uint8_t> kept,
                                                           const LevelEdges& edges,
                                                           std::span<const GridPoint> points, int qbits) {
  std::vector<std::array<int64_t, 3>> out(edges.corners.size(), {0, 0, 0});
  // Each vertex's normal: the sum of its surface faces' (b - a) x (c - a),
  // turned out of the kept cell the surface takes the face from.
  std::vector<Wide> sum(points.size(), {0, 0, 0});
  for (const SurfaceFace& f : surface_faces(mesh, kept).faces) {
    const GridPoint &a = points[f.key[0]], &b = points[f.key[1]], &c = points[f.key[2]];
    const GridPoint& o = points[mesh.cells[f.cell][f.opposite]];
    const Vec u = minus(b, a), v = minus(c, a), w = minus(o, a);
    Vec n = {u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]};
    const Int128 side = Int128{n[0]} * w[0] + Int128{n[1]} * w[1] + Int128{n[2]} * w[2];
    if (side > 0) n = {-n[0], -n[1], -n[2]};
    for (uint32_t k : f.key)
      for (size_t i = 0; i < 3; ++i) sum[k][i] += n[i];
  }
  // ... scaled to components of at most 20 bits (shifted right, toward
  // minus infinity): what the prediction's products need.
  std::vector<Vec> normal(points.size());
  for (size_t v = 0; v < points.size(); ++v) {
    Int128 largest = 0;
    for (Int128 s : sum[v]) largest = std::max(largest, s < 0 ? -s : s);
    int bits = 0;
    while (bits < 127 && (largest >> bits) != 0) ++bits;
    const int shift = std::max(0, bits - 20);
    for (size_t i = 0; i < 3; ++i) normal[v][i] = static_cast<int64_t>(sum[v][i] >> shift);
  }
  for (size_t e = 0; e < edges.corners.size(); ++e) {
    if (!edges.on_surface[e]) continue;
    const uint32_t a = edges.corners[e][0], b = edges.corners[e][1];
    // Per corner v, with normal N and d the edge from it: (d . N) N / |N|^2;
    // the node 2 (m - p) = -(t_a + t_b) / 4 half steps off the midpoint m.
    Int128 num[2][3], den[2];
    for (int side = 0; side < 2; ++side) {
      const uint32_t v = side == 0 ? a : b, w = side == 0 ? b : a;
      const Vec& n = normal[v];
      const Vec d = minus(points[w], points[v]);
      den[side] = Int128{n[0]} * n[0] + Int128{n[1]} * n[1] + Int128{n[2]} * n[2];
      const Int128 dot = Int128{d[0]} * n[0] + Int128{d[1]} * n[1] + Int128{d[2]} * n[2];
      for (size_t i = 0; i < 3; ++i) num[side][i] = den[side] == 0 ? 0 : dot * n[i];
      if (den[side] == 0) den[side] = 1;
    }
    const Int128 d = 4 * den[0] * den[1];
    for (size_t i = 0; i < 3; ++i) {
      const Int128 s = num[0][i] * den[1] + num[1][i] * den[0];
      // (Within +-2^(qbits + 1): a grid's edge makes less, and a residual
      // then stays within what the section codes.)
      const Int128 bound = Int128{1} << (qbits + 1);
      out[e][i] = static_cast<int64_t>(std::clamp(floor_div(d - 2 * s, 2 * d), -bound, bound));
    }
  }
  return out;
}

}  // namespace dtm
