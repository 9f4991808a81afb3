// point_models STREAM.dtm ... -- research for the layer coder (issue 23,
// research/point_models.md): what each candidate context model would
// cost on a stream's layers, against the coder as shipped.
//
// The layers are decoded from the stream (level l's new points given the
// coarser levels); each model is the shipped coder's recursion (spec/
// FORMAT.md §3.1) with one rule changed, run as an ideal adaptive coder: an
// adaptive bit costs -log2 of its model's probability (the same AdaptiveBit
// as the range coder), a raw bit 1, a uniform index log2(count). The models
// carry over from layer to layer, as the shipped coder's do. "shipped" is the
// real encoder's payload bytes, to check that "baseline" (the shipped rules
// run as ideal coding) measures the same thing.
//
// Candidate rules (each adds to the one before):
// - spacing: a lone point's node (one new point, no known one) is bisected
//   further, each half chosen by an adaptive bit, while the node is at least
//   an eighth of the local spacing; the context is how near each half's
//   centre comes to a point the decoder holds (the coarser levels and the
//   layer's points already decoded), relative to each other and to the
//   spacing (a well-spaced set leaves no point near another). Below that,
//   the shipped raw or reused coordinates.
// - single: a node with one new point and known ones takes the same context
//   beside its known-point classes.
// - distances: as single, the lone points' context being each half's
//   distance over the spacing, in 7 buckets each.
// - axis (on the shipped rules alone): the split's axis added to the
//   contexts of nodes with 2-12 new points and of single points.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iterator>
#include <string>
#include <unordered_map>
#include <vector>

#include "bitstream/coordinate_set.h"
#include "bitstream/range_coder.h"
#include "codec/decode.h"
#include "codec/stream/layer_coder.h"
#include "codec/stream/layer_coder_shared.h"

namespace {

using dtm::AdaptiveBit;
using dtm::GridPoint;
using dtm::MortonCode;
using namespace dtm::layer_coder;
using dtm::kBisectNodes;
using dtm::kKnownClasses;
using dtm::kLargeClasses;
using dtm::kPrefixBits;
using dtm::kReuseContexts;
using dtm::kSmallMax;
using dtm::kSplitContexts;

// The points the decoder holds, for nearest-point queries: a hash grid.
class NearPoints {
 public:
  static constexpr int kRings = 6;
  explicit NearPoints(double cell) : cell_(std::max(1.0, cell)) {}
  void add(const GridPoint& p, double spacing) {
    cells_[key(cell_of(p.x), cell_of(p.y), cell_of(p.z))].push_back(static_cast<uint32_t>(pts_.size()));
    pts_.push_back(p);
    spacing_.push_back(spacing);
  }
  // The distance from (x, y, z) to the nearest point (at most `cap`) and
  // that point's spacing (0 when none within cap).
  std::pair<double, double> nearest(double x, double y, double z, double cap, int64_t skip = -1) const {
    double best = cap * cap, s = 0;
    const int64_t cx = cell_of(x), cy = cell_of(y), cz = cell_of(z);
    // At most kRings rings of cells: beyond, the answer is `cap` (the
    // contexts only tell near from far).
    const int rings = std::min(kRings, static_cast<int>(std::ceil(cap / cell_)) + 1);
    for (int r = 0; r <= rings; ++r) {
      if (r > 0 && (r - 1) * cell_ > std::sqrt(best)) break;
      for (int64_t i = -r; i <= r; ++i)
        for (int64_t j = -r; j <= r; ++j)
          for (int64_t k = -r; k <= r; k += (std::abs(i) == r || std::abs(j) == r) ? 1 : 2 * r) {
            const auto it = cells_.find(key(cx + i, cy + j, cz + k));
            if (it == cells_.end()) continue;
            for (uint32_t q : it->second) {
              if (static_cast<int64_t>(q) == skip) continue;
              const double dx = pts_[q].x - x, dy = pts_[q].y - y, dz = pts_[q].z - z;
              const double d2 = dx * dx + dy * dy + dz * dz;
              if (d2 < best) best = d2, s = spacing_[q];
            }
          }
    }
    return {std::sqrt(best), s};
  }
  void set_spacing(size_t i, double s) { spacing_[i] = s; }

 private:
  int64_t cell_of(double v) const { return static_cast<int64_t>(std::floor(v / cell_)); }
  static uint64_t key(int64_t x, int64_t y, int64_t z) {
    return (static_cast<uint64_t>(x & 0x1FFFFF) << 42) | (static_cast<uint64_t>(y & 0x1FFFFF) << 21) |
           static_cast<uint64_t>(z & 0x1FFFFF);
  }
  double cell_;
  std::unordered_map<uint64_t, std::vector<uint32_t>> cells_;
  std::vector<GridPoint> pts_;
  std::vector<double> spacing_;
};

enum class Model { kBaseline, kSpacing, kSingle, kDistances, kAxis };
const char* name(Model m) {
  switch (m) {
    case Model::kBaseline:
      return "baseline";
    case Model::kSpacing:
      return "spacing";
    case Model::kSingle:
      return "single";
    case Model::kDistances:
      return "distances";
    case Model::kAxis:
      return "axis";
  }
  return "?";
}

static double kLowestZ = -3;
static int kMaxSteps = 64;
constexpr int kSizeClasses = 12;     // half octaves of node extent / spacing, from 1/8 up
constexpr int kNearBuckets = 9;      // d0 / (d0 + d1) in ninths
constexpr int kDistanceBuckets = 7;  // d / s: 0, 1/4, 1/2, 3/4, 1, 3/2, 2 and up
int distance_bucket(double u) {
  static constexpr double kSteps[] = {0.25, 0.5, 0.75, 1.0, 1.5, 2.0};
  int b = 0;
  for (double step : kSteps) b += u >= step;
  return b;
}

struct Tables {
  AdaptiveBit single[kKnownClasses][kKnownClasses];
  AdaptiveBit single_near[3][3][kSizeClasses][kNearBuckets];
  AdaptiveBit small[kSmallMax + 1][kSplitContexts][kBisectNodes];
  AdaptiveBit small_axis[3][kSmallMax + 1][kSplitContexts][kBisectNodes];
  AdaptiveBit single_axis[3][kKnownClasses][kKnownClasses];
  AdaptiveBit large_prefix[kLargeClasses][kPrefixBits + 1];
  AdaptiveBit reuse[3][kReuseContexts];
  AdaptiveBit lone[kSizeClasses][kNearBuckets];
  AdaptiveBit lone_d[kSizeClasses][kDistanceBuckets][kDistanceBuckets];
  std::vector<dtm::CoordinateSet> used;
  explicit Tables(int qbits) {
    for (int a = 0; a < 3; ++a) used.emplace_back(qbits);
  }
  void note(const GridPoint& p) {
    used[0].insert(static_cast<uint32_t>(p.x));
    used[1].insert(static_cast<uint32_t>(p.y));
    used[2].insert(static_cast<uint32_t>(p.z));
  }
};

class CostCoder {
 public:
  CostCoder(std::span<const MortonCode> known, std::span<const MortonCode> fresh, int qbits, Tables& t,
            Model m, NearPoints& near)
      : known_(known), fresh_(fresh), qbits_(qbits), bits_(3 * qbits), t_(t), model_(m), near_(near) {}

  double run() {
    node(0, 0, 0, fresh_.size(), 0, known_.size());
    return cost_;
  }
  double lone_bits = 0;

 private:
  void bit(AdaptiveBit& a, bool b) {
    const double p = (b ? 65536.0 - a.p0 : a.p0) / 65536.0;
    cost_ += -std::log2(p);
    a.update(b);
  }
  void index(uint64_t count) {
    if (count > 1) cost_ += std::log2(static_cast<double>(count));
  }

  // The box of a node: its low corner and its extent per axis.
  void box(int depth, MortonCode base, GridPoint& lo, std::array<int64_t, 3>& size) const {
    lo = dtm::morton_decode(base, qbits_);
    for (int a = 0; a < 3; ++a) size[a] = int64_t{1} << remaining_bits(qbits_, depth, a);
  }

  // The context of choosing a half of a node at `depth` (split axis depth %
  // 3): -1 when the node is below an eighth of the spacing (or no point is
  // near).
  int near_context(int depth, MortonCode base, int& size_class, int* buckets = nullptr) const {
    GridPoint lo;
    std::array<int64_t, 3> size;
    box(depth, base, lo, size);
    const int axis = depth % 3;
    const double cx = lo.x + size[0] / 2.0, cy = lo.y + size[1] / 2.0, cz = lo.z + size[2] / 2.0;
    const double extent = static_cast<double>(std::max({size[0], size[1], size[2]}));
    std::array<double, 3> c0 = {cx, cy, cz}, c1 = c0;
    c0[axis] -= size[axis] / 4.0;
    c1[axis] += size[axis] / 4.0;
    const double cap = 4 * extent;
    const auto [d0, s0] = near_.nearest(c0[0], c0[1], c0[2], cap);
    const auto [d1, s1] = near_.nearest(c1[0], c1[1], c1[2], cap);
    const double s = std::max(s0, s1);
    if (s <= 0) return -1;
    const double z = std::log2(extent / s);
    if (z < kLowestZ) return -1;
    size_class = std::min(kSizeClasses - 1, static_cast<int>(std::floor(2 * (z + 3))));
    if (buckets) {
      buckets[0] = distance_bucket(d0 / s);
      buckets[1] = distance_bucket(d1 / s);
    }
    const double t = d0 + d1 > 0 ? d0 / (d0 + d1) : 0.5;
    return std::min(kNearBuckets - 1, static_cast<int>(t * kNearBuckets));
  }

  void node(int depth, MortonCode base, size_t f0, size_t f1, size_t k0, size_t k1) {
    const uint64_t n = f1 - f0, k = k1 - k0;
    const int rest = bits_ - depth;
    if (rest == 0) {
      added(dtm::morton_decode(base, qbits_));
      return;
    }
    if (n == 1 && k == 0) {
      const double before = cost_;
      lone(depth, base, fresh_[f0]);
      lone_bits += cost_ - before;
      return;
    }
    const MortonCode mid = base + (MortonCode{1} << (rest - 1));
    const size_t fm = split_index(fresh_, f0, f1, mid);
    const size_t km = split_index(known_, k0, k1, mid);
    const uint64_t n0 = fm - f0, kn0 = km - k0;
    if (n == 1) {
      int size_class = 0;
      const int c =
          model_ >= Model::kSingle && model_ != Model::kAxis ? near_context(depth, base, size_class) : -1;
      if (model_ == Model::kAxis)
        bit(t_.single_axis[depth % 3][known_class(kn0)][known_class(k - kn0)], n0 == 0);
      else if (c >= 0)
        bit(t_.single_near[std::min(known_class(kn0), 2)][std::min(known_class(k - kn0), 2)][size_class][c],
            n0 == 0);
      else
        bit(t_.single[known_class(kn0)][known_class(k - kn0)], n0 == 0);
    } else if (n <= kSmallMax) {
      auto& models = model_ == Model::kAxis ? t_.small_axis[depth % 3][n][split_context(kn0, k)]
                                            : t_.small[n][split_context(kn0, k)];
      uint64_t lo = 0, hi = n;
      int heap = 1;
      while (lo < hi) {
        const uint64_t half = (lo + hi) / 2;
        const bool upper = n0 > half;
        bit(models[heap], upper);
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
      for (int i = 0; i < e; ++i) bit(prefix[i], true);
      bit(prefix[e], false);
      cost_ += e;
    }
    if (fm > f0) node(depth + 1, base, f0, fm, k0, km);
    if (f1 > fm) node(depth + 1, mid, fm, f1, km, k1);
  }

  void lone(int depth, MortonCode base, MortonCode code) {
    if (model_ >= Model::kSpacing && model_ != Model::kAxis) {
      // Halves chosen by adaptive bits while the node is large against the spacing.
      for (int step = 0; bits_ - depth > 0 && step < kMaxSteps; ++step) {
        int size_class = 0, b[2] = {0, 0};
        const int c = near_context(depth, base, size_class, b);
        if (c < 0) break;
        const MortonCode mid = base + (MortonCode{1} << (bits_ - depth - 1));
        const bool upper = code >= mid;
        bit(model_ == Model::kDistances ? t_.lone_d[size_class][b[0]][b[1]] : t_.lone[size_class][c], upper);
        if (upper) base = mid;
        ++depth;
      }
    }
    const GridPoint p = dtm::morton_decode(code, qbits_), lo = dtm::morton_decode(base, qbits_);
    for (int a = 0; a < 3; ++a) {
      const int r = remaining_bits(qbits_, depth, a);
      if (r == 0) continue;
      const uint64_t first = static_cast<uint64_t>(axis_of(lo, a)),
                     value = static_cast<uint64_t>(axis_of(p, a));
      const dtm::CoordinateSet& used = t_.used[a];
      const uint64_t m = used.count_in(first, first + (uint64_t{1} << r));
      if (m == 0) {
        cost_ += r;
        continue;
      }
      const bool reused = used.contains(static_cast<uint32_t>(value));
      if (m < (uint64_t{1} << r)) bit(t_.reuse[a][reuse_context(m, r)], reused);
      index(reused ? m : (uint64_t{1} << r) - m);
    }
    added(p);
  }

  void added(const GridPoint& p) {
    t_.note(p);
    const auto [d, s] = near_.nearest(p.x, p.y, p.z, 1e9);
    (void)d;
    near_.add(p, s);
  }

  std::span<const MortonCode> known_, fresh_;
  int qbits_, bits_;
  Tables& t_;
  Model model_;
  NearPoints& near_;
  double cost_ = 0;
};

std::vector<uint8_t> read_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), {}};
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr, "usage: point_models STREAM.dtm ...\n");
    return 2;
  }
  if (const char* e = std::getenv("PM_LOWEST_Z")) kLowestZ = std::atof(e);
  if (const char* e = std::getenv("PM_MAX_STEPS")) kMaxSteps = std::atoi(e);
  const Model models[] = {Model::kBaseline, Model::kSpacing, Model::kSingle, Model::kDistances, Model::kAxis};
  std::printf("| stream | vertices | shipped payload bpv | ");
  for (Model m : models) std::printf("%s bpv | ", name(m));
  std::printf("lone share (baseline) |\n|---|---:|---:|");
  for (size_t i = 0; i < std::size(models); ++i) std::printf("---:|");
  std::printf("---:|\n");
  for (int i = 1; i < argc; ++i) {
    const std::vector<uint8_t> bytes = read_file(argv[i]);
    dtm::ProgressiveDecoder dec;
    if (const dtm::Status s = dtm::decode_stream(bytes, dec); !s.ok()) {
      std::fprintf(stderr, "%s: %s\n", argv[i], s.message().c_str());
      return 1;
    }
    const int qbits = dec.header().grid.qbits;
    const auto& points = dec.points();
    std::vector<size_t> ends;
    for (const auto& l : dec.levels()) ends.push_back(l.vertices);
    const double n_total = static_cast<double>(points.size());
    // The shipped coder, for the check.
    double shipped = 0;
    {
      dtm::SetCoderModels real;
      real.enable_coordinate_reuse(qbits);
      std::vector<MortonCode> known;
      size_t begin = 0;
      for (size_t end : ends) {
        const std::span<const GridPoint> layer(points.data() + begin, end - begin);
        shipped += 8.0 * static_cast<double>(dtm::encode_point_set(known, layer, qbits, real).size());
        dtm::merge_known(known, layer, qbits);
        begin = end;
      }
    }
    std::printf("| %s | %zu | %.3f | ", argv[i], points.size(), shipped / n_total);
    double lone_share = 0;
    for (Model m : models) {
      Tables t(qbits);
      std::vector<MortonCode> known;
      double total = 0, lone = 0;
      size_t begin = 0;
      for (size_t end : ends) {
        const std::span<const GridPoint> layer(points.data() + begin, end - begin);
        // The decoder's points: the coarser levels, each with its spacing
        // (the distance to its nearest neighbour among them).
        const double volume_per_point =
            begin > 0 ? std::pow(2.0, 3 * qbits) / static_cast<double>(begin) : std::pow(2.0, 3 * qbits);
        NearPoints near(std::cbrt(volume_per_point) / 4);
        for (size_t v = 0; v < begin; ++v) near.add(points[v], 0);
        for (size_t v = 0; v < begin; ++v) {
          const GridPoint& p = points[v];
          near.set_spacing(v, near.nearest(p.x, p.y, p.z, 1e9, static_cast<int64_t>(v)).first);
        }
        std::vector<MortonCode> fresh;
        for (const GridPoint& p : layer) fresh.push_back(dtm::morton_encode(p, qbits));
        std::sort(fresh.begin(), fresh.end());
        CostCoder coder(known, fresh, qbits, t, m, near);
        total += coder.run();
        lone += coder.lone_bits;
        dtm::merge_known(known, layer, qbits);
        begin = end;
      }
      if (m == Model::kBaseline) lone_share = lone / total;
      std::printf("%.3f | ", total / n_total);
    }
    std::printf("%.1f%% |\n", 100 * lone_share);
    std::fflush(stdout);
  }
  return 0;
}
