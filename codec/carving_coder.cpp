#include "codec/carving_coder.h"

#include <algorithm>
#include <array>

#include "bitstream/range_coder.h"
#include "common/csr.h"
#include "common/parallel_for.h"
#include "mesh/carving.h"

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

using Models = std::array<AdaptiveBit, kCarvingContexts>;

}  // namespace

CarvingPrediction predict_carving(const TetMesh& dt, std::span<const GridPoint> points, double alpha) {
  const size_t m = dt.cells.size();
  CarvingPrediction p;
  p.kept.resize(m);
  p.context.resize(m);
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
  parallel_for(
      blocks,
      [&](size_t block) {
        for (size_t c = block * kBlock; c < std::min(m, block * kBlock + kBlock); ++c) {
          int kept_neighbors = 0;
          for (int32_t n : dt.neighbors[c]) kept_neighbors += n >= 0 && p.kept[static_cast<size_t>(n)];
          p.context[c] = static_cast<uint8_t>(bucket[c] * 5 + kept_neighbors);
        }
      },
      2);
  p.order = canonical_cell_order(dt.cells);
  return p;
}

std::vector<uint32_t> canonical_cell_order(std::span<const std::array<uint32_t, 4>> cells) {
  // Cells by their smallest vertex (a counting sort), then each vertex's
  // few cells by their other three: the order one comparison sort of the
  // sorted tuples gives, in linear time.
  const size_t m = cells.size();
  std::vector<std::array<uint32_t, 4>> sorted(m);
  parallel_for((m + 4095) / 4096,
               [&](size_t block) {
                 for (size_t k = block * 4096; k < std::min(m, block * 4096 + 4096); ++k) {
                   auto c = cells[k];
                   if (c[0] > c[1]) std::swap(c[0], c[1]);
                   if (c[2] > c[3]) std::swap(c[2], c[3]);
                   if (c[0] > c[2]) std::swap(c[0], c[2]);
                   if (c[1] > c[3]) std::swap(c[1], c[3]);
                   if (c[1] > c[2]) std::swap(c[1], c[2]);
                   sorted[k] = c;
                 }
               },
               2);
  uint32_t top = 0;
  for (const auto& c : sorted) top = std::max(top, c[3]);
  const Csr by_smallest = build_csr(m == 0 ? 0 : size_t{top} + 1, [&](auto&& emit) {
    for (uint32_t k = 0; k < m; ++k) emit(sorted[k][0], k);
  });
  std::vector<uint32_t> order = by_smallest.items;
  parallel_for((by_smallest.rows() + 4095) / 4096,
               [&](size_t block) {
                 for (size_t v = block * 4096; v < std::min(by_smallest.rows(), block * 4096 + 4096); ++v)
                   std::sort(order.begin() + by_smallest.offsets[v],
                             order.begin() + by_smallest.offsets[v + 1],
                             [&](uint32_t a, uint32_t b) { return sorted[a] < sorted[b]; });
               },
               2);
  return order;
}

std::vector<uint8_t> encode_carving(const TetMesh& dt, std::span<const GridPoint> points, double alpha,
                                    std::span<const uint8_t> kept) {
  const CarvingPrediction p = predict_carving(dt, points, alpha);
  bool any = false;
  for (size_t c = 0; c < kept.size() && !any; ++c) any = (kept[c] != 0) != (p.kept[c] != 0);
  if (!any) return {};
  Models models;
  RangeEncoder rc;
  for (uint32_t c : p.order) rc.encode(models[p.context[c]], (kept[c] != 0) != (p.kept[c] != 0));
  return rc.finish();
}

Status decode_carving(std::span<const uint8_t> section, const TetMesh& dt, std::span<const GridPoint> points,
                      double alpha, std::vector<uint8_t>& kept) {
  CarvingPrediction p = predict_carving(dt, points, alpha);
  kept = std::move(p.kept);
  if (section.empty()) return Status::Ok();
  Models models;
  RangeDecoder rc(section);
  for (uint32_t c : p.order) kept[c] ^= static_cast<uint8_t>(rc.decode(models[p.context[c]]));
  if (!rc.finished_cleanly())
    return {StatusCode::kCorrupt,
            rc.overran() ? "carving corrections end early" : "bytes after the carving corrections"};
  return Status::Ok();
}

}  // namespace dtm
