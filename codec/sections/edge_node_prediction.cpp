// Where a curved surface's edge nodes are expected (formats 19.0 and 20.0,
// spec/FORMAT.md §3.11): each surface edge's node predicted from its
// corners' normals as a curved (PN) triangle's edge passes halfway, and in
// 20.0 a crease's node from the crease's own curve, in exact integer
// arithmetic, so that every decoder predicts the same offsets.
#include <algorithm>
#include <numeric>
#include <utility>

#include "codec/sections/edge_node_coder.h"
#include "codec/sections/face_coder.h"

namespace dtm {
namespace {

using Vec = std::array<int64_t, 3>;

Vec minus(const GridPoint& a, const GridPoint& b) {
  return {int64_t{a.x} - b.x, int64_t{a.y} - b.y, int64_t{a.z} - b.z};
}

Int128 dot(const Vec& u, const Vec& v) {
  return Int128{u[0]} * v[0] + Int128{u[1]} * v[1] + Int128{u[2]} * v[2];
}

// Floor of n / d for d > 0.
Int128 floor_div(Int128 n, Int128 d) {
  const Int128 q = n / d;
  return (n % d != 0 && n < 0) ? q - 1 : q;
}

// A sum of normals scaled to components within +-2^20, shifted right
// (toward minus infinity): what the predictions' products need.
Vec within_2_20(const std::array<Int128, 3>& s) {
  Int128 largest = 0;
  for (Int128 c : s) largest = std::max(largest, c < 0 ? -c : c);
  int bits = 0;
  while (bits < 127 && (largest >> bits) != 0) ++bits;
  const int shift = std::max(0, bits - 20);
  return {static_cast<int64_t>(s[0] >> shift), static_cast<int64_t>(s[1] >> shift),
          static_cast<int64_t>(s[2] >> shift)};
}

// Whether two directions part by more than 60 degrees: u.v <= 0, or
// 4 (u.v)^2 < |u|^2 |v|^2 (each component within 2^24: the products
// within 2^100).
bool sharp(const Vec& u, const Vec& v) {
  const Int128 d = dot(u, v);
  return d <= 0 || 4 * d * d < dot(u, u) * dot(v, v);
}

// Floor of the square root of n >= 0 (Newton's iteration from above).
Int128 isqrt(Int128 n) {
  using U = unsigned __int128;
  if (n < 2) return n < 0 ? 0 : n;
  int bits = 0;
  while (bits < 127 && (n >> bits) != 0) ++bits;
  U x = U{1} << ((bits + 1) / 2);
  while (true) {
    const U y = (x + static_cast<U>(n) / x) >> 1;
    if (y >= x) return static_cast<Int128>(x);
    x = y;
  }
}

}  // namespace

EdgeNodePredictor::EdgeNodePredictor(const TetMesh& mesh, std::span<const uint8_t> kept,
                                     std::span<const GridPoint> points, int qbits, bool creases)
    : points_(points), qbits_(qbits), creases_(creases), slot_(points.size(), kOffSurface) {
  // Each surface face's (B - A) x (C - A), turned out of the kept cell the
  // surface takes it from (points below 2^24: each product below 2^50).
  const SurfaceFaces surface = surface_faces(mesh, kept);
  std::vector<Vec> normal;
  normal.reserve(surface.faces.size());
  for (const SurfaceFace& f : surface.faces) {
    const GridPoint &a = points[f.key[0]], &b = points[f.key[1]], &c = points[f.key[2]];
    const GridPoint& o = points[mesh.cells[f.cell][f.opposite]];
    const Vec u = minus(b, a), v = minus(c, a);
    Vec n = {u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]};
    if (dot(n, minus(o, a)) > 0) n = {-n[0], -n[1], -n[2]};
    normal.push_back(n);
  }
  if (!creases_) {
    // 19.0: each surface vertex's normal, the sum of its faces'.
    std::vector<std::array<Int128, 3>> sum;
    for (size_t f = 0; f < surface.faces.size(); ++f)
      for (uint32_t k : surface.faces[f].key) {
        if (slot_[k] == kOffSurface) slot_[k] = static_cast<uint32_t>(sum.size()), sum.push_back({0, 0, 0});
        for (size_t i = 0; i < 3; ++i) sum[slot_[k]][i] += normal[f][i];
      }
    normals_.reserve(sum.size());
    for (const auto& s : sum) normals_.push_back(within_2_20(s));
    return;
  }
  // 20.0: per surface vertex (slots in the order the faces reach them),
  // its faces, in the faces' order.
  uint32_t slots = 0;
  std::vector<uint32_t> vertex;  // per slot
  for (const SurfaceFace& f : surface.faces)
    for (uint32_t k : f.key)
      if (slot_[k] == kOffSurface) slot_[k] = slots++, vertex.push_back(k);
  std::vector<uint32_t> face_start(slots + 1, 0), vertex_faces;
  for (const SurfaceFace& f : surface.faces)
    for (uint32_t k : f.key) ++face_start[slot_[k] + 1];
  std::partial_sum(face_start.begin(), face_start.end(), face_start.begin());
  vertex_faces.resize(face_start.back());
  std::vector<uint32_t> fill(face_start.begin(), face_start.end() - 1);
  for (uint32_t f = 0; f < surface.faces.size(); ++f)
    for (uint32_t k : surface.faces[f].key) vertex_faces[fill[slot_[k]]++] = f;
  std::vector<Vec> direction;  // each face's normal within +-2^20, for the angles
  direction.reserve(normal.size());
  for (const Vec& n : normal) direction.push_back(within_2_20({n[0], n[1], n[2]}));
  // Per vertex v, its edges on the surface: (w, a face on it), sorted; an
  // edge of two faces that part by 60 degrees or less joins them in one
  // sector of faces about v; an edge of one, or of three or more, or of
  // two that part more, is a crease.
  neighbour_start_.assign(slots + 1, 0);
  crease_ends_.assign(slots, {0, 0, 0});
  std::vector<std::pair<uint32_t, uint32_t>> edges;  // (w, local face)
  std::vector<uint32_t> parent;
  std::vector<std::array<Int128, 3>> sums;
  for (uint32_t s = 0; s < slots; ++s) {
    const std::span<const uint32_t> faces =
        std::span(vertex_faces).subspan(face_start[s], face_start[s + 1] - face_start[s]);
    const uint32_t v = vertex[s];
    edges.clear();
    for (uint32_t i = 0; i < faces.size(); ++i)
      for (uint32_t w : surface.faces[faces[i]].key)
        if (w != v) edges.emplace_back(w, i);
    std::sort(edges.begin(), edges.end());
    parent.resize(faces.size());
    std::iota(parent.begin(), parent.end(), 0u);
    const auto root = [&](uint32_t i) {
      while (parent[i] != i) i = parent[i] = parent[parent[i]];
      return i;
    };
    std::vector<std::pair<uint32_t, bool>> neighbours;  // (w, crease)
    for (size_t b = 0; b < edges.size();) {
      size_t e = b;
      while (e < edges.size() && edges[e].first == edges[b].first) ++e;
      const bool smooth =
          e - b == 2 && !sharp(direction[faces[edges[b].second]], direction[faces[edges[b + 1].second]]);
      if (smooth) {
        const uint32_t x = root(edges[b].second), y = root(edges[b + 1].second);
        parent[std::max(x, y)] = std::min(x, y);
      }
      neighbours.emplace_back(edges[b].first, !smooth);
      b = e;
    }
    // Each sector's normal, the sum of its faces'.
    sums.assign(faces.size(), {0, 0, 0});
    for (uint32_t i = 0; i < faces.size(); ++i)
      for (size_t k = 0; k < 3; ++k) sums[root(i)][k] += normal[faces[i]][k];
    std::vector<uint32_t> sector(faces.size(), kOffSurface);
    for (uint32_t i = 0; i < faces.size(); ++i)
      if (root(i) == i)
        sector[i] = static_cast<uint32_t>(normals_.size()), normals_.push_back(within_2_20(sums[i]));
    // Its neighbours with their edge's sector at v (kCrease: a crease).
    for (size_t b = 0, n = 0; b < edges.size(); ++n) {
      size_t e = b;
      while (e < edges.size() && edges[e].first == edges[b].first) ++e;
      const auto [w, crease] = neighbours[n];
      neighbour_vertex_.push_back(w);
      neighbour_sector_.push_back(crease ? kCrease : sector[root(edges[b].second)]);
      if (crease) {
        auto& ends = crease_ends_[s];
        if (ends[0] < 2) ends[1 + ends[0]] = w;
        ++ends[0];
      }
      b = e;
    }
    neighbour_start_[s + 1] = static_cast<uint32_t>(neighbour_vertex_.size());
  }
}

std::array<Int128, 3> EdgeNodePredictor::normals_offset(uint32_t a, uint32_t b, const Vec& na,
                                                        const Vec& nb) const {
  // Per corner v, with normal N and d the edge from it: T_v = (d . N) N
  // over D_v = |N|^2, the projection of d on N; the node p lies
  // 2 (p - m) = -(T_a / D_a + T_b / D_b) / 4 half steps off the midpoint m
  // (normals within 2^20, edges within 2^25: T below 2^67, D below 2^42).
  Int128 t[2][3], den[2];
  for (int side = 0; side < 2; ++side) {
    const Vec& n = side == 0 ? na : nb;
    const Vec d = side == 0 ? minus(points_[b], points_[a]) : minus(points_[a], points_[b]);
    den[side] = dot(n, n);
    const Int128 along = dot(d, n);
    for (size_t i = 0; i < 3; ++i) t[side][i] = den[side] == 0 ? 0 : along * n[i];
    if (den[side] == 0) den[side] = 1;
  }
  const Int128 q = 4 * den[0] * den[1];
  std::array<Int128, 3> out;
  for (size_t i = 0; i < 3; ++i) out[i] = floor_div(q - 2 * (t[0][i] * den[1] + t[1][i] * den[0]), 2 * q);
  return out;
}

std::array<Int128, 3> EdgeNodePredictor::crease_offset(uint32_t a, uint32_t b) const {
  // A cubic from a to b whose tangents run along the crease: at a corner
  // with one other crease edge, to c, that turns by 60 degrees or less,
  // the direction from c past it (b - c at a, c - a at b); elsewhere the
  // edge's own. Its midpoint lies (T_a - T_b) / 8 off the edge's, T_v the
  // tangent's direction at the edge's length |d|: in half steps
  // (f_a t_a - f_b t_b) / 2^22, f_v = isqrt(|d|^2 2^40 / |t_v|^2)
  // (|d|^2 and |t|^2 below 2^50, f below 2^45, each product below 2^70).
  const Vec d = minus(points_[b], points_[a]);
  const auto tangent = [&](uint32_t v, uint32_t other, bool at_a) {
    const auto& ends = crease_ends_[slot_[v]];
    if (ends[0] != 2) return d;
    const uint32_t c = ends[1] == other ? ends[2] : ends[1];
    // (The crease through v: from c to v to the edge's other end.)
    const Vec in = at_a ? minus(points_[v], points_[c]) : d;
    const Vec out = at_a ? d : minus(points_[c], points_[v]);
    if (sharp(in, out)) return d;
    return at_a ? minus(points_[other], points_[c]) : minus(points_[c], points_[other]);
  };
  const Vec ta = tangent(a, b, true), tb = tangent(b, a, false);
  const Int128 length2 = dot(d, d) << 40;
  const Int128 fa = isqrt(length2 / dot(ta, ta)), fb = isqrt(length2 / dot(tb, tb));
  std::array<Int128, 3> out;
  for (size_t i = 0; i < 3; ++i)
    out[i] = floor_div(2 * (fa * ta[i] - fb * tb[i]) + (Int128{1} << 22), Int128{1} << 23);
  return out;
}

std::array<int64_t, 3> EdgeNodePredictor::offset(uint32_t a, uint32_t b) const {
  std::array<Int128, 3> p;
  if (!creases_) {
    const Vec zero = {0, 0, 0};
    p = normals_offset(a, b, slot_[a] == kOffSurface ? zero : normals_[slot_[a]],
                       slot_[b] == kOffSurface ? zero : normals_[slot_[b]]);
  } else {
    // (A surface edge: both corners on the surface, each the other's
    // neighbour there.)
    const auto sector_at = [&](uint32_t v, uint32_t w) {
      const uint32_t s = slot_[v];
      if (s == kOffSurface) return kNotSurfaceEdge;
      const auto first = neighbour_vertex_.begin() + neighbour_start_[s],
                 last = neighbour_vertex_.begin() + neighbour_start_[s + 1];
      const auto it = std::lower_bound(first, last, w);
      return it == last || *it != w ? kNotSurfaceEdge
                                    : neighbour_sector_[static_cast<size_t>(it - neighbour_vertex_.begin())];
    };
    const uint32_t sa = sector_at(a, b), sb = sector_at(b, a);
    if (sa == kNotSurfaceEdge || sb == kNotSurfaceEdge) return {0, 0, 0};
    p = sa == kCrease || sb == kCrease ? crease_offset(a, b)
                                       : normals_offset(a, b, normals_[sa], normals_[sb]);
  }
  // (Within +-2^(qbits + 1): a grid's edge makes less, and a node's
  // difference from it then stays within what the section codes.)
  const Int128 bound = Int128{1} << (qbits_ + 1);
  std::array<int64_t, 3> out;
  for (size_t i = 0; i < 3; ++i) out[i] = static_cast<int64_t>(std::clamp(p[i], -bound, bound));
  return out;
}

}  // namespace dtm
