// The stream's writers: its header and each layer, field by field with
// their checksums. In the encoder library: a decoder-only program holds
// none of them (codec/CMakeLists.txt).
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "codec/stream/format.h"

namespace dtm {

std::vector<uint8_t> write_header(StreamHeader h);

// The layer header (checksum computed) followed by the candidate section
// (7.0 and later), the payload, the carving section (4.0 and later), the
// region and face sections (9.0), the value section (5.0 and later) and the
// cell value section (10.0).
std::vector<uint8_t> write_layer(LayerHeader h, std::span<const uint8_t> payload,
                                 std::span<const uint8_t> carving = {}, std::span<const uint8_t> values = {},
                                 std::span<const uint8_t> candidates = {},
                                 std::span<const uint8_t> regions = {}, std::span<const uint8_t> faces = {},
                                 std::span<const uint8_t> cell_values = {},
                                 std::span<const uint8_t> order = {}, std::span<const uint8_t> exact = {},
                                 std::span<const uint8_t> edge_nodes = {},
                                 std::span<const uint8_t> edge_values = {},
                                 std::span<const uint8_t> node_order = {},
                                 std::span<const uint8_t> node_labels = {});

// Writes a bricked layer (8.0): the header (index_bytes, chunk_bytes and
// the checksum computed), the index, the chunks.
std::vector<uint8_t> write_bricked_layer(LayerHeader h, std::span<const uint8_t> index,
                                         std::span<const uint8_t> chunks);

}  // namespace dtm
