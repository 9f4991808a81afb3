// carving_models STREAM.dtm ... -- research for the carving corrections
// (issue 23, research/point_models.md): what candidate contexts would
// cost on a stream's corrections.
//
// Every level is decoded (its Delaunay cells in the canonical order and its
// true verdicts, the corrections applied); each variant codes the same
// wrong predictions in the same order as an ideal adaptive coder (-log2 of
// the AdaptiveBit's probability, fresh models per level, as the real coder).
// "5.0 coder" and "6.0 coder" are the real encoder's bits for the same
// verdicts with 5.0's and 6.0's contexts (spec/FORMAT.md §3.2).
//
// Variants, each a context from the cell's circumradius bucket (16 quarter
// octaves) and its face neighbours, "decoded" meaning earlier in the order:
// - 5.0: the bucket and how many neighbours alpha keeps;
// - 5.0 + wrong: and how many decoded neighbours alpha got wrong (0, 1, 2+);
// - verdicts: how many neighbours are kept by their decoded verdict (alpha's
//   where not decoded), and wrong 0/1/2+; in quarter, half (6.0) and whole
//   octave buckets;
// - verdicts + new: quarter octaves, and how many of the cell's vertices
//   the level's layer added (0-4);
// - verdicts + decoded: quarter octaves, and how many neighbours are decoded;
// - verdicts, wrong 0-3: quarter octaves, wrong capped at 3.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "bitstream/range_coder.h"
#include "codec/decode.h"
#include "codec/sections/carving_coder.h"

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

// What a variant sees of a cell.
struct CellView {
  int bucket;        // circumradius bucket, < kCarvingRatioBuckets
  int alpha_kept;    // neighbours alpha keeps
  int verdict_kept;  // neighbours kept: decoded verdict, else alpha's
  int wrong;         // decoded neighbours alpha got wrong
  int decoded;       // decoded neighbours
  int fresh;         // vertices the level's layer added
};

struct Variant {
  const char* name;
  size_t contexts;
  size_t (*context)(const CellView&);
};

constexpr int B = dtm::kCarvingRatioBuckets;
const Variant kVariants[] = {
    {"5.0", B * 5, [](const CellView& v) -> size_t { return v.bucket * 5 + v.alpha_kept; }},
    {"5.0 + wrong", B * 5 * 3,
     [](const CellView& v) -> size_t { return (v.bucket * 5 + v.alpha_kept) * 3 + std::min(v.wrong, 2); }},
    {"verdicts, quarter octaves", B * 5 * 3,
     [](const CellView& v) -> size_t { return (v.bucket * 5 + v.verdict_kept) * 3 + std::min(v.wrong, 2); }},
    {"verdicts, half octaves (6.0)", B / 2 * 5 * 3,
     [](const CellView& v) -> size_t {
       return (v.bucket / 2 * 5 + v.verdict_kept) * 3 + std::min(v.wrong, 2);
     }},
    {"verdicts, octaves", B / 4 * 5 * 3,
     [](const CellView& v) -> size_t {
       return (v.bucket / 4 * 5 + v.verdict_kept) * 3 + std::min(v.wrong, 2);
     }},
    {"verdicts + new", B * 5 * 3 * 5,
     [](const CellView& v) -> size_t {
       return ((v.bucket * 5 + v.verdict_kept) * 3 + std::min(v.wrong, 2)) * 5 + v.fresh;
     }},
    {"verdicts + decoded", B * 5 * 3 * 5,
     [](const CellView& v) -> size_t {
       return ((v.bucket * 5 + v.verdict_kept) * 3 + std::min(v.wrong, 2)) * 5 + v.decoded;
     }},
    {"verdicts, wrong 0-3", B * 5 * 4,
     [](const CellView& v) -> size_t { return (v.bucket * 5 + v.verdict_kept) * 4 + std::min(v.wrong, 3); }},
};

double coder_bits(const dtm::TetMesh& dt, const dtm::ProgressiveDecoder& d, double alpha,
                  const std::vector<uint8_t>& kept, dtm::CarvingContexts contexts) {
  return 8.0 * static_cast<double>(dtm::encode_carving(dt, d.points(), alpha, kept, contexts).size());
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr, "usage: carving_models STREAM.dtm ...\n");
    return 2;
  }
  constexpr size_t kCount = std::size(kVariants);
  std::printf("| stream | vertices | cells, all levels | wrong predictions | 5.0 coder | 6.0 coder |");
  for (const Variant& v : kVariants) std::printf(" %s |", v.name);
  std::printf("\n|---|---:|---:|---:|---:|---:|");
  for (size_t i = 0; i < kCount; ++i) std::printf("---:|");
  std::printf("\n");
  for (int i = 1; i < argc; ++i) {
    const std::vector<uint8_t> bytes = read_file(argv[i]);
    double coder5 = 0, coder6 = 0;
    std::vector<double> totals(kCount, 0);
    uint64_t cells = 0, wrong_predictions = 0;
    dtm::ProgressiveDecoder dec;
    const auto on_level = [&](const dtm::ProgressiveDecoder& d, const dtm::DecodedLevel& level) {
      const dtm::TetMesh dt = d.delaunay(dtm::IncrementalDelaunay::CellOrder::kCanonical);
      const std::vector<uint8_t> kept = d.carving(dt);
      const dtm::CarvingPrediction p =
          dtm::predict_carving(dt, d.points(), level.alpha, dtm::CarvingContexts::kAlphaNeighbours);
      bool any = false;
      for (uint32_t c : p.order) any = any || kept[c] != p.kept[c];
      if (!any) return;
      std::vector<Cost> costs;
      for (const Variant& v : kVariants) costs.emplace_back(v.contexts);
      const uint32_t coarser = level.vertices - new_vertices(d, level);
      std::vector<uint8_t> done(dt.cells.size(), 0);
      for (uint32_t c : p.order) {
        const bool wrong = kept[c] != p.kept[c];
        CellView v{p.context[c] / 5, p.context[c] % 5, 0, 0, 0, 0};
        for (int32_t n : dt.neighbors[c]) {
          if (n < 0) continue;
          const auto k = static_cast<size_t>(n);
          if (done[k]) {
            ++v.decoded;
            v.wrong += kept[k] != p.kept[k];
            v.verdict_kept += kept[k];
          } else {
            v.verdict_kept += p.kept[k];
          }
        }
        for (uint32_t vertex : dt.cells[c]) v.fresh += vertex >= coarser;
        for (size_t m = 0; m < kCount; ++m) costs[m].code(kVariants[m].context(v), wrong);
        done[c] = 1;
        ++cells;
        wrong_predictions += wrong;
      }
      coder5 += coder_bits(dt, d, level.alpha, kept, dtm::CarvingContexts::kAlphaNeighbours);
      coder6 += coder_bits(dt, d, level.alpha, kept, dtm::CarvingContexts::kDecodedNeighbours);
      for (size_t m = 0; m < kCount; ++m) totals[m] += costs[m].bits;
    };
    if (const dtm::Status s = dec.feed(bytes, on_level); !s.ok()) {
      std::fprintf(stderr, "%s: %s\n", argv[i], s.message().c_str());
      return 1;
    }
    std::printf("| %s | %zu | %llu | %llu | %.0f | %.0f |", argv[i], dec.points().size(),
                static_cast<unsigned long long>(cells), static_cast<unsigned long long>(wrong_predictions),
                coder5, coder6);
    for (double t : totals) std::printf(" %.0f |", t);
    std::printf("\n");
    std::fflush(stdout);
  }
  return 0;
}
