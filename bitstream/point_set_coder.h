// The first point-set coder: a layer's points are a set, so they are sent in
// Morton (octree) order as Rice-coded gaps between consecutive Morton codes.
// For n points spread over the 2^(3q) cells of the grid it costs about
// log2(2^(3q) / n) + 1.5 bits per point: close to the size of an unordered
// set drawn uniformly, and blind to the shape (issue 5 makes it small).
//
// Payload: one byte k (the Rice parameter, 0..3q), then for each point, in
// ascending Morton order, gap = code - previous code - 1 (the first point's
// gap is its code) as q = gap >> k in unary (q one bits, then a zero bit)
// and the low k bits of gap, most significant first. Bits fill bytes from
// the most significant bit; the last byte is padded with zero bits.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "bitstream/status.h"
#include "core/grid.h"

namespace dtm {

using MortonCode = unsigned __int128;

MortonCode morton_encode(const GridPoint& p, int qbits);
GridPoint morton_decode(MortonCode code, int qbits);

// Encodes distinct points of a qbits grid, in any order.
std::vector<uint8_t> encode_point_set(std::span<const GridPoint> points, int qbits);

// Decodes exactly `count` points, appending them in Morton order. Rejects
// (kCorrupt) codes outside the grid, a payload that ends early, trailing
// bytes, and non-zero padding.
Status decode_point_set(std::span<const uint8_t> payload, int qbits, uint32_t count,
                        std::vector<GridPoint>& out);

// The fewest payload bytes that `count` points can take: a decoder rejects
// counts the bytes cannot hold before allocating anything for them.
inline uint64_t min_payload_bytes(uint64_t count) { return 1 + (count + 7) / 8; }

}  // namespace dtm
