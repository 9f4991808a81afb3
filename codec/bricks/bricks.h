// Bricked layers (format 8.0, header flag `bricks`; spec/FORMAT.md §3.5):
// each layer's new points and carving corrections are grouped by the octree
// nodes of one depth (bricks: contiguous Morton ranges), one separately
// addressable chunk per brick, listed in the layer's index. A chunk decodes
// from the base layer and the coarser layers' points inside its brick alone,
// so that a reader decodes a region from the chunks around it
// (codec/region_decode.h) and the chunks of a layer decode on every core.
// What encoder, decoder and region reader share is defined here once.
#pragma once

#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include "codec/stream/format.h"
#include "codec/stream/layer_coder.h"
#include "common/grid.h"
#include "common/status.h"
#include "mesh/delaunay.h"

namespace dtm {

// One chunk of a bricked layer's index, in ascending brick order.
struct BrickChunk {
  uint64_t brick = 0;  // the brick's Morton prefix (3 x depth bits)
  uint32_t new_points = 0;
  uint32_t payload_bytes = 0;
  uint32_t carving_bytes = 0;
  uint32_t value_bytes = 0;  // with the stream's flag values: the chunk's value section
  // Low 32 bits of XXH3-64 of the chunk's bytes before its cell values.
  uint32_t checksum = 0;
  uint32_t region_bytes = 0;  // with the stream's flag regions (15.0): its cells' regions
  uint32_t face_bytes = 0;    // with the stream's flag faces (17.0): its cells' faces' tags
  // With flag cell_data, in level 0's layer (16.0): its cells' values and
  // their own checksum (0 without them), so that a reader that needs only
  // the chunk's points reads and checks the bytes before them.
  uint32_t cell_value_bytes = 0, cell_value_checksum = 0;
  // Not stored, derived while parsing:
  uint64_t offset = 0;         // of the chunk from the start of the layer's chunk area
  uint64_t points_before = 0;  // new points of the layer in the chunks before this one
  uint64_t size() const { return points_size() + cell_value_bytes; }
  // The bytes before its cell values: what a reader of its points reads.
  uint64_t points_size() const {
    return uint64_t{payload_bytes} + carving_bytes + value_bytes + region_bytes + face_bytes;
  }
};

// A chunk's bytes: its payload (the layer coder from the brick's node), its
// carving corrections, its values, its kept cells' regions, their faces'
// tags, their values.
// `bytes`: the whole chunk, or its points_size() bytes (cell values empty).
struct ChunkBytes {
  std::span<const uint8_t> payload, carving, values, regions, faces, cell_values;
};
ChunkBytes split_chunk(const BrickChunk& chunk, std::span<const uint8_t> bytes);

// Which of the optional sizes a layer's index entries hold: region_bytes
// with the stream's flag regions, face_bytes with flag faces,
// cell_value_bytes with flag cell_data in level 0's layer.
struct IndexFields {
  bool regions = false, faces = false, cell_values = false;
};
IndexFields index_fields(uint16_t stream_flags, int level);

// The index's layout: write_brick_index (brick_index_encoder.h).
// Parses and checks an index against its layer (of level `level`): bricks
// ascending and below 8^depth, the new points adding up to new_vertices and
// the chunk sizes to chunk_bytes, no empty chunk, a payload of at least the
// range coder's flush for a chunk of points, and none for a chunk without;
// carving bytes only with the stream's flag carving_corrections; with flag
// values, value bytes in every chunk with points and in no other, without
// it in none; region bytes only with flag regions, face bytes only with
// flag faces, cell value bytes only
// with flag cell_data in level 0's layer, and a cell value checksum of 0
// without them. Allocates in proportion to the index's bytes only.
Status parse_brick_index(std::span<const uint8_t> index, int depth, int qbits, uint64_t new_vertices,
                         uint64_t chunk_bytes, uint16_t stream_flags, int level,
                         std::vector<BrickChunk>& out);
// The chunk of `brick`, or nullptr.
const BrickChunk* find_chunk(std::span<const BrickChunk> chunks, uint64_t brick);
// Low 32 bits of XXH3-64 of a chunk's bytes.
uint32_t chunk_checksum(std::span<const uint8_t> bytes);

inline uint64_t brick_of(MortonCode code, int qbits, int depth) {
  return static_cast<uint64_t>(code >> (3 * (qbits - depth)));
}
inline PointSetNode brick_node(uint64_t brick, int qbits, int depth) {
  return {3 * depth, MortonCode{brick} << (3 * (qbits - depth))};
}

GridBox brick_box(uint64_t brick, int qbits, int depth);
// The bricks of depth `depth` that meet `box`, ascending, and the box they
// cover together.
std::vector<uint64_t> bricks_meeting(const GridBox& box, int qbits, int depth, GridBox* covered = nullptr);

// Who codes each cell's carving correction in a bricked layer: the brick
// that holds the cell's vertex of smallest Morton code, and only for a cell
// whose circumradius (HIERARCHY.md §2's) is at most the layer's kept_radius:
// a larger cell is never kept and costs no bit (kNoBrick). `codes`: each
// vertex's Morton code.
inline constexpr uint64_t kNoBrick = UINT64_MAX;
std::vector<uint64_t> carving_bricks_of_cells(const TetMesh& dt, std::span<const GridPoint> points,
                                              std::span<const MortonCode> codes, int qbits, int depth,
                                              double kept_radius);

// Per point, its rank in the ascending order of `codes` (distinct): the
// order in which a bricked layer's carving chunks visit their cells
// (codec/sections/carving_coder.h), the same for the whole level and for any part
// of it.
std::vector<uint32_t> morton_ranks(std::span<const MortonCode> codes);

// The coder state every chunk of a bricked layer starts from: the set
// coder's models as the base layer (one chunk, depth 0) leaves them, plus the
// coordinates of the coarser levels' points inside the chunk's brick
// (spec/FORMAT.md §3.5). Models learnt within one brick go no further.
SetCoderModels chunk_models(const SetCoderModels& after_base, std::span<const MortonCode> known_in_brick,
                            int qbits);
// The Morton codes of `known` (ascending) inside a brick.
std::span<const MortonCode> known_in_brick(std::span<const MortonCode> known, uint64_t brick, int qbits,
                                           int depth);

// Decoder: checks a chunk's bytes against its checksums (kCorrupt, naming
// the brick and `at`, the chunk's first byte in the stream): the whole
// chunk, or its points_size() bytes alone.
Status check_chunk(const BrickChunk& chunk, std::span<const uint8_t> bytes, uint64_t at);
// Decodes one chunk's new points (ascending Morton code), appending them to
// `out`. `known`: every point of V_{l+1} the caller holds in the brick (at
// least); `after_base`: the models as the base layer left them.
Status decode_chunk_points(const BrickChunk& chunk, std::span<const uint8_t> payload,
                           std::span<const MortonCode> known, int qbits, int depth,
                           const SetCoderModels& after_base, std::vector<GridPoint>& out);
// Chunks of one layer with their bytes, in ascending brick order: all of
// them (the whole decoder) or those a region needs.
struct ChunkInput {
  const BrickChunk* chunk = nullptr;
  std::span<const uint8_t> bytes;
  uint64_t at = 0;  // its first byte in the stream (what a damage names)
};
// The chunks checked, then decoded on every core; their points appended to
// `out` in ascending Morton order. The base layer (known empty) decodes with
// `models` and leaves them as the later chunks' start; a later layer only
// reads them.
Status decode_bricked_points(std::span<const ChunkInput> chunks, std::span<const MortonCode> known, int qbits,
                             int depth, SetCoderModels& models, std::vector<GridPoint>& out);

// The values of a layer's chunks (their points `added`, in the chunks'
// order), each chunk's decoded from the points of the coarser levels in its
// brick (found among `known_points`, whose values `known_values` holds, in
// any order) and its own (codec/sections/value_fields.h), on every core; one
// FieldValues per field in `out`.
Status decode_bricked_values(std::span<const ChunkInput> chunks, int qbits, int depth,
                             std::span<const FieldDescription> fields,
                             std::span<const GridPoint> known_points,
                             std::span<const FieldValues> known_values, std::span<const GridPoint> added,
                             std::vector<FieldValues>& out);

// Encoder (dtm_encoder, chunk_encoder.cpp; the decoder's side above is
// chunk_decoder.cpp).
// The deepest brick depth (at most kMaxBrickDepth and qbits) at which the
// layer's points fill their bricks with `target` points on average; 0 when
// none does. `codes`: the layer's, ascending.
int choose_brick_depth(std::span<const MortonCode> codes, int qbits, uint64_t target);
// One chunk's new points (ascending Morton code, all in `brick`) coded as
// decode_chunk_points reads them: `known` as there, `after_base` the models
// the base layer left.
std::vector<uint8_t> encode_chunk_points(std::span<const GridPoint> points, std::span<const MortonCode> known,
                                         uint64_t brick, int qbits, int depth,
                                         const SetCoderModels& after_base);
// What the encoder made of one brick of a layer: its new points' count,
// payload and value section (empty without points), its carving
// corrections (empty when alpha is right there), its kept cells' regions
// (empty with one region, or none kept), their faces' tags (empty when
// none has a tag) and values (level 0's, with cell data; empty when none
// is kept).
struct BrickParts {
  uint64_t brick = 0;
  uint32_t new_points = 0;
  std::vector<uint8_t> payload, carving, values, regions, faces, cell_values;
};
// The layer's chunks from its bricks' parts (ascending bricks, each once):
// one chunk, with its checksum, for every brick with points, corrections,
// regions, tagged faces or cell values, its bytes (payload, carving,
// values, regions, faces, cell values) appended to `chunk_bytes`.
std::vector<BrickChunk> write_chunks(std::span<const BrickParts> parts, std::vector<uint8_t>& chunk_bytes);

}  // namespace dtm
