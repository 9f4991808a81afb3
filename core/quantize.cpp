#include "core/quantize.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <string>

#include "common/parallel_sort.h"

namespace dtm {

double largest_extent(std::span<const InputPoint> points) {
  if (points.empty()) return 0;
  InputPoint lo = points[0], hi = points[0];
  for (const InputPoint& p : points) {
    lo = {std::min(lo.x, p.x), std::min(lo.y, p.y), std::min(lo.z, p.z)};
    hi = {std::max(hi.x, p.x), std::max(hi.y, p.y), std::max(hi.z, p.z)};
  }
  return std::max({hi.x - lo.x, hi.y - lo.y, hi.z - lo.z});
}

StatusOr<QuantizedPoints> quantize(std::span<const InputPoint> input, int qbits) {
  return quantize(input, qbits, 1.0);
}

StatusOr<QuantizedPoints> quantize(std::span<const InputPoint> input, int qbits, double scale) {
  if (qbits < kMinQBits || qbits > kMaxQBits)
    return invalid_input("qbits must be in [1, 24], got " + std::to_string(qbits));
  if (input.empty()) return invalid_input("no points to quantize");

  std::array<double, 3> lo{INFINITY, INFINITY, INFINITY}, hi{-INFINITY, -INFINITY, -INFINITY};
  for (size_t i = 0; i < input.size(); ++i) {
    const double c[3] = {input[i].x * scale, input[i].y * scale, input[i].z * scale};
    for (int a = 0; a < 3; ++a) {
      if (!std::isfinite(c[a]))
        return invalid_input("point " + std::to_string(i) + " has a non-finite coordinate");
      lo[a] = std::min(lo[a], c[a]);
      hi[a] = std::max(hi[a], c[a]);
    }
  }
  const double extent = std::max({hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]});
  if (!std::isfinite(extent))
    return invalid_input("the points' bounding box is wider than a double can hold");
  const int32_t max_cell = static_cast<int32_t>((uint32_t{1} << qbits) - 1);

  QuantizedPoints out;
  out.grid.qbits = qbits;
  out.grid.origin = lo;
  out.grid.step = extent > 0 ? extent / max_cell : 1.0;

  std::vector<GridPoint> cells(input.size());
  const double inv = 1.0 / out.grid.step;
  for (size_t i = 0; i < input.size(); ++i) {
    auto q = [&](double v, int a) {
      const double t = std::floor((v - lo[a]) * inv + 0.5);
      return static_cast<int32_t>(std::clamp(t, 0.0, static_cast<double>(max_cell)));
    };
    cells[i] = {q(input[i].x * scale, 0), q(input[i].y * scale, 1), q(input[i].z * scale, 2)};
  }

  // The cells sorted (a total order, ties by index: the same on any
  // number of threads), then moved into that order in place and merged
  // where equal: the points are the cells' own memory, not a second array
  // of them (a 10M-point input held both, 113 MiB more, on every MPI rank).
  std::vector<uint32_t> order(input.size());
  std::iota(order.begin(), order.end(), 0u);
  parallel_sort(order.begin(), order.end(),
                [&](uint32_t a, uint32_t b) { return cells[a] != cells[b] ? cells[a] < cells[b] : a < b; });
  out.input_to_point.resize(input.size());
  for (size_t i = 0; i < order.size(); ++i) out.input_to_point[order[i]] = static_cast<uint32_t>(i);
  // cells[i] becomes cells[order[i]], cycle by cycle; `order` marks what is done.
  constexpr uint32_t kDone = UINT32_MAX;
  for (size_t i = 0; i < order.size(); ++i) {
    if (order[i] == kDone) continue;
    const GridPoint first = cells[i];
    for (size_t j = i;;) {
      const size_t k = order[j];
      order[j] = kDone;
      if (k == i) {
        cells[j] = first;
        break;
      }
      cells[j] = cells[k];
      j = k;
    }
  }
  // Equal cells merged; `order` then says each sorted place's point.
  size_t distinct = 0;
  for (size_t i = 0; i < cells.size(); ++i) {
    if (distinct == 0 || cells[i] != cells[distinct - 1])
      cells[distinct++] = cells[i];
    else
      ++out.duplicates_merged;
    order[i] = static_cast<uint32_t>(distinct - 1);
  }
  for (uint32_t& p : out.input_to_point) p = order[p];
  std::vector<uint32_t>().swap(order);
  cells.resize(distinct);
  if (distinct < input.size()) cells.shrink_to_fit();
  out.points = std::move(cells);
  return out;
}

}  // namespace dtm
