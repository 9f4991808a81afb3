#include "point_set_coder.h"

#include <algorithm>
#include <bit>

#include "bitstream/coordinate_set.h"
#include "bitstream/range_coder.h"

namespace dtm {

// Context layout (spec/FORMAT.md §3.1).
constexpr int kKnownClasses = 7;   // class(k): 0, 1, 2, 3-4, 5-8, 9-16, 17+
constexpr int kSmallMax = 12;      // n0 of nodes with 2..12 new points: bisection
constexpr int kSplitContexts = 29; // 0: no known point; else 1 + 4 * share bucket + size class
constexpr int kBisectNodes = 32;   // heap positions of the bisection of [0, 12]
constexpr int kLargeClasses = 33;  // bit_width(n) of nodes with n > 12 (n < 2^32)
constexpr int kPrefixBits = 40;    // Exp-Golomb prefix: at most 40 ones
constexpr int kReuseContexts = 24; // floor(2 log2(values in range / values used there)), capped

struct SetCoderModels::Tables {
  AdaptiveBit single[kKnownClasses][kKnownClasses];
  AdaptiveBit small[kSmallMax + 1][kSplitContexts][kBisectNodes];
  AdaptiveBit large_prefix[kLargeClasses][kPrefixBits + 1];
  AdaptiveBit reuse[3][kReuseContexts];
  // Format 3: the grid's qbits, and the values each axis has taken in the
  // stream so far (made at the first point: a stream refused before its
  // first payload costs no memory). Format 2: qbits 0.
  int reuse_qbits = 0;
  std::vector<CoordinateSet> used_sets;

  bool reuses_coordinates() const { return reuse_qbits > 0; }
  std::vector<CoordinateSet>& used() {
    if (used_sets.empty())
      for (int a = 0; a < 3; ++a) used_sets.emplace_back(reuse_qbits);
    return used_sets;
  }
  void note(const GridPoint& p) {
    if (!reuses_coordinates()) return;
    auto& sets = used();
    sets[0].insert(static_cast<uint32_t>(p.x));
    sets[1].insert(static_cast<uint32_t>(p.y));
    sets[2].insert(static_cast<uint32_t>(p.z));
  }
};

SetCoderModels::SetCoderModels() : tables_(std::make_unique<Tables>()) {}

void SetCoderModels::enable_coordinate_reuse(int qbits) {
  tables_->used_sets.clear();
  tables_->reuse_qbits = qbits;
}
SetCoderModels::~SetCoderModels() = default;
SetCoderModels::SetCoderModels(SetCoderModels&&) noexcept = default;
SetCoderModels& SetCoderModels::operator=(SetCoderModels&&) noexcept = default;

MortonCode morton_encode(const GridPoint& p, int qbits) {
  MortonCode code = 0;
  for (int i = qbits - 1; i >= 0; --i) {
    code = (code << 3) | (static_cast<unsigned>((p.x >> i) & 1) << 2) |
           (static_cast<unsigned>((p.y >> i) & 1) << 1) | static_cast<unsigned>((p.z >> i) & 1);
  }
  return code;
}

GridPoint morton_decode(MortonCode code, int qbits) {
  GridPoint p;
  for (int i = 0; i < qbits; ++i) {
    p.z |= static_cast<int32_t>((code >> (3 * i)) & 1) << i;
    p.y |= static_cast<int32_t>((code >> (3 * i + 1)) & 1) << i;
    p.x |= static_cast<int32_t>((code >> (3 * i + 2)) & 1) << i;
  }
  return p;
}

void merge_known(std::vector<MortonCode>& known, std::span<const GridPoint> added, int qbits) {
  const size_t old_size = known.size();
  for (const GridPoint& p : added) known.push_back(morton_encode(p, qbits));
  std::sort(known.begin() + old_size, known.end());
  std::inplace_merge(known.begin(), known.begin() + old_size, known.end());
}

namespace {

int known_class(uint64_t k) {
  if (k <= 2) return static_cast<int>(k);
  if (k <= 4) return 3;
  if (k <= 8) return 4;
  if (k <= 16) return 5;
  return 6;
}

// The share of the known points in the first child, in 7 buckets, and how
// many known points back it: where the coarser level is dense, the finer one
// is too.
int split_context(uint64_t k0, uint64_t k) {
  if (k == 0) return 0;
  const int share = static_cast<int>((7 * (2 * k0 + 1)) / (2 * (k + 1)));  // 0..6
  const int size = k <= 1 ? 0 : k <= 4 ? 1 : k <= 16 ? 2 : 3;
  return 1 + 4 * share + size;
}

// n * (k0 + 1/2) / (k + 1), rounded half up: the known points' guess at n0.
uint64_t predicted_first(uint64_t n, uint64_t k0, uint64_t k) {
  const unsigned __int128 num = static_cast<unsigned __int128>(n) * (2 * k0 + 1) + (k + 1);
  return static_cast<uint64_t>(num / (2 * (k + 1)));
}

// The context of a lone point's reuse bit: how crowded the node's interval of
// 2^r values is with used ones, b = floor(2 log2(2^r / m)), at most 23.
int reuse_context(uint64_t m, int r) {
  const unsigned __int128 range_squared = static_cast<unsigned __int128>(1) << (2 * r);
  int b = 0;
  while (b + 1 < kReuseContexts &&
         (static_cast<unsigned __int128>(m) * m << (b + 1)) <= range_squared)
    ++b;
  return b;
}

// The bits a lone point has left on each axis at depth d (x is split first).
int remaining_bits(int qbits, int depth, int axis) { return qbits - (depth + 2 - axis) / 3; }

int32_t axis_of(const GridPoint& p, int axis) { return axis == 0 ? p.x : axis == 1 ? p.y : p.z; }

uint64_t zigzag(int64_t d) { return d >= 0 ? 2 * static_cast<uint64_t>(d) : 2 * static_cast<uint64_t>(-d) - 1; }
int64_t unzigzag(uint64_t u) { return (u & 1) ? -static_cast<int64_t>((u + 1) / 2) : static_cast<int64_t>(u / 2); }

// The first index in [lo, hi) of `codes` whose code is >= mid.
size_t split_index(std::span<const MortonCode> codes, size_t lo, size_t hi, MortonCode mid) {
  return static_cast<size_t>(
      std::lower_bound(codes.begin() + lo, codes.begin() + hi, mid) - codes.begin());
}

class Encoder {
 public:
  Encoder(std::span<const MortonCode> known, std::span<const MortonCode> fresh, int qbits,
          SetCoderModels::Tables& t)
      : known_(known), fresh_(fresh), qbits_(qbits), bits_(3 * qbits), t_(t) {}

  std::vector<uint8_t> run() {
    node(0, 0, 0, fresh_.size(), 0, known_.size());
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
        if (upper) lo = half + 1;
        else hi = half;
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
      const uint64_t first = static_cast<uint64_t>(axis_of(lo, a)), value = static_cast<uint64_t>(axis_of(p, a));
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
      if (reused) rc_.encode_index(used_below, m);
      else rc_.encode_index(value - first - used_below, (uint64_t{1} << r) - m);
    }
    t_.note(p);
  }

  std::span<const MortonCode> known_, fresh_;
  int qbits_, bits_;
  SetCoderModels::Tables& t_;
  RangeEncoder rc_;
};

class Decoder {
 public:
  Decoder(std::span<const uint8_t> payload, std::span<const MortonCode> known, int qbits,
          SetCoderModels::Tables& t, std::vector<GridPoint>& out)
      : rc_(payload), known_(known), qbits_(qbits), bits_(3 * qbits), t_(t), out_(out) {}

  Status run(uint32_t count) {
    if (!node(0, 0, count, 0, known_.size())) return {StatusCode::kCorrupt, error_};
    if (!rc_.finished_cleanly())
      return {StatusCode::kCorrupt, rc_.overran() ? "point-set payload ends early"
                                                  : "point-set payload does not end where its bytes do"};
    return Status::Ok();
  }

 private:
  bool fail(const char* why) {
    error_ = why;
    return false;
  }

  bool node(int depth, MortonCode base, uint64_t n, size_t k0, size_t k1) {
    // A payload that runs past its end only reads zeros: stop at once rather
    // than decode what the stream does not hold.
    if (rc_.overran()) return fail("point-set payload ends early");
    const uint64_t k = k1 - k0;
    const int rest = bits_ - depth;
    if (rest == 0) {
      if (n > 1) return fail("two points in one grid cell");
      if (k > 0) return fail("a point of this layer is already in a coarser level");
      out_.push_back(morton_decode(base, qbits_));
      t_.note(out_.back());
      return true;
    }
    if (n == 1 && k == 0) return lone(depth, base);
    const MortonCode mid = base + (MortonCode{1} << (rest - 1));
    const size_t km = split_index(known_, k0, k1, mid);
    const uint64_t kn0 = km - k0;
    uint64_t n0 = 0;
    if (n == 1) {
      // Bit 1: the point is in the second child.
      n0 = rc_.decode(t_.single[known_class(kn0)][known_class(k - kn0)]) ? 0 : 1;
    } else if (n <= kSmallMax) {
      auto& models = t_.small[n][split_context(kn0, k)];
      uint64_t lo = 0, hi = n;
      int heap = 1;
      while (lo < hi) {
        const uint64_t half = (lo + hi) / 2;
        const bool upper = rc_.decode(models[heap]);
        heap = 2 * heap + upper;
        if (upper) lo = half + 1;
        else hi = half;
      }
      n0 = lo;
    } else {
      auto& prefix = t_.large_prefix[std::bit_width(n)];
      int e = 0;
      while (rc_.decode(prefix[e]))
        if (++e > kPrefixBits - 1) return fail("point count out of range");
      const uint64_t u = (uint64_t{1} << e) | rc_.decode_raw(e);
      const int64_t value = static_cast<int64_t>(predicted_first(n, kn0, k)) + unzigzag(u - 1);
      if (value < 0 || static_cast<uint64_t>(value) > n) return fail("point count out of range");
      n0 = static_cast<uint64_t>(value);
    }
    if (n0 > 0 && !node(depth + 1, base, n0, k0, km)) return false;
    if (n > n0 && !node(depth + 1, mid, n - n0, km, k1)) return false;
    return true;
  }

  bool lone(int depth, MortonCode base) {
    if (!t_.reuses_coordinates()) {
      const int rest = bits_ - depth;
      MortonCode offset = 0;
      if (rest > 64) offset = MortonCode{rc_.decode_raw(rest - 64)} << 64;
      offset |= rc_.decode_raw(std::min(rest, 64));
      out_.push_back(morton_decode(base + offset, qbits_));
      return true;
    }
    GridPoint p = morton_decode(base, qbits_);
    int32_t* coordinate[3] = {&p.x, &p.y, &p.z};
    for (int a = 0; a < 3; ++a) {
      const int r = remaining_bits(qbits_, depth, a);
      if (r == 0) continue;
      const uint64_t first = static_cast<uint64_t>(*coordinate[a]), size = uint64_t{1} << r;
      const CoordinateSet& used = t_.used()[a];
      const uint64_t m = used.count_in(first, first + size);
      uint64_t value = 0;
      if (m == 0) {
        value = first + rc_.decode_raw(r);
      } else {
        const bool reused = m == size || rc_.decode(t_.reuse[a][reuse_context(m, r)]);
        const uint64_t count = reused ? m : size - m;
        const uint64_t i = rc_.decode_index(count);
        if (i >= count) return fail("coordinate rank out of range");
        value = reused ? used.select(first, i) : used.select_absent(first, i);
      }
      *coordinate[a] = static_cast<int32_t>(value);
    }
    out_.push_back(p);
    t_.note(p);
    return true;
  }

  RangeDecoder rc_;
  std::span<const MortonCode> known_;
  int qbits_, bits_;
  SetCoderModels::Tables& t_;
  std::vector<GridPoint>& out_;
  const char* error_ = "";
};

}  // namespace

std::vector<uint8_t> encode_point_set(std::span<const MortonCode> known,
                                      std::span<const GridPoint> points, int qbits,
                                      SetCoderModels& models) {
  if (points.empty()) return {};
  std::vector<MortonCode> fresh;
  fresh.reserve(points.size());
  for (const GridPoint& p : points) fresh.push_back(morton_encode(p, qbits));
  std::sort(fresh.begin(), fresh.end());
  return Encoder(known, fresh, qbits, models.tables()).run();
}

Status decode_point_set(std::span<const uint8_t> payload, std::span<const MortonCode> known,
                        int qbits, uint32_t count, SetCoderModels& models,
                        std::vector<GridPoint>& out) {
  if (count == 0) {
    if (!payload.empty()) return {StatusCode::kCorrupt, "payload bytes in a layer of no points"};
    return Status::Ok();
  }
  if (payload.size() < min_payload_bytes(count))
    return {StatusCode::kCorrupt, "payload too short for its point count"};
  return Decoder(payload, known, qbits, models.tables(), out).run(count);
}

}  // namespace dtm
