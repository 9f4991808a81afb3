// meshinfo: what a .dtm stream holds, read from its headers (checksums
// verified, no mesh rebuilt); with --stats, each level decoded and measured.
#include <CLI/CLI.hpp>
#include <cstdio>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "codec/decode.h"
#include "codec/format.h"
#include "core/level.h"
#include "tools/stream_input.h"
#include "tools/tool_main.h"

namespace {

constexpr const char* kExamples = R"(
Examples:
  meshinfo bunny.dtm
  meshinfo bunny.dtm --json
  meshinfo bunny.dtm --stats      # also decodes every level: tetrahedra, solid angles)";

struct QualityRow {
  uint64_t tetrahedra = 0;
  dtm::MeshQuality quality;
};

// The paper's quality figures of every level the stream holds, each from its
// own analysis (the level's points carved as the decoder carves them).
std::vector<QualityRow> decode_quality(const std::string& input, std::span<const uint8_t> bytes) {
  std::vector<QualityRow> rows;
  dtm::Status failed;
  dtm::ProgressiveDecoder decoder;
  const dtm::Status st =
      decoder.feed(bytes, [&](const dtm::ProgressiveDecoder& d, const dtm::DecodedLevel& l) {
        if (!failed.ok()) return;
        // The canonical order: the figures' sums come out the same on every run.
        dtm::TetMesh dt = d.delaunay(dtm::IncrementalDelaunay::CellOrder::kCanonical);
        const std::vector<uint8_t> kept = d.carving(dt);
        if (!d.mesh_status().ok()) {
          failed = d.mesh_status();
          return;
        }
        auto level = dtm::analyze_level(d.points(), std::move(dt), {dtm::AlphaKind::kFixed, l.alpha}, kept);
        // Hostile points (too many cells) are refused by name.
        if (!level.ok())
          failed = level.status().with_context("level " + std::to_string(l.level));
        else
          rows.push_back({level->mesh_cells, dtm::mesh_quality(*level)});
      });
  if (!st.ok()) throw std::runtime_error(input + ": " + st.message());
  if (!failed.ok()) throw std::runtime_error(input + ": " + failed.message());
  return rows;
}

// Each field's share of the stream: its value sections in the complete layers.
std::vector<uint64_t> total_field_bytes(const dtm::StreamSummary& s) {
  std::vector<uint64_t> bytes(s.fields.size(), 0);
  for (const auto& l : s.layers)
    for (size_t f = 0; f < l.field_bytes.size(); ++f) bytes[f] += l.field_bytes[f];
  return bytes;
}

nlohmann::json summary_json(const std::string& input, const dtm::StreamSummary& s,
                            const std::vector<QualityRow>& quality) {
  const auto& h = s.header;
  const double step = h.grid.step;
  const bool truncated = s.status.code() == dtm::StatusCode::kTruncated;
  nlohmann::json j;
  j["input"] = input;
  j["version"] = std::to_string(h.version_major) + "." + std::to_string(h.version_minor);
  j["qbits"] = h.grid.qbits;
  j["origin"] = {h.grid.origin[0], h.grid.origin[1], h.grid.origin[2]};
  j["step"] = step;
  j["alpha_policy"] = dtm::to_string(h.alpha_policy);
  j["cell_hashes"] = (h.flags & dtm::kFlagCellHashes) != 0;
  j["carving_corrections"] = (h.flags & dtm::kFlagCarvingCorrections) != 0;
  j["level_count"] = h.level_count;
  j["vertices"] = h.vertex_count;
  j["bytes"] = s.bytes;
  j["bits_per_vertex"] = 8.0 * s.bytes / h.vertex_count;
  j["truncated"] = truncated;
  if (truncated) j["truncation"] = s.status.message();
  const std::vector<uint64_t> field_bytes = total_field_bytes(s);
  j["fields"] = nlohmann::json::array();
  for (size_t f = 0; f < s.fields.size(); ++f) {
    const dtm::FieldDescription& d = s.fields[f];
    j["fields"].push_back({{"name", d.name},
                           {"type", dtm::value_type_name(d.type)},
                           {"components", d.components},
                           {"mode", d.lossy ? "lossy" : "lossless"},
                           {"error_bound", d.error_bound},
                           {"bytes", field_bytes[f]}});
  }
  j["field_table_bytes"] = s.field_table_bytes;
  j["levels"] = nlohmann::json::array();
  for (size_t i = 0; i < s.layers.size(); ++i) {
    const auto& l = s.layers[i];
    const uint64_t layer_bytes = l.size();
    nlohmann::json row = {{"level", l.header.level},
                          {"vertices", l.header.level_vertices},
                          {"new_vertices", l.header.new_vertices},
                          {"carving_bytes", l.header.carving_bytes},
                          {"value_bytes", l.header.value_bytes},
                          {"alpha", l.header.alpha * step},
                          {"layer_bytes", layer_bytes},
                          {"layer_bits_per_new_vertex", 8.0 * layer_bytes / l.header.new_vertices},
                          {"complete", l.complete}};
    if (!s.fields.empty() && l.complete) {
      nlohmann::json per_field = nlohmann::json::object();
      for (size_t f = 0; f < s.fields.size(); ++f) per_field[s.fields[f].name] = l.field_bytes[f];
      row["field_bytes"] = per_field;
    }
    if (h.flags & dtm::kFlagCellHashes) {
      char hex[17];
      std::snprintf(hex, sizeof hex, "%016llx", static_cast<unsigned long long>(l.header.cell_hash));
      row["cell_hash"] = hex;
    }
    if (i < quality.size())
      row.update({{"tetrahedra", quality[i].tetrahedra},
                  {"boundary_vertices", quality[i].quality.boundary_vertices},
                  {"avg_min_solid_angle", quality[i].quality.avg_min_solid_angle},
                  {"min_solid_angle", quality[i].quality.min_solid_angle}});
    j["levels"].push_back(row);
  }
  return j;
}

void print_table(const std::string& input, const dtm::StreamSummary& s,
                 const std::vector<QualityRow>& quality, bool stats) {
  const auto& h = s.header;
  const double step = h.grid.step;
  std::printf("%s: .dtm %u.%u, %u vertices in %u levels, q=%d, step=%.6g, alpha policy %s%s%s\n",
              input.c_str(), h.version_major, h.version_minor, h.vertex_count, h.level_count, h.grid.qbits,
              step, dtm::to_string(h.alpha_policy),
              (h.flags & dtm::kFlagCarvingCorrections) ? ", carving corrections" : ", alpha carving (paper)",
              (h.flags & dtm::kFlagCellHashes) ? ", cell hashes" : "");
  const bool truncated = s.status.code() == dtm::StatusCode::kTruncated;
  std::printf("%llu bytes, %.2f bits per vertex%s\n", static_cast<unsigned long long>(s.bytes),
              8.0 * s.bytes / h.vertex_count,
              truncated ? (", TRUNCATED: " + s.status.message()).c_str() : "");
  const std::vector<uint64_t> field_bytes = total_field_bytes(s);
  for (size_t f = 0; f < s.fields.size(); ++f) {
    const dtm::FieldDescription& d = s.fields[f];
    std::printf("field '%s': %s%s, %s, %llu bytes\n", d.name.c_str(), dtm::value_type_name(d.type),
                d.components > 1 ? (" x " + std::to_string(d.components)).c_str() : "",
                d.lossy ? ("within " + std::to_string(d.error_bound)).c_str() : "lossless",
                static_cast<unsigned long long>(field_bytes[f]));
  }
  std::printf("%5s %9s %9s %11s %11s %9s %9s%s%s\n", "level", "vertices", "new", "alpha", "layer_bytes",
              "bits/new", "carving", s.fields.empty() ? "" : "    values",
              stats ? "      tets  boundary avg_minSA    min_SA" : "");
  for (size_t i = 0; i < s.layers.size(); ++i) {
    const auto& l = s.layers[i];
    const uint64_t layer_bytes = l.size();
    std::printf("%5u %9u %9u %11.5g %11llu %9.2f %9u", l.header.level, l.header.level_vertices,
                l.header.new_vertices, l.header.alpha * step, static_cast<unsigned long long>(layer_bytes),
                8.0 * layer_bytes / l.header.new_vertices, l.header.carving_bytes);
    if (!s.fields.empty()) std::printf(" %9u", l.header.value_bytes);
    if (i < quality.size())
      std::printf(" %9llu %9llu %9.6f %9.3g", static_cast<unsigned long long>(quality[i].tetrahedra),
                  static_cast<unsigned long long>(quality[i].quality.boundary_vertices),
                  quality[i].quality.avg_min_solid_angle, quality[i].quality.min_solid_angle);
    std::printf("%s\n", l.complete ? "" : "  (incomplete)");
  }
}

struct Command {
  std::string input;
  bool json = false, stats = false;
};

void add_options(CLI::App& app, Command& c) {
  app.add_option("input", c.input, ".dtm stream ('-' = standard input)")->required();
  app.add_flag("--json", c.json, "print JSON");
  app.add_flag("--stats", c.stats, "decode every level and add its quality figures");
}

int run(const Command& c) {
  const std::string& input = c.input;
  std::vector<uint8_t> bytes;
  dtm::read_in_chunks(input, [&](std::span<const uint8_t> chunk) {
    bytes.insert(bytes.end(), chunk.begin(), chunk.end());
    return true;
  });
  const dtm::StreamSummary s = dtm::scan_stream(bytes);
  const bool truncated = s.status.code() == dtm::StatusCode::kTruncated;
  if (!s.status.ok() && !truncated) throw std::runtime_error(input + ": " + s.status.message());
  if (s.layers.empty() && truncated && s.bytes < dtm::kHeaderSize)
    throw std::runtime_error(input + ": " + s.status.message());
  const std::vector<QualityRow> quality = c.stats ? decode_quality(input, bytes) : std::vector<QualityRow>{};
  if (c.json)
    std::printf("%s\n", summary_json(input, s, quality).dump(2).c_str());
  else
    print_table(input, s, quality, c.stats);
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  return dtm::tool_main<Command>("meshinfo", "describe a .dtm stream", kExamples, argc, argv, add_options,
                                 run);
}
