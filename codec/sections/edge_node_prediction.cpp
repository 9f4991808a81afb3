// Where a curved surface's edge nodes are expected (format 19.0,
// spec/FORMAT.md §3.11): each surface edge's node predicted from its
// corners' normals as a curved (PN) triangle's edge passes halfway, in
// exact integer arithmetic, so that every decoder predicts the same offsets.
#include <algorithm>

#include "codec/sections/edge_node_coder.h"
#include "codec/sections/face_coder.h"

namespace dtm {
namespace {

using Vec = std::array<int64_t, 3>;

Vec minus(const GridPoint& a, const GridPoint& b) {
  return {int64_t{a.x} - b.x, int64_t{a.y} - b.y, int64_t{a.z} - b.z};
}

// Floor of n / d for d > 0.
Int128 floor_div(Int128 n, Int128 d) {
  const Int128 q = n / d;
  return (n % d != 0 && n < 0) ? q - 1 : q;
}

}  // namespace

EdgeNodePredictor::EdgeNodePredictor(const TetMesh& mesh, std::span<const uint8_t> kept,
                                     std::span<const GridPoint> points, int qbits)
    : points_(points), qbits_(qbits), slot_(points.size(), kOffSurface) {
  // Each surface vertex's normal: the sum of its surface faces'
  // (B - A) x (C - A), turned out of the kept cell the surface takes the
  // face from (points below 2^24: each product below 2^50, each sum well
  // within 128 bits).
  std::vector<std::array<Int128, 3>> sum;
  for (const SurfaceFace& f : surface_faces(mesh, kept).faces) {
    const GridPoint &a = points[f.key[0]], &b = points[f.key[1]], &c = points[f.key[2]];
    const GridPoint& o = points[mesh.cells[f.cell][f.opposite]];
    const Vec u = minus(b, a), v = minus(c, a), w = minus(o, a);
    Vec n = {u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]};
    const Int128 side = Int128{n[0]} * w[0] + Int128{n[1]} * w[1] + Int128{n[2]} * w[2];
    if (side > 0) n = {-n[0], -n[1], -n[2]};
    for (uint32_t k : f.key) {
      if (slot_[k] == kOffSurface) slot_[k] = static_cast<uint32_t>(sum.size()), sum.push_back({0, 0, 0});
      for (size_t i = 0; i < 3; ++i) sum[slot_[k]][i] += n[i];
    }
  }
  // ... scaled to components within +-2^20 (shifted right, toward minus
  // infinity): what the prediction's products need.
  normals_.reserve(sum.size());
  for (const auto& s : sum) {
    Int128 largest = 0;
    for (Int128 c : s) largest = std::max(largest, c < 0 ? -c : c);
    int bits = 0;
    while (bits < 127 && (largest >> bits) != 0) ++bits;
    const int shift = std::max(0, bits - 20);
    normals_.push_back({static_cast<int64_t>(s[0] >> shift), static_cast<int64_t>(s[1] >> shift),
                        static_cast<int64_t>(s[2] >> shift)});
  }
}

std::array<int64_t, 3> EdgeNodePredictor::offset(uint32_t a, uint32_t b) const {
  // Per corner v, with normal N and d the edge from it: T_v = (d . N) N
  // over D_v = |N|^2, the projection of d on N; the node p lies
  // 2 (p - m) = -(T_a / D_a + T_b / D_b) / 4 half steps off the midpoint m
  // (normals within 2^20, edges within 2^25: T below 2^67, D below 2^42).
  Int128 t[2][3], den[2];
  for (int side = 0; side < 2; ++side) {
    const uint32_t v = side == 0 ? a : b, w = side == 0 ? b : a;
    const Vec n = slot_[v] == kOffSurface ? Vec{0, 0, 0} : normals_[slot_[v]];
    const Vec d = minus(points_[w], points_[v]);
    den[side] = Int128{n[0]} * n[0] + Int128{n[1]} * n[1] + Int128{n[2]} * n[2];
    const Int128 dot = Int128{d[0]} * n[0] + Int128{d[1]} * n[1] + Int128{d[2]} * n[2];
    for (size_t i = 0; i < 3; ++i) t[side][i] = den[side] == 0 ? 0 : dot * n[i];
    if (den[side] == 0) den[side] = 1;
  }
  // (Within +-2^(qbits + 1): a grid's edge makes less, and a node's
  // difference from it then stays within what the section codes.)
  const Int128 q = 4 * den[0] * den[1], bound = Int128{1} << (qbits_ + 1);
  std::array<int64_t, 3> out;
  for (size_t i = 0; i < 3; ++i) {
    const Int128 s = t[0][i] * den[1] + t[1][i] * den[0];
    out[i] = static_cast<int64_t>(std::clamp(floor_div(q - 2 * s, 2 * q), -bound, bound));
  }
  return out;
}

}  // namespace dtm
