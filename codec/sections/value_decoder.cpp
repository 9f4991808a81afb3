// Values read (spec/FORMAT.md §3.3): the decoder's side of value_coder.h.
#include <algorithm>
#include <vector>

#include "codec/sections/value_coder.h"
#include "codec/sections/value_coder_shared.h"

namespace dtm {
namespace {

Status decode_residual(RangeDecoder& dec, ValuePredictor::Models& m, int ctx, Int128& r) {
  r = 0;
  if (!dec.decode(m.nonzero[ctx])) return Status::Ok();
  const bool negative = dec.decode(m.negative[ctx]);
  int cls = 1;
  while (cls < kMaxClass && dec.decode(m.more[ctx][std::min(cls, kValueClassModels) - 1])) ++cls;
  const int below = cls - 1;
  const int modelled = std::min(2, below);
  UInt128 mag = 1;
  int node = 1;
  for (int i = 0; i < modelled; ++i) {
    const bool bit = dec.decode(m.mantissa[std::min(cls, kValueClassModels) - 1][node]);
    mag = mag << 1 | static_cast<UInt128>(bit);
    node = 2 * node + bit;
  }
  int raw = below - modelled;
  while (raw > 0) {
    const int n = std::min(raw, 32);
    raw -= n;
    mag = mag << n | static_cast<UInt128>(dec.decode_raw(n));
  }
  r = negative ? -static_cast<Int128>(mag) : static_cast<Int128>(mag);
  return Status::Ok();
}

}  // namespace

void ValueDecoder::know(std::span<const Int128> ordered) {
  for (const Int128 v : ordered) predictor_.add((v - scale_.offset) / scale_.step);
}

Status ValueDecoder::decode_layer(std::span<const uint8_t> block, std::span<const Neighbours> neighbours,
                                  std::vector<Int128>& ordered) {
  RangeDecoder dec(block);
  ordered.clear();
  ordered.reserve(neighbours.size());
  const uint64_t mode = dec.decode_raw(2);
  if (mode >= kValueModes) return {StatusCode::kCorrupt, "a value section names an unknown prediction mode"};
  for (const Neighbours& n : neighbours) {
    const ValuePredictor::Prediction pred = predictor_.predict(n);
    Int128 r = 0;
    DTM_RETURN_IF_ERROR(decode_residual(dec, predictor_.models(), pred.context, r));
    const Int128 v = pred.value(static_cast<ValueMode>(mode)) + r;
    if (v < 0 || v >= (Int128{1} << kMaxClass) || v > max_scaled_ || dec.overran())
      return {StatusCode::kCorrupt, "a value section decodes out of range"};
    predictor_.add(v);
    ordered.push_back(scale_.offset + v * scale_.step);
  }
  if (!dec.finished_cleanly())
    return {StatusCode::kCorrupt, "a value section has bytes left over or ends early"};
  return Status::Ok();
}

}  // namespace dtm
