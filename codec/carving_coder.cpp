#include "codec/carving_coder.h"

#include <algorithm>
#include <array>

#include "bitstream/range_coder.h"
#include "common/parallel_for.h"
#include "mesh/carving.h"
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
  p.order = canonical_cell_order(dt.cells);  // the identity for an exported triangulation
  return p;
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
                      double alpha, std::vector<uint8_t>& kept, std::vector<uint32_t>* order) {
  CarvingPrediction p = predict_carving(dt, points, alpha);
  kept = std::move(p.kept);
  if (order) *order = p.order;
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
