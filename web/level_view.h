// What a viewer needs of each decoded level, made as the level completes:
// the carved cells with their neighbours (for a cut through the solid or
// shrunken cells) and their regions, the boundary surface, the boundary
// flags, and the new vertices' positions and values as floats ready for a
// GPU buffer.
//
// The same code runs natively (tests, the equivalence check's reference) and
// in the WebAssembly decoder the browser viewer uses (web/wasm/): one
// decoder, so the page shows what meshdec writes.
#pragma once

#include <array>
#include <cstdint>
#include <deque>
#include <span>
#include <string>
#include <vector>

#include "codec/decode.h"
#include "common/status.h"

namespace dtm {

struct LevelView {
  int level = 0;
  uint32_t vertices = 0;                       // the level is the first `vertices` of the decoder's points
  uint32_t first_new = 0;                      // its layer's points are [first_new, vertices)
  uint64_t stream_bytes = 0;                   // bytes of the stream up to the end of its layer
  std::vector<std::array<uint32_t, 4>> cells;  // the carved cells, positively oriented
  // cell_neighbors[c][i]: the carved cell across the face of c opposite its
  // vertex i, or -1 when that face is on the level's boundary.
  std::vector<std::array<int32_t, 4>> cell_neighbors;
  // Per cell, its region: 1 + its index in the decoder's regions() (1 in a
  // stream without regions).
  std::vector<uint8_t> cell_regions;
  // Faces of exactly one carved cell, normal pointing out (right-hand rule):
  // the surface meshdec writes as PLY or OFF, in another order.
  std::vector<std::array<uint32_t, 3>> surface;
  std::vector<uint8_t> surface_regions;  // per face, its cell's region
  std::vector<uint8_t> boundary;         // per vertex of the level (mesh/topology.h)
  // The layer's points in input units, minus the grid's centre (floats keep
  // every grid point of up to 24 bits exactly), x y z each.
  std::vector<float> new_positions;
  // Per field, the layer's points' values, every component, vertex-major.
  std::vector<std::vector<float>> new_values;
};

// The stream's grid centre in input units: what new_positions are relative to.
std::array<double, 3> grid_centre(const Grid& grid);

// Feeds a stream to a ProgressiveDecoder and makes a LevelView of every level
// it completes, queued until taken: one chunk may complete several levels,
// and the decoder shows only the finest after feed() returns.
class LevelViewer {
 public:
  explicit LevelViewer(DecoderOptions options = {});

  // ok, or the error that stopped decoding (a damaged layer, or a level whose
  // mesh cannot be made); the levels queued before it stand.
  Status feed(std::span<const uint8_t> bytes);
  // At the end of the input: ok (every level), kTruncated (the input stopped
  // after a whole level or earlier) or the error.
  Status finish() const;

  bool has_level() const { return !ready_.empty(); }
  LevelView take_level();  // the oldest queued level; has_level() must hold

  const ProgressiveDecoder& decoder() const { return decoder_; }

 private:
  void make_view(const ProgressiveDecoder& d, const DecodedLevel& level);

  ProgressiveDecoder decoder_;
  std::deque<LevelView> ready_;
  Status error_;
};

// One line of JSON that identifies a level exactly: counts, and XXH3 hashes
// of its points in decoder order, of its carved cell set (codec/stream/format.h's
// cell_set_hash), of its surface (sorted), its boundary flags and each field's
// values as decoded; with regions, each region's label, name, cell count and
// cell set hash, and the surface's faces with their regions. The equivalence test compares the native and the
// WebAssembly lines of every level of every stream.
std::string level_summary_json(const ProgressiveDecoder& decoder, const LevelView& view);
// The summary's last line: how the stream ended ("done", "truncated" or
// "error") and the decoder's message.
std::string end_summary_json(const Status& end);

}  // namespace dtm
