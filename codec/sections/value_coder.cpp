#include "codec/sections/value_coder.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <utility>

#include "bitstream/range_coder.h"
#include "codec/sections/value_coder_shared.h"
#include "common/parallel_for.h"

namespace dtm {

namespace {

// The 26 cells around a cell: the 6 sharing a face, the 12 sharing an edge,
// the 8 sharing a corner.
constexpr std::array<std::array<int8_t, 3>, 26> kFirstRing = [] {
  std::array<std::array<int8_t, 3>, 26> out{};
  size_t n = 0;
  for (int nonzero = 1; nonzero <= 3; ++nonzero)
    for (int z = -1; z <= 1; ++z)
      for (int y = -1; y <= 1; ++y)
        for (int x = -1; x <= 1; ++x)
          if ((x != 0) + (y != 0) + (z != 0) == nonzero)
            out[n++] = {static_cast<int8_t>(x), static_cast<int8_t>(y), static_cast<int8_t>(z)};
  return out;
}();

// a / b for a >= 0, b > 0, in 64 bits when both fit (Int128 division is a
// library call, and a prediction makes two).
Int128 floor_ratio(Int128 a, Int128 b) {
  constexpr Int128 kFits = Int128{1} << 62;
  if (a < kFits && b < kFits) return static_cast<int64_t>(a) / static_cast<int64_t>(b);
  return a / b;
}

int spread_context(Int128 lowest, Int128 highest) {
  const int width = bit_width128(static_cast<UInt128>(highest - lowest));
  return std::min(kValueSpreadContexts - 1, (width + 1) / 2);
}

}  // namespace

ValuePredictor::ValuePredictor() : models_(std::make_unique<Models>()) {}
ValuePredictor::~ValuePredictor() = default;
ValuePredictor::ValuePredictor(ValuePredictor&&) noexcept = default;
ValuePredictor& ValuePredictor::operator=(ValuePredictor&&) noexcept = default;

std::array<int64_t, 3> NeighbourSearch::cell_of(const GridPoint& p) const {
  return {(p.x - origin_[0]) / cell_, (p.y - origin_[1]) / cell_, (p.z - origin_[2]) / cell_};
}

std::vector<Neighbours> NeighbourSearch::layer(std::span<const GridPoint> points) {
  prepare(points);
  // Every point of the layer is in the grid first, named by its place in
  // the coding order; each one's search then skips those named after it, so
  // the searches are independent (and run on every core) and find what a
  // search made as the points came would.
  const auto first = static_cast<uint32_t>(points_.size());
  for (const GridPoint& p : points) add(p);
  std::vector<Neighbours> out(points.size());
  // A run of points at a time, each on the threads the work holds then:
  // the encoder codes the values beside the cells' sections, on its share
  // of the threads, and when the cells are done their threads come to the
  // next run (common/threads.h). In one call, bunny_1m's finest layer kept
  // the one thread it started with, 0.4 s alone on 2 cores.
  constexpr size_t kBlock = 1024, kRun = 64 * kBlock;
  for (size_t run = 0; run < points.size(); run += kRun) {
    const size_t end = std::min(points.size(), run + kRun);
    parallel_for((end - run + kBlock - 1) / kBlock,
                 [&](size_t block) {
                   const size_t from = run + block * kBlock;
                   for (size_t i = from; i < std::min(end, from + kBlock); ++i)
                     out[i] = nearest(points[i], first + static_cast<uint32_t>(i));
                 },
                 2);
  }
  return out;
}

void NeighbourSearch::know(std::span<const GridPoint> points) {
  prepare(points);
  for (const GridPoint& p : points) add(p);
}

void NeighbourSearch::prepare(std::span<const GridPoint> incoming) {
  if (points_.empty() && incoming.empty()) return;
  const GridPoint first = points_.empty() ? incoming[0] : points_[0];
  std::array<int64_t, 3> lo = {first.x, first.y, first.z}, hi = lo;
  auto grow = [&](const GridPoint& p) {
    const std::array<int64_t, 3> c = {p.x, p.y, p.z};
    for (int a = 0; a < 3; ++a) lo[a] = std::min(lo[a], c[a]), hi[a] = std::max(hi[a], c[a]);
  };
  for (const GridPoint& p : points_) grow(p);
  for (const GridPoint& p : incoming) grow(p);
  // About kPointsPerCell points per cell once the layer is in, so that the
  // 8 nearest usually lie within one ring of cells. The grid only speeds the
  // search up: the neighbours it finds are the exact nearest, whatever its size.
  constexpr int64_t kPointsPerCell = 2;
  const int64_t extent = std::max({hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]}) + 1;
  const auto total = static_cast<int64_t>(points_.size() + incoming.size());
  int64_t per_side = 1;
  while ((per_side + 1) * (per_side + 1) * (per_side + 1) * kPointsPerCell <= total) ++per_side;
  origin_ = lo;
  cell_ = std::max<int64_t>(1, (extent + per_side - 1) / per_side);
  for (int a = 0; a < 3; ++a) dims_[a] = (hi[a] - lo[a]) / cell_ + 1;
  const auto cells = static_cast<size_t>(dims_[0] * dims_[1] * dims_[2]);
  // Counting sort of the known points by cell.
  cell_start_.assign(cells + 1, 0);
  std::vector<uint32_t> cell_of_point(points_.size());
  for (uint32_t i = 0; i < points_.size(); ++i)
    ++cell_start_[(cell_of_point[i] = bucket(cell_of(points_[i]))) + 1];
  for (size_t b = 0; b < cells; ++b) cell_start_[b + 1] += cell_start_[b];
  settled_.resize(points_.size());
  std::vector<uint32_t> fill(cell_start_.begin(), cell_start_.end() - 1);
  for (uint32_t i = 0; i < points_.size(); ++i) settled_[fill[cell_of_point[i]]++] = {points_[i], i};
  recent_.assign(cells, {});
}

void NeighbourSearch::add(const GridPoint& p) {
  recent_[bucket(cell_of(p))].push_back({p, static_cast<uint32_t>(points_.size())});
  points_.push_back(p);
}

Neighbours NeighbourSearch::nearest(const GridPoint& p, uint32_t known) const {
  if (known == 0) return {};
  // The kValueNeighbours nearest known points, ties to the earlier coded:
  // rings of cells around p's, until no farther ring can hold a nearer one.
  struct Near {
    int64_t d2;
    uint32_t index;
    bool operator<(const Near& o) const { return d2 != o.d2 ? d2 < o.d2 : index < o.index; }
  };
  // best[0..found) in ascending order; `worst` is the farthest kept once
  // there are kValueNeighbours of them (until then, anything is taken).
  std::array<Near, kValueNeighbours> best;
  int found = 0;
  int64_t worst = INT64_MAX;
  auto consider = [&](const Entry& e) {
    if (e.index >= known) return;  // coded after p
    const int64_t dx = e.p.x - p.x, dy = e.p.y - p.y, dz = e.p.z - p.z;
    const Near n{dx * dx + dy * dy + dz * dz, e.index};
    if (n.d2 > worst) return;  // most points, once the first ring is in
    int k = 0;
    if (found < kValueNeighbours)
      k = found++;
    else if (n < best[kValueNeighbours - 1])
      k = kValueNeighbours - 1;
    else
      return;
    while (k > 0 && n < best[k - 1]) {
      best[k] = best[k - 1];
      --k;
    }
    best[k] = n;
    if (found == kValueNeighbours) worst = best[kValueNeighbours - 1].d2;
  };
  const std::array<int64_t, 3> c = cell_of(p);
  const std::array<int64_t, 3> q = {p.x, p.y, p.z};
  // How far p is, along axis a, from the points of cell k on that axis (its
  // grid coordinates run from origin + k cell_ to origin + (k + 1) cell_ - 1).
  auto gap = [&](int a, int64_t k) -> int64_t {
    if (k < c[a]) return q[a] - (origin_[a] + (k + 1) * cell_ - 1);
    if (k > c[a]) return origin_[a] + k * cell_ - q[a];
    return 0;
  };
  // A cell wholly farther than the 8th nearest found cannot change them
  // (one exactly as far could, by the tie rule: not skipped).
  auto visit = [&](int64_t x, int64_t y, int64_t z) {
    if (x < 0 || x >= dims_[0] || y < 0 || y >= dims_[1] || z < 0 || z >= dims_[2]) return;
    const int64_t gx = gap(0, x), gy = gap(1, y), gz = gap(2, z);
    if (gx * gx + gy * gy + gz * gz > worst) return;
    const size_t b = bucket({x, y, z});
    for (const Entry* e = settled_.data() + cell_start_[b]; e != settled_.data() + cell_start_[b + 1]; ++e)
      consider(*e);
    for (const Entry& e : recent_[b]) consider(e);
  };
  const int64_t rings = std::max({dims_[0], dims_[1], dims_[2]});
  for (int64_t r = 0; r <= rings; ++r) {
    if (r <= 1) {
      // p's cell and its 26 neighbours, nearest kinds first (faces, edges,
      // corners), so that the 8 nearest fill early and most points are
      // turned away at the first comparison.
      if (r == 1)
        for (const auto& o : kFirstRing) visit(c[0] + o[0], c[1] + o[1], c[2] + o[2]);
      else
        visit(c[0], c[1], c[2]);
    } else {
      for (int64_t z = c[2] - r; z <= c[2] + r; ++z)
        for (int64_t y = c[1] - r; y <= c[1] + r; ++y) {
          const bool y_or_z_on_ring = std::abs(z - c[2]) == r || std::abs(y - c[1]) == r;
          for (int64_t x = c[0] - r; x <= c[0] + r; x += y_or_z_on_ring ? 1 : 2 * r) visit(x, y, z);
        }
    }
    if (found < kValueNeighbours) continue;
    // Every point outside the cells searched is at least `outside` from p
    // along some axis (strict below: one exactly that far could win a tie).
    int64_t outside = INT64_MAX;
    for (int a = 0; a < 3; ++a) {
      if (c[a] - r - 1 >= 0) outside = std::min(outside, gap(a, c[a] - r - 1));
      if (c[a] + r + 1 < dims_[a]) outside = std::min(outside, gap(a, c[a] + r + 1));
    }
    if (outside == INT64_MAX || worst < outside * outside) break;
  }
  Neighbours out;
  out.count = found;
  for (int k = 0; k < found; ++k) out.index[k] = best[k].index, out.d2[k] = best[k].d2;
  return out;
}

void ValuePredictor::add(Int128 value) {
  values_.push_back(value);
  sum_ += value;
}

ValuePredictor::Prediction ValuePredictor::predict(const Neighbours& n) const {
  if (n.count == 0) return {};
  // Weights d_1^2 / d_i^2 in 16-bit fixed point (the nearest weighs 2^16),
  // exact integers, so that every decoder predicts the same value.
  // Every quantity is non-negative, so truncating division is floor; the
  // 64-bit paths give the same integers as the 128-bit ones, only faster.
  const int64_t nearest = std::max<int64_t>(1, n.d2[0]);
  Int128 num = 0, den = 0;
  Int128 lowest = values_[n.index[0]], highest = lowest;
  for (int k = 0; k < n.count; ++k) {
    const Int128 v = values_[n.index[k]];
    const int64_t d2 = std::max<int64_t>(1, n.d2[k]);
    const int64_t w = nearest < (int64_t{1} << 46) ? (nearest << 16) / d2
                                                   : static_cast<int64_t>((Int128{nearest} << 16) / d2);
    num += w * v;
    den += w;
    lowest = std::min(lowest, v), highest = std::max(highest, v);
  }
  const auto count = static_cast<Int128>(values_.size());
  return {floor_ratio(2 * num + den, 2 * den), floor_ratio(2 * sum_ + count, 2 * count),
          spread_context(lowest, highest)};
}

Int128 to_ordered(uint64_t bits, ValueType type) {
  switch (type) {
    case ValueType::kI8:
      return static_cast<int8_t>(bits);
    case ValueType::kU8:
      return static_cast<uint8_t>(bits);
    case ValueType::kI16:
      return static_cast<int16_t>(bits);
    case ValueType::kU16:
      return static_cast<uint16_t>(bits);
    case ValueType::kI32:
      return static_cast<int32_t>(bits);
    case ValueType::kU32:
      return static_cast<uint32_t>(bits);
    case ValueType::kI64:
      return static_cast<int64_t>(bits);
    case ValueType::kU64:
      return static_cast<Int128>(bits);
    case ValueType::kF32: {
      // fpzip's map: negative floats reversed under the positive ones, so
      // that the integers order as the floats do (NaNs beyond infinities).
      const auto b = static_cast<uint32_t>(bits);
      const uint32_t u = (b >> 31) ? ~b : (b | 0x80000000u);
      return static_cast<Int128>(u) - (Int128{1} << 31);
    }
    case ValueType::kF64: {
      const uint64_t u = (bits >> 63) ? ~bits : (bits | (uint64_t{1} << 63));
      return static_cast<Int128>(u) - (Int128{1} << 63);
    }
  }
  return 0;
}

uint64_t from_ordered(Int128 ordered, ValueType type) {
  switch (type) {
    case ValueType::kI8:
    case ValueType::kI16:
    case ValueType::kI32:
    case ValueType::kI64:
      return static_cast<uint64_t>(static_cast<int64_t>(ordered));
    case ValueType::kU8:
    case ValueType::kU16:
    case ValueType::kU32:
    case ValueType::kU64:
      return static_cast<uint64_t>(ordered);
    case ValueType::kF32: {
      const auto u = static_cast<uint32_t>(static_cast<uint64_t>(ordered + (Int128{1} << 31)));
      return (u >> 31) ? (u & 0x7fffffffu) : ~u;
    }
    case ValueType::kF64: {
      const auto u = static_cast<uint64_t>(ordered + (Int128{1} << 63));
      return (u >> 63) ? (u & ~(uint64_t{1} << 63)) : ~u;
    }
  }
  return 0;
}

double dequantize(Int128 q, const LossyScale& scale, bool float32) {
  const double v = scale.origin + static_cast<double>(q) * scale.step;
  return float32 ? static_cast<double>(static_cast<float>(v)) : v;
}

}  // namespace dtm
