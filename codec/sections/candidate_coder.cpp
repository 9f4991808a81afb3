#include "codec/sections/candidate_coder.h"

#include <algorithm>
#include <bit>
#include <limits>
#include <utility>

#include "codec/sections/candidate_coder_shared.h"
#include "common/parallel_for.h"
#include "common/release.h"
#include "mesh/topology.h"

namespace dtm {
namespace {

int64_t floor_div(int64_t a, int64_t b) {  // b > 0
  const int64_t q = a / b;
  return (a % b != 0 && a < 0) ? q - 1 : q;
}

int bit_width(int64_t v) { return static_cast<int>(std::bit_width(static_cast<uint64_t>(v))); }

int64_t squared_distance(const GridPoint& a, const GridPoint& b) {
  const int64_t dx = int64_t{a.x} - b.x, dy = int64_t{a.y} - b.y, dz = int64_t{a.z} - b.z;
  return dx * dx + dy * dy + dz * dz;
}

// The circumcentre of a cell rounded to the grid (each coordinate
// floor(c + 1/2), computed exactly), and its context; false when the cell
// gives none (too large, or the centre is outside the grid). Neither depends
// on the order of the cell's vertices: the rounded centre is p0 plus the
// rounded offset for any vertex p0 (p0 is on the grid), and the context
// takes the centre's nearest vertex.
bool cell_centre(const std::array<uint32_t, 4>& ids, std::span<const GridPoint> coarse, int qbits,
                 GridPoint& at, int& context) {
  const GridPoint& p0 = coarse[ids[0]];
  int64_t d[3][3];
  for (int i = 0; i < 3; ++i) {
    const GridPoint& q = coarse[ids[i + 1]];
    d[i][0] = int64_t{q.x} - p0.x, d[i][1] = int64_t{q.y} - p0.y, d[i][2] = int64_t{q.z} - p0.z;
  }
  for (int axis = 0; axis < 3; ++axis) {
    int64_t lo = 0, hi = 0;
    for (const auto& row : d) lo = std::min(lo, row[axis]), hi = std::max(hi, row[axis]);
    if (hi - lo >= kMaxCandidateCellExtent) return false;
  }
  // |d| < 2^13: |a|^2 < 2^28, cross products < 2^27, numerators < 2^57.
  auto cross = [](const int64_t* u, const int64_t* v, int64_t* w) {
    w[0] = u[1] * v[2] - u[2] * v[1], w[1] = u[2] * v[0] - u[0] * v[2], w[2] = u[0] * v[1] - u[1] * v[0];
  };
  int64_t bc[3], ca[3], ab[3];
  cross(d[1], d[2], bc), cross(d[2], d[0], ca), cross(d[0], d[1], ab);
  const int64_t det2 = 2 * (d[0][0] * bc[0] + d[0][1] * bc[1] + d[0][2] * bc[2]);
  if (det2 == 0) return false;
  int64_t len2[3];
  for (int i = 0; i < 3; ++i) len2[i] = d[i][0] * d[i][0] + d[i][1] * d[i][1] + d[i][2] * d[i][2];
  int64_t off[3];
  const int64_t den = std::abs(det2);
  for (int k = 0; k < 3; ++k) {
    int64_t num = len2[0] * bc[k] + len2[1] * ca[k] + len2[2] * ab[k];
    if (det2 < 0) num = -num;
    off[k] = floor_div(2 * num + den, 2 * den);
    // Beyond the grid's side from a grid point: outside the grid.
    if (std::abs(off[k]) >= (int64_t{1} << qbits)) return false;
  }
  const int64_t x = p0.x + off[0], y = p0.y + off[1], z = p0.z + off[2];
  if (!candidate_inside_grid(x, y, z, qbits)) return false;
  at = {static_cast<int32_t>(x), static_cast<int32_t>(y), static_cast<int32_t>(z)};
  int64_t shortest = std::numeric_limits<int64_t>::max(), nearest = std::numeric_limits<int64_t>::max();
  for (int i = 0; i < 4; ++i) {
    nearest = std::min(nearest, squared_distance(at, coarse[ids[i]]));
    for (int j = i + 1; j < 4; ++j)
      shortest = std::min(shortest, squared_distance(coarse[ids[i]], coarse[ids[j]]));
  }
  context = std::clamp(bit_width(nearest) - bit_width(shortest) + 2, 0, kCentreContexts - 1);
  return true;
}

uint64_t key_of(const GridPoint& at, int context, int qbits) {
  return (static_cast<uint64_t>(morton_encode(at, qbits)) << kCandidateContextBits) |
         static_cast<uint64_t>(context);
}

// Runs emit_block(first, last, out) over blocks of [0, n) on every core and
// joins the blocks' keys in order.
template <class EmitBlock>
void keys_in_blocks(size_t n, std::vector<uint64_t>& keys, const EmitBlock& emit_block) {
  constexpr size_t kBlock = 1 << 14;
  const size_t blocks = (n + kBlock - 1) / kBlock;
  std::vector<std::vector<uint64_t>> found(blocks);
  parallel_for(blocks, [&](size_t b) { emit_block(b * kBlock, std::min(n, (b + 1) * kBlock), found[b]); });
  size_t total = keys.size();
  for (const auto& f : found) total += f.size();
  keys.reserve(total);
  for (auto& f : found) {
    keys.insert(keys.end(), f.begin(), f.end());
    release(f);
  }
}

void add_cell_centres(std::span<const std::array<uint32_t, 4>> cells, std::span<const GridPoint> coarse,
                      int qbits, std::vector<uint64_t>& keys) {
  keys_in_blocks(cells.size(), keys, [&](size_t first, size_t last, std::vector<uint64_t>& out) {
    GridPoint at;
    int context = 0;
    for (size_t i = first; i < last; ++i)
      if (cell_centre(cells[i], coarse, qbits, at, context)) out.push_back(key_of(at, context, qbits));
  });
}

void add_edge_midpoints(std::span<const std::array<uint32_t, 4>> cells, std::span<const GridPoint> coarse,
                        int qbits, std::vector<uint64_t>& keys) {
  const Csr neighbours = vertex_neighbors(cells, vertex_cells(cells, coarse.size()));
  std::vector<int64_t> nearest(coarse.size(), std::numeric_limits<int64_t>::max());
  parallel_for(
      coarse.size(),
      [&](size_t u) {
        for (uint32_t v : neighbours.row(u))
          nearest[u] = std::min(nearest[u], squared_distance(coarse[u], coarse[v]));
      },
      1 << 14);
  keys_in_blocks(coarse.size(), keys, [&](size_t first, size_t last, std::vector<uint64_t>& out) {
    for (size_t u = first; u < last; ++u)
      for (uint32_t v : neighbours.row(u)) {
        if (v < u) continue;
        const GridPoint& a = coarse[u];
        const GridPoint& b = coarse[v];
        // Half up: the coordinates are not negative.
        const GridPoint mid{(a.x + b.x + 1) >> 1, (a.y + b.y + 1) >> 1, (a.z + b.z + 1) >> 1};
        const int ratio = bit_width(squared_distance(a, b)) - bit_width(std::min(nearest[u], nearest[v]));
        out.push_back(key_of(mid, kCentreContexts + std::clamp(ratio, 0, kMidpointContexts - 1), qbits));
      }
  });
}

// Sorts keys of at most `bits` significant bits: least significant digit
// first, 16 bits a pass.
void radix_sort(std::vector<uint64_t>& keys, int bits) {
  std::vector<uint64_t> other(keys.size());
  std::vector<size_t> start(size_t{1} << 16);
  for (int shift = 0; shift < bits; shift += 16) {
    std::fill(start.begin(), start.end(), 0);
    for (uint64_t k : keys) ++start[(k >> shift) & 0xffff];
    size_t sum = 0;
    for (size_t& s : start) sum += std::exchange(s, sum);
    for (uint64_t k : keys) other[start[(k >> shift) & 0xffff]++] = k;
    keys.swap(other);
  }
}

}  // namespace

CandidateList layer_candidates(std::span<const std::array<uint32_t, 4>> cells,
                               std::span<const GridPoint> coarse, std::span<const MortonCode> known,
                               int qbits, uint8_t kinds) {
  CandidateList out;
  out.qbits = qbits;
  if (qbits > kMaxCandidateQBits) return out;
  std::vector<uint64_t>& keys = out.keys;
  if (kinds & kCandidateCellCentres) add_cell_centres(cells, coarse, qbits, keys);
  if (kinds & kCandidateEdgeMidpoints) add_edge_midpoints(cells, coarse, qbits, keys);
  radix_sort(keys, 3 * qbits + kCandidateContextBits);
  // Distinct places (the first is the smallest context), none known: one
  // walk beside the known codes, both ascending.
  size_t kept = 0, k = 0;
  for (size_t i = 0; i < keys.size(); ++i) {
    const uint64_t code = keys[i] >> kCandidateContextBits;
    if (kept > 0 && (keys[kept - 1] >> kCandidateContextBits) == code) continue;
    while (k < known.size() && known[k] < code) ++k;
    if (k < known.size() && known[k] == code) continue;
    keys[kept++] = keys[i];
  }
  keys.resize(kept);
  keys.shrink_to_fit();
  return out;
}

bool candidate_inside_grid(int64_t x, int64_t y, int64_t z, int qbits) {
  const int64_t side = int64_t{1} << qbits;
  return x >= 0 && y >= 0 && z >= 0 && x < side && y < side && z < side;
}

}  // namespace dtm
