// The level table that meshenc prints while it works and writes as JSON.
// The JSON field names are a contract: other tools read them.
#pragma once

#include <cstdio>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "codec/encode.h"
#include "common/grid.h"
#include "core/hierarchy.h"

namespace dtm {

// Column header and one row per level; alpha and errors in (scaled) input units.
// `reference`: the rows have the shape error against the input's solid, both ways.
void print_table_header(std::FILE* out, bool reference);
void print_table_row(std::FILE* out, const LevelReport& level, const Grid& grid);

nlohmann::json level_json(const LevelStats& s, const Grid& grid);
// meshenc --report: `input` names the file encoded.
nlohmann::json report_json(const std::string& input, const EncodeReport& report);

}  // namespace dtm
