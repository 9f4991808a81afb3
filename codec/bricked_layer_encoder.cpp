// A bricked layer's encoder (spec/FORMAT.md §3.5); the decoder's side is
// codec/bricked_layer_decoder.cpp.
#include <algorithm>

#include "codec/bricks.h"
#include "codec/carving_coder.h"
#include "common/parallel_for.h"

namespace dtm {

int choose_brick_depth(std::span<const MortonCode> codes, int qbits, uint64_t target) {
  int best = 0;
  for (int depth = 1; depth <= std::min(qbits, kMaxBrickDepth); ++depth) {
    uint64_t bricks = 0, previous = UINT64_MAX;
    for (const MortonCode c : codes) {
      const uint64_t b = brick_of(c, qbits, depth);
      bricks += b != previous;
      previous = b;
    }
    if (bricks == 0 || codes.size() < target * bricks) break;
    best = depth;
  }
  return best;
}

BrickedLayerBytes encode_bricked_layer(const BrickedLayerInput& in) {
  const int q = in.qbits, depth = in.depth;
  std::vector<MortonCode> codes;
  codes.reserve(in.points.size());
  for (const GridPoint& p : in.points) codes.push_back(morton_encode(p, q));

  // The bricks with new points, and each one's points.
  std::vector<uint64_t> point_bricks;
  std::vector<size_t> first_point;
  for (size_t i = 0; i < codes.size(); ++i) {
    const uint64_t b = brick_of(codes[i], q, depth);
    if (point_bricks.empty() || point_bricks.back() != b) point_bricks.push_back(b), first_point.push_back(i);
  }
  first_point.push_back(codes.size());

  // The bricks that own cells carrying a correction bit.
  std::vector<uint64_t> carving_bricks;
  std::vector<std::vector<uint8_t>> carving_sections;
  if (in.dt && !in.kept.empty()) {
    std::vector<MortonCode> vertex_codes(in.level_points.size());
    for (size_t v = 0; v < vertex_codes.size(); ++v) vertex_codes[v] = morton_encode(in.level_points[v], q);
    const std::vector<uint64_t> owner =
        carving_bricks_of_cells(*in.dt, in.level_points, vertex_codes, q, depth, in.kept_radius);
    carving_bricks = owner;
    std::erase(carving_bricks, kNoBrick);
    std::sort(carving_bricks.begin(), carving_bricks.end());
    carving_bricks.erase(std::unique(carving_bricks.begin(), carving_bricks.end()), carving_bricks.end());
    std::vector<uint32_t> chunk_of_cell(owner.size(), kNoCarvingChunk);
    for (size_t c = 0; c < owner.size(); ++c)
      if (owner[c] != kNoBrick)
        chunk_of_cell[c] =
            static_cast<uint32_t>(std::lower_bound(carving_bricks.begin(), carving_bricks.end(), owner[c]) -
                                  carving_bricks.begin());
    carving_sections = encode_carving_chunks(*in.dt, in.level_points, in.alpha, in.kept, chunk_of_cell,
                                             carving_bricks.size());
  }

  // Payloads: the base layer's one chunk with the stream's models (which it
  // leaves as every later chunk's start), each later chunk from those.
  std::vector<std::vector<uint8_t>> payloads(point_bricks.size());
  const bool base = in.known.empty();
  parallel_for(
      point_bricks.size(),
      [&](size_t i) {
        const std::span<const GridPoint> points(in.points.data() + first_point[i],
                                                first_point[i + 1] - first_point[i]);
        const std::span<const MortonCode> known = known_in_brick(in.known, point_bricks[i], q, depth);
        const PointSetNode node = brick_node(point_bricks[i], q, depth);
        if (base) {
          payloads[i] = encode_point_set(known, points, q, *in.models, node);
          return;
        }
        SetCoderModels models = chunk_models(*in.models, known, q);
        payloads[i] = encode_point_set(known, points, q, models, node);
      },
      base ? SIZE_MAX : 2);

  // The chunks: every brick with points or corrections, ascending.
  BrickedLayerBytes out;
  std::vector<BrickChunk> chunks;
  size_t p = 0, c = 0;
  while (p < point_bricks.size() || c < carving_bricks.size()) {
    const uint64_t brick = std::min(p < point_bricks.size() ? point_bricks[p] : UINT64_MAX,
                                    c < carving_bricks.size() ? carving_bricks[c] : UINT64_MAX);
    BrickChunk chunk;
    chunk.brick = brick;
    const size_t start = out.chunks.size();
    if (p < point_bricks.size() && point_bricks[p] == brick) {
      chunk.new_points = static_cast<uint32_t>(first_point[p + 1] - first_point[p]);
      chunk.payload_bytes = static_cast<uint32_t>(payloads[p].size());
      out.chunks.insert(out.chunks.end(), payloads[p].begin(), payloads[p].end());
      out.payload_bytes += payloads[p].size();
      ++p;
    }
    if (c < carving_bricks.size() && carving_bricks[c] == brick) {
      chunk.carving_bytes = static_cast<uint32_t>(carving_sections[c].size());
      out.chunks.insert(out.chunks.end(), carving_sections[c].begin(), carving_sections[c].end());
      out.carving_bytes += carving_sections[c].size();
      ++c;
    }
    if (chunk.size() == 0) continue;  // a brick whose cells alpha carves right
    chunk.checksum = chunk_checksum(std::span(out.chunks).subspan(start));
    chunks.push_back(chunk);
  }
  out.chunk_count = chunks.size();
  out.index = write_brick_index(chunks);
  return out;
}

}  // namespace dtm
