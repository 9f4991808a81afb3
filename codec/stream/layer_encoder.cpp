// The layer coder's encoder (spec/FORMAT.md §3.1); layer_decoder.cpp mirrors it.
#include <algorithm>

#include "codec/stream/layer_coder.h"
#include "codec/stream/layer_coder_shared.h"

namespace dtm {
namespace layer_coder {
namespace {

class Encoder {
 public:
  Encoder(std::span<const MortonCode> known, std::span<const MortonCode> fresh, int qbits,
          SetCoderModels::Tables& t)
      : known_(known), fresh_(fresh), qbits_(qbits), bits_(3 * qbits), t_(t) {}

  std::vector<uint8_t> run(PointSetNode start) {
    node(start.depth, start.base, 0, fresh_.size(), 0, known_.size());
    return rc_.finish();
  }

 private:
  // Node of depth `depth` starting at code `base`; fresh_[f0, f1) and
  // known_[k0, k1) lie in it; f1 > f0.
  void node(int depth, MortonCode base, size_t f0, size_t f1, size_t k0, size_t k1) {
    const uint64_t n = f1 - f0, k = k1 - k0;
    const int rest = bits_ - depth;
    if (rest == 0) {  // one cell, one new point (the input is distinct)
      t_.note(morton_decode(base, qbits_));
      return;
    }
    if (n == 1 && k == 0) {
      lone(depth, base, fresh_[f0]);
      return;
    }
    const MortonCode mid = base + (MortonCode{1} << (rest - 1));
    const size_t fm = split_index(fresh_, f0, f1, mid);
    const size_t km = split_index(known_, k0, k1, mid);
    const uint64_t n0 = fm - f0, kn0 = km - k0;
    if (n == 1) {
      rc_.encode(t_.single[known_class(kn0)][known_class(k - kn0)], n0 == 0);
    } else if (n <= kSmallMax) {
      auto& models = t_.small[n][split_context(kn0, k)];
      uint64_t lo = 0, hi = n;
      int heap = 1;
      while (lo < hi) {
        const uint64_t half = (lo + hi) / 2;
        const bool upper = n0 > half;
        rc_.encode(models[heap], upper);
        heap = 2 * heap + upper;
        if (upper)
          lo = half + 1;
        else
          hi = half;
      }
    } else {
      const uint64_t guess = predicted_first(n, kn0, k);
      const uint64_t u = zigzag(static_cast<int64_t>(n0) - static_cast<int64_t>(guess)) + 1;
      const int e = std::bit_width(u) - 1;
      auto& prefix = t_.large_prefix[std::bit_width(n)];
      for (int i = 0; i < e; ++i) rc_.encode(prefix[i], true);
      rc_.encode(prefix[e], false);
      rc_.encode_raw(u, e);  // the bits below the leading one
    }
    if (fm > f0) node(depth + 1, base, f0, fm, k0, km);
    if (f1 > fm) node(depth + 1, mid, fm, f1, km, k1);
  }

  void lone(int depth, MortonCode base, MortonCode code) {
    if (!t_.reuses_coordinates()) {
      const MortonCode offset = code - base;
      const int rest = bits_ - depth;
      if (rest > 64) rc_.encode_raw(static_cast<uint64_t>(offset >> 64), rest - 64);
      rc_.encode_raw(static_cast<uint64_t>(offset), std::min(rest, 64));
      return;
    }
    const GridPoint p = morton_decode(code, qbits_), lo = morton_decode(base, qbits_);
    for (int a = 0; a < 3; ++a) {
      const int r = remaining_bits(qbits_, depth, a);
      if (r == 0) continue;
      const uint64_t first = static_cast<uint64_t>(axis_of(lo, a)),
                     value = static_cast<uint64_t>(axis_of(p, a));
      const CoordinateSet& used = t_.used()[a];
      const uint64_t m = used.count_in(first, first + (uint64_t{1} << r));
      if (m == 0) {
        rc_.encode_raw(value - first, r);
        continue;
      }
      const bool reused = used.contains(static_cast<uint32_t>(value));
      // Every value of the interval used: the coordinate is one of them.
      if (m < (uint64_t{1} << r)) rc_.encode(t_.reuse[a][reuse_context(m, r)], reused);
      const uint64_t used_below = used.count_in(first, value);
      if (reused)
        rc_.encode_index(used_below, m);
      else
        rc_.encode_index(value - first - used_below, (uint64_t{1} << r) - m);
    }
    t_.note(p);
  }

  std::span<const MortonCode> known_, fresh_;
  int qbits_, bits_;
  SetCoderModels::Tables& t_;
  RangeEncoder rc_;
};

}  // namespace
}  // namespace layer_coder

std::vector<uint8_t> encode_point_set(std::span<const MortonCode> known, std::span<const GridPoint> points,
                                      int qbits, SetCoderModels& models, PointSetNode start) {
  if (points.empty()) return {};
  std::vector<MortonCode> fresh;
  fresh.reserve(points.size());
  for (const GridPoint& p : points) fresh.push_back(morton_encode(p, qbits));
  std::sort(fresh.begin(), fresh.end());
  return layer_coder::Encoder(known, fresh, qbits, models.tables()).run(start);
}

}  // namespace dtm
