// The layer coder: the points a layer adds are a set, coded as a binary
// space partition conditioned on the points the decoder already holds (the
// coarser levels). spec/FORMAT.md §3.1 is the normative definition.
//
// The grid's cells are ordered by Morton code (3q bits, x y z interleaved,
// most significant first); a node at depth b is the set of codes sharing a
// b-bit prefix, and its two children split it by the next bit. For a node
// holding n >= 1 new points and k known ones (k0, k1 in its children, known
// to both sides), the coder sends n0, the new points in the first child:
// - n = 1 and k = 0 (a lone point): each axis's remaining bits, raw in
//   format 2; in format 3 first an adaptive bit saying whether the value is
//   one the stream has already used on that axis, then its rank among those
//   values or among the others (grids, extrusions and CAD parts repeat
//   coordinates: torus_10k's rings -20%, fandisk -3%, TetGen interiors +-0);
// - n = 1 and k > 0: one adaptive bit, context (class(k0), class(k1));
// - 2 <= n <= 12: n0 by bisection of [0, n], adaptive bits with context
//   (n, the split the known points predict, the node tree position);
// - n > 12: n0 minus the known points' prediction, zigzag Exp-Golomb with
//   adaptive prefix bits.
// Known points make the coder follow the object's density (a finer level
// fills the same volume as the coarser one, at the same grading): measured,
// 2-4% of a stream. Most of a stream is the raw low bits of lone points,
// below the sampling spacing (docs/STREAM_SIZE.md). The models carry over
// from layer to layer of one stream.
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include "common/grid.h"
#include "common/status.h"

namespace dtm {

using MortonCode = unsigned __int128;

MortonCode morton_encode(const GridPoint& p, int qbits);
GridPoint morton_decode(MortonCode code, int qbits);

// The adaptive models of one stream: created at the stream's start, updated
// by every layer in stream order, identically by encoder and decoder.
class SetCoderModels {
 public:
  SetCoderModels();
  // Format 3: lone points' coordinates may be sent as values the stream has
  // already used (§3.1). Call before the first layer, with the stream's qbits.
  void enable_coordinate_reuse(int qbits);
  // Format 7.0: points a layer sends outside the set coder (beside
  // candidates, codec/sections/candidate_coder.h) count as used coordinates, as the
  // set coder's own do; noted before the layer's payload.
  void note_points(std::span<const GridPoint> points);
  // A copy, for an encoder that tries a layer two ways and keeps one.
  SetCoderModels clone() const;
  ~SetCoderModels();
  SetCoderModels(SetCoderModels&&) noexcept;
  SetCoderModels& operator=(SetCoderModels&&) noexcept;
  struct Tables;
  Tables& tables() { return *tables_; }

 private:
  std::unique_ptr<Tables> tables_;
};

// Where a payload's traversal starts: the root, or (8.0, a brick's chunk)
// the octree node of depth `depth` (Morton bits, a multiple of 3) whose
// codes start at `base`; every point, new or known, lies in it.
struct PointSetNode {
  int depth = 0;
  MortonCode base = 0;
};

// Known points: ascending Morton codes of every point of the coarser levels
// (in the node). New points: distinct, none of them known, any order.
std::vector<uint8_t> encode_point_set(std::span<const MortonCode> known, std::span<const GridPoint> points,
                                      int qbits, SetCoderModels& models, PointSetNode start = {});

// Decodes exactly `count` new points, appending them in Morton order. Rejects
// (kCorrupt) a payload that does not describe `count` distinct points none of
// which is known, or that does not end exactly where its bytes do. `models`
// are left in an unspecified state after an error.
Status decode_point_set(std::span<const uint8_t> payload, std::span<const MortonCode> known, int qbits,
                        uint32_t count, SetCoderModels& models, std::vector<GridPoint>& out,
                        PointSetNode start = {});

// Merges ascending `added` codes into ascending `known`.
void merge_known(std::vector<MortonCode>& known, std::span<const GridPoint> added, int qbits);

// The fewest payload bytes a layer of `count` points takes: the range coder's
// final flush (4 bytes) when count > 0. Adaptive coding can make a point cost
// far less than a bit, so counts are not bounded by payload size; the decoder
// grows its output as points are decoded, never to the claimed count.
inline uint64_t min_payload_bytes(uint64_t count) { return count > 0 ? 4 : 0; }

}  // namespace dtm
