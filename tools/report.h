// The level table that meshenc prints while it works and writes as JSON.
// The JSON field names are a contract: other tools read them.
#pragma once

#include <cstdio>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/grid.h"
#include "core/hierarchy.h"

namespace dtm {

struct ReportContext {
  std::string input;
  Grid grid;
  uint64_t duplicates_merged = 0;
  double scale = 1.0;  // input coordinates were multiplied by this before quantization
  std::vector<uint64_t> layer_bytes;  // per level, when a stream was written (0: not streamed)
  std::vector<int> streamed_levels;   // hierarchy level of each stream level
  uint64_t stream_bytes = 0;
};

// Column header and one row per level; alpha and errors in (scaled) input units.
void print_table_header(std::FILE* out);
void print_table_row(std::FILE* out, const LevelStats& s, const Grid& grid);

nlohmann::json level_json(const LevelStats& s, const Grid& grid);
nlohmann::json report_json(const ReportContext& ctx, const std::vector<LevelStats>& levels);

}  // namespace dtm
