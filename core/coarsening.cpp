#include "core/coarsening.h"

#include <algorithm>
#include <cmath>

#include "common/parallel_for.h"
#include "core/boundary_simplification.h"
#include "mesh/geometry.h"

namespace dtm {
namespace {

// One greedy pass at spacing factor beta over `order`; `fixed` vertices are
// kept whatever their neighbours.
Coarsening greedy_pass(const LevelGeometry& L, std::span<const uint32_t> order,
                       std::span<const uint8_t> fixed, std::span<const double> h, double beta) {
  Coarsening c;
  c.beta = beta;
  c.keep.assign(L.size(), 0);
  for (uint32_t v : order) {
    if (!fixed[v]) {
      const Vec3 p = to_vec(L.points[v]);
      auto conflicts = [&](uint32_t w) {
        if (!c.keep[w]) return false;
        const double r = beta * 0.5 * (h[v] + h[w]);
        const Vec3 e = to_vec(L.points[w]) - p;
        return dot(e, e) < r * r;
      };
      bool free = true;
      for (uint32_t u : L.neighbors.row(v))
        if (conflicts(u)) {
          free = false;
          break;
        }
      if (!free) continue;
    }
    c.keep[v] = 1;
    ++c.kept;
  }
  return c;
}

}  // namespace

std::vector<double> local_spacing(const LevelGeometry& L) {
  const size_t n = L.size();
  std::vector<double> sum(n, 0);
  std::vector<uint32_t> count(n, 0);
  // Each thread adds the edges' lengths to the vertices of its own range of
  // ids, the cells in order and each cell's pairs in order: every sum is
  // added up as one pass would, to the bit. (A level's cells are listed by
  // their least corner: a thread's cells come in long runs.)
  const auto add = [&](size_t part, size_t parts) {
    const auto lo = static_cast<uint32_t>(uint64_t{n} * part / parts);
    const auto hi = static_cast<uint32_t>(uint64_t{n} * (part + 1) / parts);
    const auto mine = [&](uint32_t v) { return v - lo < hi - lo; };
    for (size_t c = 0; c < L.dt.cells.size(); ++c) {
      if (!L.in_mesh[c]) continue;
      const auto& k = L.dt.cells[c];
      if (!mine(k[0]) && !mine(k[1]) && !mine(k[2]) && !mine(k[3])) continue;
      for (int i = 0; i < 4; ++i)
        for (int j = i + 1; j < 4; ++j) {
          const bool first = mine(k[i]), second = mine(k[j]);
          if (!first && !second) continue;
          const double d = norm(to_vec(L.points[k[i]]) - to_vec(L.points[k[j]]));
          if (first) sum[k[i]] += d, ++count[k[i]];
          if (second) sum[k[j]] += d, ++count[k[j]];
        }
    }
  };
  if (L.dt.cells.size() < (size_t{1} << 15))
    add(0, 1);
  else
    on_every_thread(add);
  std::vector<double> h(n);
  parallel_for(
      n,
      [&](size_t v) {
        if (count[v] > 0) {
          h[v] = sum[v] / count[v];
          return;
        }
        double s = 0;
        const auto row = L.neighbors.row(v);
        for (uint32_t u : row) s += norm(to_vec(L.points[u]) - to_vec(L.points[v]));
        h[v] = row.empty() ? 0 : s / static_cast<double>(row.size());
      },
      4096);
  return h;
}

Coarsening choose_coarser(const LevelGeometry& L, const LevelSurface& surface, const CoarseningOptions& o) {
  const size_t n = L.size();
  // The chord error of every boundary vertex whose surface neighbourhood is
  // a disk; the other vertices on the surface must stay. A vertex in no kept
  // cell (outside the solid) shapes nothing: it is chosen like an interior one.
  std::vector<uint8_t> on_surface(n, 0), fixed(n, 0);
  for (uint32_t v = 0; v < n; ++v) on_surface[v] = surface.holds(L.boundary, v);
  fixed = on_surface;
  std::vector<double> error(n, 0);
  const Csr none{std::vector<uint32_t>(n + 1, 0), {}};
  for (const BoundaryCandidate& b :
       boundary_candidates(L, surface, none, {}, std::numeric_limits<double>::infinity())) {
    error[b.vertex] = b.error;
    fixed[b.vertex] = b.error > o.dmax;
  }
  std::vector<uint32_t> order;
  order.reserve(n);
  std::vector<uint32_t> boundary;
  for (uint32_t v = 0; v < n; ++v) {
    if (fixed[v])
      order.push_back(v);
    else if (on_surface[v])
      boundary.push_back(v);
  }
  std::stable_sort(boundary.begin(), boundary.end(),
                   [&](uint32_t a, uint32_t b) { return error[a] > error[b]; });
  order.insert(order.end(), boundary.begin(), boundary.end());
  for (uint32_t v = 0; v < n; ++v)
    if (!on_surface[v]) order.push_back(v);

  const std::vector<double> h = local_spacing(L);
  // The kept count falls as beta grows. From the caller's guess (the
  // previous level's beta), secant steps on the count, kept inside a
  // bracket: three or four passes find the share within 1%.
  const double target = o.keep_share * static_cast<double>(n);
  const double tolerance = 0.01 * static_cast<double>(n);
  double lo = 0.3, hi = 3.0;  // kept(lo) > target > kept(hi), as far as known
  double beta = std::clamp(o.beta_guess, lo, hi);
  Coarsening best;
  double prev_beta = 0, prev_kept = 0;
  for (int trial = 0; trial < 16; ++trial) {
    Coarsening c = greedy_pass(L, order, fixed, h, beta);
    const double kept = static_cast<double>(c.kept);
    if (best.keep.empty() || std::abs(kept - target) < std::abs(static_cast<double>(best.kept) - target))
      best = std::move(c);
    if (std::abs(static_cast<double>(best.kept) - target) <= tolerance) break;
    (kept > target ? lo : hi) = beta;
    double next = 0.5 * (lo + hi);
    if (trial > 0 && kept != prev_kept) {
      const double secant = beta + (target - kept) * (beta - prev_beta) / (kept - prev_kept);
      if (secant > lo && secant < hi) next = secant;
    } else if (trial == 0) {
      // The share kept goes roughly as beta^-3 in a volume.
      const double scaled = beta * std::cbrt(kept / std::max(1.0, target));
      if (scaled > lo && scaled < hi) next = scaled;
    }
    prev_beta = beta, prev_kept = kept;
    beta = next;
  }
  best.fixed = static_cast<uint64_t>(std::count(fixed.begin(), fixed.end(), 1));
  return best;
}

}  // namespace dtm
