// What a .dtm stream holds, as meshinfo shows it and the Python package's
// dtmesh.info() returns it: the headers' figures (checksums verified, no
// mesh rebuilt) and, on request, every level decoded and measured.
#pragma once

#include <cstdint>
#include <nlohmann/json.hpp>
#include <span>
#include <string>
#include <vector>

#include "codec/stream/format.h"
#include "core/level.h"

namespace dtm {

// One level's quality figures, from its own analysis (the level's points
// carved as the decoder carves them).
struct QualityRow {
  uint64_t tetrahedra = 0;
  MeshQuality quality;
};

// scan_stream() with meshinfo's refusals: throws std::runtime_error naming
// `input` for a damaged or foreign stream, or one too short for a header.
// A truncated stream is returned, its status saying so.
StreamSummary scan_for_info(const std::string& input, std::span<const uint8_t> bytes);

// Every level the stream holds, decoded and measured (coarsest first).
// Throws std::runtime_error naming `input` if a level cannot be decoded.
std::vector<QualityRow> decode_quality(const std::string& input, std::span<const uint8_t> bytes);

// Each field's share of the stream: its value sections in the complete layers.
std::vector<uint64_t> total_field_bytes(const StreamSummary& s);

// meshinfo --json (and --stats when `quality` has the rows). The field
// names are a contract: other tools read them.
nlohmann::json summary_json(const std::string& input, const StreamSummary& s,
                            const std::vector<QualityRow>& quality);

}  // namespace dtm
