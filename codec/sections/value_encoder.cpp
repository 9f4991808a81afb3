// Values written (spec/FORMAT.md §3.3): the encoder's side of
// value_coder.h, and the scales a field's values are sent with.
#include <algorithm>
#include <cmath>
#include <string>
#include <utility>
#include <vector>

#include "codec/sections/value_coder.h"
#include "codec/sections/value_coder_shared.h"

namespace dtm {
namespace {

void encode_residual(RangeEncoder& enc, ValuePredictor::Models& m, int ctx, Int128 r) {
  enc.encode(m.nonzero[ctx], r != 0);
  if (r == 0) return;
  enc.encode(m.negative[ctx], r < 0);
  const UInt128 mag = r < 0 ? static_cast<UInt128>(-r) : static_cast<UInt128>(r);
  const int cls = bit_width128(mag);
  for (int j = 1; j < cls; ++j) enc.encode(m.more[ctx][std::min(j, kValueClassModels) - 1], true);
  if (cls < kMaxClass) enc.encode(m.more[ctx][std::min(cls, kValueClassModels) - 1], false);
  const int below = cls - 1;  // bits under the leading one
  const int modelled = std::min(2, below);
  int node = 1;
  for (int i = 0; i < modelled; ++i) {
    const bool bit = (mag >> (below - 1 - i)) & 1;
    enc.encode(m.mantissa[std::min(cls, kValueClassModels) - 1][node], bit);
    node = 2 * node + bit;
  }
  int raw = below - modelled;
  while (raw > 0) {
    const int n = std::min(raw, 32);
    raw -= n;
    enc.encode_raw(static_cast<uint64_t>(mag >> raw) & ((uint64_t{1} << n) - 1), n);
  }
}

}  // namespace

StatusOr<std::vector<Int128>> quantize_within(std::span<const double> values, double error, bool float32,
                                              LossyScale& scale) {
  if (!(error > 0) || !std::isfinite(error))
    return invalid_input("the error bound must be a positive number");
  double lo = 0, largest = 0;
  for (size_t i = 0; i < values.size(); ++i) {
    if (!std::isfinite(values[i]))
      return invalid_input("vertex " + std::to_string(i) + " holds " +
                           (std::isnan(values[i]) ? "NaN" : "an infinity") +
                           ", which a lossy field cannot keep");
    lo = i == 0 ? values[i] : std::min(lo, values[i]);
    largest = std::max(largest, std::abs(values[i]));
  }
  // The step leaves room for the rounding of origin + q * step and of its
  // conversion to the field's type: two units in the last place of the
  // largest magnitude.
  const double ulp = float32
                         ? std::nextafter(static_cast<float>(largest), INFINITY) - static_cast<float>(largest)
                         : std::nextafter(largest, INFINITY) - largest;
  scale = {lo, 2 * error - 4 * ulp};
  if (!(scale.step > 0)) return invalid_input("the error bound is smaller than the values' precision");
  std::vector<Int128> out;
  out.reserve(values.size());
  for (size_t i = 0; i < values.size(); ++i) {
    const double exact = (values[i] - lo) / scale.step;
    if (exact > 1e18) return invalid_input("the error bound is too small for the values' range");
    const auto q = static_cast<Int128>(std::llround(exact));
    Int128 chosen = -1;
    for (const Int128 candidate : {q, q - 1, q + 1})
      if (candidate >= 0 && std::abs(dequantize(candidate, scale, float32) - values[i]) <= error) {
        chosen = candidate;
        break;
      }
    if (chosen < 0)
      return invalid_input("vertex " + std::to_string(i) + ": no value within the error bound " +
                           std::to_string(error) + " of " + std::to_string(values[i]) + " at this precision");
    out.push_back(chosen);
  }
  return out;
}

ValueScale value_scale(std::span<const Int128> ordered) {
  ValueScale s;
  if (ordered.empty()) return s;
  s.offset = *std::min_element(ordered.begin(), ordered.end());
  UInt128 g = 0;
  for (const Int128 v : ordered) {
    UInt128 a = static_cast<UInt128>(v - s.offset), b = g;
    while (b != 0) a = std::exchange(b, a % b);  // gcd(v - offset, g)
    g = a;
  }
  s.step = g == 0 ? 1 : static_cast<Int128>(g);
  return s;
}

std::vector<uint8_t> ValueEncoder::encode_layer(std::span<const Neighbours> neighbours,
                                                std::span<const Int128> ordered) {
  // The predictions do not depend on the mode (every earlier value is
  // known exactly): make them once, then code the layer in each mode with a
  // copy of the models, and keep the smallest.
  std::vector<ValuePredictor::Prediction> predictions;
  std::vector<Int128> values;
  for (size_t i = 0; i < neighbours.size(); ++i) {
    values.push_back((ordered[i] - scale_.offset) / scale_.step);
    predictions.push_back(predictor_.predict(neighbours[i]));
    predictor_.add(values.back());
  }
  auto code = [&](ValueMode mode, ValuePredictor::Models& models) {
    RangeEncoder enc;
    enc.encode_raw(static_cast<uint64_t>(mode), 2);
    for (size_t i = 0; i < values.size(); ++i)
      encode_residual(enc, models, predictions[i].context, values[i] - predictions[i].value(mode));
    return enc.finish();
  };
  ValueMode best = ValueMode::kNeighbours;
  size_t best_size = SIZE_MAX;
  for (int m = 0; m < kValueModes; ++m) {
    ValuePredictor::Models trial = predictor_.models();
    const size_t size = code(static_cast<ValueMode>(m), trial).size();
    if (size < best_size) best_size = size, best = static_cast<ValueMode>(m);
  }
  return code(best, predictor_.models());
}

void ValueEncoder::know(std::span<const Int128> ordered) {
  for (const Int128 v : ordered) predictor_.add((v - scale_.offset) / scale_.step);
}

}  // namespace dtm
