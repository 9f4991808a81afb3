#include "codec/sections/carving_coder.h"

#include <algorithm>
#include <array>
#include <boost/multiprecision/cpp_int.hpp>
#include <limits>

#include "codec/sections/carving_coder_shared.h"
#include "common/parallel_for.h"
#include "mesh/carving.h"
#include "mesh/geometry.h"
#include "mesh/predicates.h"
#include "mesh/topology.h"

namespace dtm {
namespace {

// Circumradius over alpha, in quarter octaves from 2^-7/4 to 2^7/4: the
// bucket is how many of these the ratio exceeds (spec/FORMAT.md §3.2 lists
// them; products with alpha are exact IEEE operations, so both sides agree).
constexpr std::array<double, kCarvingRatioBuckets - 1> kRatioSteps = {
    0.29730177875068026, 0.3535533905932738, 0.42044820762685725, 0.5,
    0.5946035575013605,  0.7071067811865476, 0.8408964152537145,  1.0,
    1.189207115002721,   1.4142135623730951, 1.681792830507429,   2.0,
    2.378414230005442,   2.8284271247461903, 3.363585661014858};
static_assert(kRatioSteps[7] == 1.0, "bucket 8 and above: alpha removes the cell");

}  // namespace

ChunkCells group_by_chunk(std::span<const uint32_t> order, std::span<const uint32_t> chunk_of_cell,
                          size_t chunk_count) {
  ChunkCells g;
  g.first.assign(chunk_count + 1, 0);
  for (uint32_t c : order)
    if (chunk_of_cell[c] != kNoCarvingChunk) ++g.first[chunk_of_cell[c] + 1];
  for (size_t i = 0; i < chunk_count; ++i) g.first[i + 1] += g.first[i];
  g.cells.resize(g.first[chunk_count]);
  std::vector<uint32_t> next(g.first.begin(), g.first.end() - 1);
  for (uint32_t c : order)
    if (chunk_of_cell[c] != kNoCarvingChunk) g.cells[next[chunk_of_cell[c]]++] = c;
  return g;
}

// A bricked layer's coding order: the cells by their vertices' ranks
// (each cell's ascending, cells ascending), as canonical_cell_order orders
// them by vertex number.
std::vector<uint32_t> ranked_order(const TetMesh& dt, std::span<const uint32_t> vertex_rank) {
  std::vector<std::array<uint32_t, 4>> ranked(dt.cells.size());
  parallel_ranges(ranked.size(), 16384, [&](size_t first, size_t last) {
    for (size_t c = first; c < last; ++c)
      for (int i = 0; i < 4; ++i) ranked[c][i] = vertex_rank[dt.cells[c][i]];
  });
  return canonical_cell_order(ranked);
}

ChunkCells chunk_cells(const TetMesh& dt, std::span<const uint32_t> chunk_of_cell, size_t chunk_count,
                       std::span<const uint32_t> vertex_rank) {
  return group_by_chunk(ranked_order(dt, vertex_rank), chunk_of_cell, chunk_count);
}

CarvingContexts carving_contexts(uint8_t format_major) {
  return format_major >= 6 ? CarvingContexts::kDecodedNeighbours : CarvingContexts::kAlphaNeighbours;
}

CarvingContexts exact_carving_contexts(uint8_t format_major) {
  // (14.0's flip flags, exact_cell_coder.h, code the flips 13.0's contexts
  // told the carving of: without them it spends less on the TetGen models,
  // 0.01-0.06 bits a vertex, and as much on the Netgen and gmsh parts.)
  return format_major == 13   ? CarvingContexts::kExactMarginShapeFlip
         : format_major >= 12 ? CarvingContexts::kExactMarginShape
                              : CarvingContexts::kExactMargin;
}

CarvingPrediction predict_carving(const TetMesh& dt, std::span<const GridPoint> points, double alpha,
                                  CarvingContexts contexts, std::span<const uint32_t> chunk_of_cell) {
  const size_t m = dt.cells.size();
  CarvingPrediction p;
  p.kept.resize(m);
  std::vector<uint8_t> bucket(m);
  // Each cell on its own: every core (the same bits whatever the split).
  constexpr size_t kBlock = 4096;
  const size_t blocks = (m + kBlock - 1) / kBlock;
  parallel_for(
      blocks,
      [&](size_t block) {
        for (size_t c = block * kBlock; c < std::min(m, block * kBlock + kBlock); ++c) {
          const double radius = carving_radius(points, dt.cells[c]);
          uint8_t b = 0;
          for (double step : kRatioSteps) b += radius > step * alpha;
          bucket[c] = b;
          p.kept[c] = radius <= alpha;
        }
      },
      2);
  // The context from alpha's verdicts: the whole of 4.0's, the start of 6.0's.
  const bool half_octaves = contexts != CarvingContexts::kAlphaNeighbours;
  p.context.resize(m);
  parallel_for(
      blocks,
      [&](size_t block) {
        for (size_t c = block * kBlock; c < std::min(m, block * kBlock + kBlock); ++c) {
          int kept_neighbors = 0;
          for (int32_t n : dt.neighbors[c])
            kept_neighbors +=
                n >= 0 && p.kept[static_cast<size_t>(n)] &&
                (chunk_of_cell.empty() || chunk_of_cell[static_cast<size_t>(n)] == chunk_of_cell[c]);
          p.context[c] =
              static_cast<uint8_t>((half_octaves ? bucket[c] / 2 : bucket[c]) * 5 + kept_neighbors);
        }
      },
      2);
  p.order = canonical_cell_order(dt.cells);  // the identity for an exported triangulation
  if (contexts == CarvingContexts::kExactMargin || contexts == CarvingContexts::kExactMarginShape ||
      contexts == CarvingContexts::kExactMarginShapeFlip) {
    const bool shape = contexts != CarvingContexts::kExactMargin;
    const bool flip = contexts == CarvingContexts::kExactMarginShapeFlip;
    p.margin.resize(m);
    // A cell's neighbours lie anywhere in the arrays: their corners are
    // asked for some cells ahead, as this pass otherwise waits on memory
    // most of its time (bunny_1m's level 0 on 2 cores: 1.0 s, 0.5-0.6 s so).
    constexpr size_t kAhead = 16;
    parallel_for(
        blocks,
        [&](size_t block) {
          const size_t end = std::min(m, block * kBlock + kBlock);
          for (size_t c = block * kBlock; c < end; ++c) {
            if (c + kAhead < end)
              for (int32_t n : dt.neighbors[c + kAhead])
                if (n >= 0) __builtin_prefetch(&dt.cells[static_cast<size_t>(n)]);
            if (c + kAhead / 2 < end)
              for (int32_t n : dt.neighbors[c + kAhead / 2])
                if (n >= 0)
                  for (uint32_t q : dt.cells[static_cast<size_t>(n)]) __builtin_prefetch(&points[q]);
            p.margin[c] = margin_bucket(dt, points, c);
            if (shape) {
              const auto& v = dt.cells[c];
              p.margin[c] = static_cast<uint8_t>(
                  p.margin[c] * kShapeBuckets +
                  shape_bucket({points[v[0]], points[v[1]], points[v[2]], points[v[3]]}));
            }
            if (flip)
              p.margin[c] = static_cast<uint8_t>(p.margin[c] * kFlipBuckets + flip_bucket(dt, points, c));
          }
        },
        2);
  }
  return p;
}

uint8_t shape_bucket(const std::array<GridPoint, 4>& c) {
  // With D = 6V and S the sum of the squared edge lengths (l^2 = S / 6),
  // quality > t exactly when 432 D^2 > t^2 S^3: t = 0.05 and 0.2 give the
  // integer factors 172800 and 10800. D^2 S^3 reach 2^165: decided in
  // doubles where they are clearly apart (their relative error is below
  // 1e-15), in 256-bit integers otherwise.
  using boost::multiprecision::int256_t;
  const Int128 d = abs_six_volume(c[0], c[1], c[2], c[3]);
  int64_t s = 0;
  for (size_t i = 0; i < 4; ++i)
    for (size_t j = i + 1; j < 4; ++j) {
      const int64_t x = int64_t{c[i].x} - c[j].x, y = int64_t{c[i].y} - c[j].y, z = int64_t{c[i].z} - c[j].z;
      s += x * x + y * y + z * z;
    }
  const double dd = static_cast<double>(d) * static_cast<double>(d);
  const double s3 = static_cast<double>(s) * static_cast<double>(s) * static_cast<double>(s);
  const auto above = [&](int64_t factor) {
    const double lhs = static_cast<double>(factor) * dd;
    if (lhs > s3 * (1 + 1e-9)) return true;
    if (lhs < s3 * (1 - 1e-9)) return false;
    const int256_t big_d = static_cast<int256_t>(static_cast<int64_t>(d >> 64)) * (int256_t{1} << 64) +
                           static_cast<int256_t>(static_cast<uint64_t>(d));
    const int256_t big_s = s;
    return int256_t{factor} * big_d * big_d > big_s * big_s * big_s;
  };
  static_assert(kShapeSteps[0] == 0.05 && kShapeSteps[1] == 0.2, "the factors below are theirs");
  return static_cast<uint8_t>(above(172800) + above(10800));
}

double squared_quality(const GridPoint& a, const GridPoint& b, const GridPoint& c, const GridPoint& d) {
  const std::array<GridPoint, 4> t = {a, b, c, d};
  int64_t s = 0;
  for (size_t i = 0; i < 4; ++i)
    for (size_t j = i + 1; j < 4; ++j) {
      const int64_t x = int64_t{t[i].x} - t[j].x, y = int64_t{t[i].y} - t[j].y, z = int64_t{t[i].z} - t[j].z;
      s += x * x + y * y + z * z;
    }
  const auto dd = static_cast<double>(abs_six_volume(a, b, c, d));
  const auto ss = static_cast<double>(s);
  return ss == 0 ? 0 : (dd * dd) / (ss * ss * ss);
}

uint8_t valid_flips(const TetMesh& dt, std::span<const GridPoint> points, size_t cell,
                    std::array<uint32_t, 4>& far) {
  // Across the faces opposite corners x and y, the neighbours (p, q, y, z)
  // and (p, q, x, z') close the ring around the edge (p, q) when z = z':
  // the edge then has these three cells only.
  const std::array<uint32_t, 4>& c = dt.cells[cell];
  far.fill(UINT32_MAX);
  for (size_t k = 0; k < 4; ++k) {
    const int32_t n = dt.neighbors[cell][k];
    if (n < 0) continue;
    for (uint32_t v : dt.cells[static_cast<size_t>(n)])
      if (std::find(c.begin(), c.end(), v) == c.end()) far[k] = v;
  }
  uint8_t bits = 0;
  for (size_t j = 0; j < kCornerPairs.size(); ++j) {
    const auto [kx, ky] = kCornerPairs[j];
    if (far[kx] == UINT32_MAX || far[kx] != far[ky]) continue;
    std::array<uint32_t, 2> edge{};
    for (size_t k = 0, e = 0; k < 4; ++k)
      if (k != kx && k != ky) edge[e++] = c[k];
    const GridPoint &x = points[c[kx]], &y = points[c[ky]], &z = points[far[kx]];
    const int op = orientation(x, y, z, points[edge[0]]), oq = orientation(x, y, z, points[edge[1]]);
    if (op != 0 && oq != 0 && (op > 0) != (oq > 0)) bits |= static_cast<uint8_t>(1 << j);
  }
  return bits;
}

uint8_t flip_bucket(const TetMesh& dt, std::span<const GridPoint> points, size_t cell) {
  std::array<uint32_t, 4> far{};
  const uint8_t valid = valid_flips(dt, points, cell, far);
  const std::array<uint32_t, 4>& c = dt.cells[cell];
  for (size_t j = 0; j < kCornerPairs.size(); ++j) {
    if (!(valid >> j & 1)) continue;
    const auto [kx, ky] = kCornerPairs[j];
    std::array<uint32_t, 2> edge{};
    for (size_t k = 0, e = 0; k < 4; ++k)
      if (k != kx && k != ky) edge[e++] = c[k];
    const GridPoint &p = points[edge[0]], &q = points[edge[1]];
    const GridPoint &x = points[c[kx]], &y = points[c[ky]], &z = points[far[kx]];
    const double before =
        std::min({squared_quality(p, q, x, y), squared_quality(p, q, y, z), squared_quality(p, q, x, z)});
    const double after = std::min(squared_quality(x, y, z, p), squared_quality(x, y, z, q));
    if (after > before) return 1;
  }
  return 0;
}

uint8_t margin_bucket(const TetMesh& dt, std::span<const GridPoint> points, size_t cell) {
  // The corners ascending (the encoder's and the decoder's triangulations
  // list them in any order), the centre relative to the first: centre - a
  // = num / (2 det), so |p - centre|^2 / R^2 - 1 = |2 det (p - a) - num|^2 /
  // |num|^2 - 1, one formula in doubles on both sides.
  std::array<GridPoint, 4> c;
  for (int k = 0; k < 4; ++k) c[static_cast<size_t>(k)] = points[dt.cells[cell][static_cast<size_t>(k)]];
  std::sort(c.begin(), c.end());
  const Vec3 a = to_vec(c[0]), u = to_vec(c[1]) - a, v = to_vec(c[2]) - a, w = to_vec(c[3]) - a;
  const double det2 = 2 * dot(u, cross(v, w));
  const Vec3 num = cross(v, w) * dot(u, u) + cross(w, u) * dot(v, v) + cross(u, v) * dot(w, w);
  const double r2 = dot(num, num);
  if (det2 == 0 || r2 == 0) return 0;
  double least = std::numeric_limits<double>::infinity();
  for (int k = 0; k < 4; ++k) {
    const int32_t n = dt.neighbors[cell][static_cast<size_t>(k)];
    if (n < 0) continue;
    for (uint32_t q : dt.cells[static_cast<size_t>(n)]) {
      if (std::find(dt.cells[cell].begin(), dt.cells[cell].end(), q) != dt.cells[cell].end()) continue;
      const Vec3 d = (to_vec(points[q]) - a) * det2 - num;
      least = std::min(least, dot(d, d) / r2 - 1);
    }
  }
  uint8_t b = 0;
  for (double step : kMarginSteps) b += least > step;
  return b;
}

}  // namespace dtm
