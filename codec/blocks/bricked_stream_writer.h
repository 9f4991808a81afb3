// The bytes of a bricked stream (format 8.0, spec/FORMAT.md §3.5) once its
// levels are built (codec/blocks/bricked_encoder.h): the header, the field
// table, and each level's layer, coarsest first, its bricks' points and
// values coded by the ranks in turn, put together with the carving
// corrections the blocks made into chunks (codec/bricks/bricks.h).
#pragma once

#include <cstdint>
#include <map>
#include <span>
#include <vector>

#include "codec/blocks/block_levels.h"
#include "codec/blocks/bricked_encoder.h"
#include "codec/sections/region_coder.h"
#include "codec/sections/value_fields.h"
#include "common/exchange.h"
#include "common/grid.h"
#include "common/progress.h"
#include "common/status.h"
#include "core/hierarchy.h"

namespace dtm {

// What the encoder keeps of a level for the stream.
struct BrickedLevel {
  double alpha = 0, kept_radius = 0;
  int brick_depth = 0;
  std::map<uint64_t, std::vector<uint8_t>> carving;  // per brick
  std::map<uint64_t, std::vector<uint8_t>> regions;  // per brick owning a kept cell, with regions
  std::map<uint64_t, std::vector<uint8_t>> faces;    // per brick tagging a face, with tagged faces
  // Level 0 with cell data: per brick owning a kept cell, its cell value
  // section; each field's bytes in them, and where the cells' values came
  // from (BlockFigures).
  std::map<uint64_t, std::vector<uint8_t>> cell_values;
  std::vector<uint64_t> cell_field_bytes;
  uint64_t cells_from_input = 0, cells_from_nearest = 0;
  uint64_t tagged_faces_kept = 0;  // the input's tagged triangles among its tagged faces
  uint64_t cell_hash = 0;
  LevelStats stats;

  // Adds a block's sections (moved from), its cell fields' bytes and its
  // cells' sources.
  void take_sections(BlockAnalysis& a);
  // Adds a block's face sections (moved from) and its tagged triangles kept.
  void take_faces(BlockAnalysis& a);
  void clear_sections();
};

struct BrickedStreamInput {
  std::span<const GridPoint> points;  // every grid point
  Grid grid;                          // as the stream holds it (the input's units)
  AlphaKind alpha_policy = AlphaKind::kPaper;
  bool cell_hashes = false;
  const FieldSectionEncoder* values = nullptr;  // or none
  std::span<const RegionLabel> regions;         // the region table (2 or more: flag regions), or none
  std::span<const RegionLabel> face_tags;       // the face tag table (flag faces), or none
  // With cell data, the cell field table's (level 0's chunks carry their
  // cells' values, made by the blocks: BrickedLevel::cell_values), or none.
  const FieldSectionEncoder* cell_values = nullptr;
  const MortonIndex* index = nullptr;  // of `points`
  std::span<const uint8_t> level_of;   // per grid point: the coarsest level that holds it
  bool decode_order = true;            // BrickedEncoding::decode_order made (else empty)
  RankExchange* exchange = nullptr;
  PhaseCallback on_phase;
};

// The stream of `levels` (finest first; the coarsest one chunk of depth 0),
// on every rank; with every level's byte counts. The levels' carving and
// regions are moved from.
StatusOr<BrickedEncoding> write_bricked_stream(const BrickedStreamInput& in,
                                               std::vector<BrickedLevel>& levels);

}  // namespace dtm
