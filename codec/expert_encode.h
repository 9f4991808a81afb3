// The expert's encoder: a built hierarchy -> .dtm bytes. codec/encode.h is
// the one-call path (quantize, build the hierarchy, encode); this header is
// for callers who build or adjust the hierarchy themselves.
//
//   auto q = quantize(points, 14);
//   auto h = build_hierarchy(q->points, hierarchy_options);
//   auto stream = encode_stream(*h, q->points, q->grid, hierarchy_options.alpha.kind);
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "common/grid.h"
#include "common/status.h"
#include "core/hierarchy.h"
#include "core/quantize.h"
#include "mesh/carving.h"

namespace dtm {

struct StreamOptions {
  // Store each level's canonical cell-set hash, so that a decoder built
  // against another CGAL can prove it rebuilt the same meshes (meshdec --verify).
  bool cell_hashes = false;
  // Stream every level_step-th level of the hierarchy (levels 0, s, 2s, ...)
  // and its coarsest: fewer, larger layers cost fewer bits (each layer's
  // points are coded given the coarser ones, and deciding which layer a point
  // belongs to is what costs) at the price of fewer levels of detail. The
  // stream numbers its levels 0, 1, 2, ... in that order.
  int level_step = 1;
};

struct EncodedStream {
  std::vector<uint8_t> bytes;
  // Bytes of each hierarchy level's layer (header included), indexed by
  // hierarchy level; 0 for a level left out by level_step.
  std::vector<uint64_t> layer_bytes;
  // Of those, the carving corrections' (spec/FORMAT.md §3.2).
  std::vector<uint64_t> carving_bytes;
  // The hierarchy level of each stream level (finest first).
  std::vector<int> streamed_levels;
  // The order in which a decoder produces the vertices (coarsest layer
  // first, ascending Morton code within a layer): decode_order[i] is the
  // index into `points` of the decoder's vertex i.
  std::vector<uint32_t> decode_order;
};

// `points` are the grid points the hierarchy's vertex indices refer to.
// kInvalidInput if the levels are not nested, level_step < 1 or there are
// more than 65535 levels to stream.
StatusOr<EncodedStream> encode_stream(const Hierarchy& hierarchy, std::span<const GridPoint> points,
                                      const Grid& grid, AlphaKind alpha_policy,
                                      const StreamOptions& options = {});

}  // namespace dtm
