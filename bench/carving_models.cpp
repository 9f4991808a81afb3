// carving_models STREAM.dtm ... -- research for the carving corrections
// (issue 23, docs/research/point_models.md): what candidate contexts would
// cost on a stream's corrections, against the contexts as shipped.
//
// Every level is decoded (its Delaunay cells in the canonical order and its
// true verdicts, the corrections applied); each model codes the same flips
// (the cells where alpha's verdict is wrong) in the same order as an ideal
// adaptive coder (-log2 of the AdaptiveBit's probability, fresh models per
// level, as the shipped coder). "shipped" is the shipped encoder's bytes for
// the same verdicts.
//
// Candidate contexts, beside the shipped (circumradius / alpha bucket, how
// many face neighbours alpha keeps):
// - flips: how many of the face neighbours already coded (earlier in the
//   order) were flipped, 0, 1, 2+;
// - verdicts: the neighbours' kept count taking the true verdict of those
//   already coded and alpha's for the others, with the flips count.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "bitstream/range_coder.h"
#include "codec/carving_coder.h"
#include "codec/decode.h"

namespace {

using dtm::AdaptiveBit;

struct Cost {
  std::vector<AdaptiveBit> models;
  double bits = 0;
  explicit Cost(size_t contexts) : models(contexts) {}
  void code(size_t context, bool b) {
    AdaptiveBit& a = models[context];
    bits += -std::log2((b ? 65536.0 - a.p0 : a.p0) / 65536.0);
    a.update(b);
  }
};

std::vector<uint8_t> read_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), {}};
}

// The vertices the level's layer added (the decoder numbers vertices in
// decode order: the coarser levels' first).
uint32_t new_vertices(const dtm::ProgressiveDecoder& d, const dtm::DecodedLevel& level) {
  uint32_t coarser = 0;
  for (const auto& l : d.levels())
    if (l.vertices < level.vertices) coarser = std::max(coarser, l.vertices);
  return level.vertices - coarser;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr, "usage: carving_models STREAM.dtm ...\n");
    return 2;
  }
  std::printf(
      "| stream | vertices | cells, all levels | flips | shipped bits | baseline | flips | verdicts | "
      "verdicts "
      "without alpha's neighbours | + new vertices | flips 0-3 | coded count "
      "|\n|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n");
  for (int i = 1; i < argc; ++i) {
    const std::vector<uint8_t> bytes = read_file(argv[i]);
    double shipped = 0, base = 0, flips_cost = 0, verdicts_cost = 0, plain_cost = 0, fresh_cost = 0,
           flips4_cost = 0, coded_cost = 0;
    uint64_t cells = 0, flips = 0;
    dtm::ProgressiveDecoder dec;
    const auto on_level = [&](const dtm::ProgressiveDecoder& d, const dtm::DecodedLevel& level) {
      const dtm::TetMesh dt = d.delaunay(dtm::IncrementalDelaunay::CellOrder::kCanonical);
      const std::vector<uint8_t> kept = d.carving(dt);
      const dtm::CarvingPrediction p =
          dtm::predict_carving(dt, d.points(), level.alpha, dtm::CarvingContexts::kAlphaNeighbours);
      Cost c0(dtm::kAlphaNeighbourContexts), c1(dtm::kAlphaNeighbourContexts * 3),
          c2(dtm::kCarvingRatioBuckets * 5 * 3 * 5), c3(dtm::kCarvingRatioBuckets * 5 * 3),
          c4(dtm::kCarvingRatioBuckets * 5 * 3 * 5), c5(dtm::kCarvingRatioBuckets * 5 * 4),
          c6(dtm::kCarvingRatioBuckets * 5 * 5 * 3);
      const uint32_t coarser = level.vertices - new_vertices(d, level);
      std::vector<uint8_t> done(dt.cells.size(), 0);
      bool any = false;
      for (uint32_t c : p.order) any = any || kept[c] != p.kept[c];
      if (!any) return;
      for (uint32_t c : p.order) {
        const bool flip = kept[c] != p.kept[c];
        int flipped = 0, verdict_kept = 0, coded = 0;
        for (int32_t n : dt.neighbors[c]) {
          if (n < 0) continue;
          const auto k = static_cast<size_t>(n);
          if (done[k]) {
            ++coded;
            flipped += kept[k] != p.kept[k];
            verdict_kept += kept[k];
          } else {
            verdict_kept += p.kept[k];
          }
        }
        const int bucket = p.context[c] / 5;
        const int f = std::min(flipped, 2);
        c0.code(p.context[c], flip);
        c1.code(p.context[c] * 3 + f, flip);
        c2.code(((bucket / 2) * 5 + verdict_kept) * 3 + f, flip);
        c6.code(((bucket / 4) * 5 + verdict_kept) * 3 + f, flip);
        c3.code((bucket * 5 + verdict_kept) * 3 + f, flip);
        int fresh = 0;
        for (uint32_t v : dt.cells[c]) fresh += v >= coarser;
        c4.code(((bucket * 5 + verdict_kept) * 3 + f) * 5 + fresh, flip);
        c5.code((bucket * 5 + verdict_kept) * 4 + std::min(flipped, 3), flip);
        done[c] = 1;
        ++cells;
        flips += flip;
      }
      shipped +=
          8.0 * static_cast<double>(dtm::encode_carving(dt, d.points(), level.alpha, kept,
                                                        dtm::carving_contexts(d.header().version_major))
                                        .size());
      base += c0.bits, flips_cost += c1.bits, verdicts_cost += c2.bits, plain_cost += c3.bits;
      fresh_cost += c4.bits, flips4_cost += c5.bits, coded_cost += c6.bits;
    };
    if (const dtm::Status s = dec.feed(bytes, on_level); !s.ok()) {
      std::fprintf(stderr, "%s: %s\n", argv[i], s.message().c_str());
      return 1;
    }
    std::printf("| %s | %zu | %llu | %llu | %.0f | %.0f | %.0f | %.0f | %.0f | %.0f | %.0f | %.0f |\n",
                argv[i], dec.points().size(), static_cast<unsigned long long>(cells),
                static_cast<unsigned long long>(flips), shipped, base, flips_cost, verdicts_cost, plain_cost,
                fresh_cost, flips4_cost, coded_cost);
    std::fflush(stdout);
  }
  return 0;
}
