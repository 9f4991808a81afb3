// The carving corrections of one level (spec/FORMAT.md §3.2), encoder and
// decoder side by side. Alpha predicts which cells of DT(V_l) the level
// keeps (mesh/carving.h); the encoder knows the true verdicts (the reference
// solid's, spec/HIERARCHY.md §3) and sends, for every cell, whether the
// prediction is wrong, as an adaptive binary symbol. The cells are visited
// in a canonical order and the contexts use only what the decoder has: the
// cell's circumradius over alpha and how many of its face neighbours alpha
// keeps. Each level's section is coded alone (fresh models), so a decoder
// reads the sections of the levels it shows and no other.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "common/grid.h"
#include "common/status.h"
#include "mesh/delaunay.h"

namespace dtm {

// Per cell of `dt` (vertex ids index `points`): alpha's verdict and the
// context of its correction; and the canonical order of the cells (each
// cell's ids ascending, cells ascending).
struct CarvingPrediction {
  std::vector<uint8_t> kept;     // per cell: alpha keeps it
  std::vector<uint8_t> context;  // per cell: < kCarvingContexts
  std::vector<uint32_t> order;   // cell indices in coding order
};
inline constexpr int kCarvingRatioBuckets = 16;
inline constexpr int kCarvingContexts = kCarvingRatioBuckets * 5;
CarvingPrediction predict_carving(const TetMesh& dt, std::span<const GridPoint> points, double alpha);

// The section for true verdicts `kept` (per cell of dt); empty when alpha's
// prediction is right everywhere.
std::vector<uint8_t> encode_carving(const TetMesh& dt, std::span<const GridPoint> points, double alpha,
                                    std::span<const uint8_t> kept);

// The level's verdicts, per cell of dt, from its section (empty: alpha's).
// kCorrupt if the section ends before its last symbol or has bytes after it.
// `order`, if given, receives the canonical order of dt's cells (computed on
// the way: the order the section codes them in).
Status decode_carving(std::span<const uint8_t> section, const TetMesh& dt, std::span<const GridPoint> points,
                      double alpha, std::vector<uint8_t>& kept, std::vector<uint32_t>* order = nullptr);

}  // namespace dtm
