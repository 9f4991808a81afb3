// The bytes of a .dtm stream, defined once for the encoder, the decoder and
// meshinfo. spec/FORMAT.md is the normative description; keep them in step.
//
//   stream = header, layer(L), layer(L-1), ..., layer(0)     coarsest first
//   header = 56 bytes (below), ending with its own checksum
//   layer  = 38-byte layer header + payload (the new points of the level)
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <span>
#include <vector>

#include "bitstream/status.h"
#include "core/grid.h"
#include "core/level.h"

namespace dtm {

inline constexpr std::array<uint8_t, 8> kMagic = {0x89, 'D', 'T', 'M', 0x0D, 0x0A, 0x1A, 0x0A};
inline constexpr uint8_t kVersionMajor = 3;        // what the encoder writes
inline constexpr uint8_t kOldestVersionMajor = 2;  // the decoder also reads 2.x
inline constexpr uint8_t kVersionMinor = 0;
inline constexpr size_t kHeaderSize = 56;
inline constexpr size_t kLayerHeaderSize = 38;
inline constexpr uint16_t kFlagCellHashes = 1;  // each layer carries its level's cell-set hash
inline constexpr uint16_t kKnownFlags = kFlagCellHashes;

struct StreamHeader {
  uint8_t version_major = kVersionMajor;
  uint8_t version_minor = kVersionMinor;
  Grid grid;
  AlphaPolicy::Kind alpha_policy = AlphaPolicy::Kind::kPaper;
  uint16_t flags = 0;
  uint16_t level_count = 0;
  uint32_t vertex_count = 0;  // of the finest level (level 0)
};

struct LayerHeader {
  uint16_t level = 0;
  uint32_t new_vertices = 0;    // points in this layer's payload
  uint32_t level_vertices = 0;  // |V_level| = the coarser level's count + new_vertices
  double alpha = 0;             // grid units
  uint32_t payload_bytes = 0;
  uint64_t cell_hash = 0;       // meaningful with kFlagCellHashes, else 0
  uint64_t checksum = 0;        // XXH3-64 of the first 30 header bytes and the payload
};

std::vector<uint8_t> write_header(const StreamHeader& h);
// Parses and validates the header at the start of `bytes`. kNeedMoreInput if
// fewer than kHeaderSize bytes are given.
Status parse_header(std::span<const uint8_t> bytes, StreamHeader& h);

std::vector<uint8_t> write_layer(LayerHeader h, std::span<const uint8_t> payload);
// Parses a layer header (not its payload) and checks it against the stream
// header and the previous layer (`previous_level_vertices`, 0 for the base).
// `expected_level` is the level this layer must carry.
Status parse_layer_header(std::span<const uint8_t> bytes, const StreamHeader& stream,
                          int expected_level, uint32_t previous_level_vertices, LayerHeader& h);
// True if the layer's checksum matches its header and payload.
bool layer_checksum_ok(std::span<const uint8_t> layer_header_bytes,
                       std::span<const uint8_t> payload, uint64_t checksum);

// What a stream holds, read from its headers without decoding any point
// (meshinfo). Checksums are verified.
struct LayerSummary {
  LayerHeader header;
  uint64_t offset = 0;  // of the layer header in the stream
  bool complete = false;
};
struct StreamSummary {
  StreamHeader header;
  std::vector<LayerSummary> layers;  // coarsest first; the last may be incomplete
  uint64_t bytes = 0;                // bytes given
  Status status;                     // ok, or why the scan stopped early
};
StreamSummary scan_stream(std::span<const uint8_t> bytes);

// A level's canonical cell-set hash: each cell as its four grid points in
// lexicographic order (12 int32, little-endian), cells in lexicographic
// order, XXH3-64 of the concatenation.
uint64_t cell_set_hash(std::span<const GridPoint> points,
                       std::span<const std::array<uint32_t, 4>> cells);

}  // namespace dtm
