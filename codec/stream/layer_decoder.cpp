// The layer coder's decoder (spec/FORMAT.md §3.1); layer_encoder.cpp mirrors it.
#include "codec/stream/layer_coder.h"
#include "codec/stream/layer_coder_shared.h"

namespace dtm {
namespace layer_coder {
namespace {

class Decoder {
 public:
  Decoder(std::span<const uint8_t> payload, std::span<const MortonCode> known, int qbits,
          SetCoderModels::Tables& t, std::vector<GridPoint>& out)
      : rc_(payload), known_(known), qbits_(qbits), bits_(3 * qbits), t_(t), out_(out) {}

  Status run(uint32_t count, PointSetNode start) {
    DTM_RETURN_IF_ERROR(node(start.depth, start.base, count, 0, known_.size()));
    if (!rc_.finished_cleanly())
      return fail(rc_.overran() ? "point-set payload ends early"
                                : "point-set payload does not end where its bytes do");
    return Status::Ok();
  }

 private:
  static Status fail(const char* why) { return {StatusCode::kCorrupt, why}; }

  Status node(int depth, MortonCode base, uint64_t n, size_t k0, size_t k1) {
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
      return Status::Ok();
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
        if (upper)
          lo = half + 1;
        else
          hi = half;
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
    if (n0 > 0) DTM_RETURN_IF_ERROR(node(depth + 1, base, n0, k0, km));
    if (n > n0) DTM_RETURN_IF_ERROR(node(depth + 1, mid, n - n0, km, k1));
    return Status::Ok();
  }

  Status lone(int depth, MortonCode base) {
    if (!t_.reuses_coordinates()) {
      const int rest = bits_ - depth;
      MortonCode offset = 0;
      if (rest > 64) offset = MortonCode{rc_.decode_raw(rest - 64)} << 64;
      offset |= rc_.decode_raw(std::min(rest, 64));
      out_.push_back(morton_decode(base + offset, qbits_));
      return Status::Ok();
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
        uint64_t i = 0;
        DTM_RETURN_IF_ERROR(rc_.decode_index(count, i));
        value = reused ? used.select(first, i) : used.select_absent(first, i);
      }
      *coordinate[a] = static_cast<int32_t>(value);
    }
    out_.push_back(p);
    t_.note(p);
    return Status::Ok();
  }

  RangeDecoder rc_;
  std::span<const MortonCode> known_;
  int qbits_, bits_;
  SetCoderModels::Tables& t_;
  std::vector<GridPoint>& out_;
};

}  // namespace
}  // namespace layer_coder

Status decode_point_set(std::span<const uint8_t> payload, std::span<const MortonCode> known, int qbits,
                        uint32_t count, SetCoderModels& models, std::vector<GridPoint>& out,
                        PointSetNode start) {
  if (count == 0) {
    if (!payload.empty()) return {StatusCode::kCorrupt, "payload bytes in a layer of no points"};
    return Status::Ok();
  }
  if (payload.size() < min_payload_bytes(count))
    return {StatusCode::kCorrupt, "payload too short for its point count"};
  return layer_coder::Decoder(payload, known, qbits, models.tables(), out).run(count, start);
}

}  // namespace dtm
