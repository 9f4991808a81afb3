#include "tools/stream_info.h"

#include <cstdio>
#include <stdexcept>

#include "codec/decode.h"

namespace dtm {

StreamSummary scan_for_info(const std::string& input, std::span<const uint8_t> bytes) {
  StreamSummary s = scan_stream(bytes);
  const bool truncated = s.status.code() == StatusCode::kTruncated;
  if (!s.status.ok() && !truncated) throw std::runtime_error(input + ": " + s.status.message());
  if (s.layers.empty() && truncated && s.bytes < kHeaderSize)
    throw std::runtime_error(input + ": " + s.status.message());
  return s;
}

// The paper's quality figures of every level the stream holds, each from its
// own analysis (the level's points carved as the decoder carves them).
std::vector<QualityRow> decode_quality(const std::string& input, std::span<const uint8_t> bytes) {
  std::vector<QualityRow> rows;
  Status failed;
  ProgressiveDecoder decoder;
  const Status st = decoder.feed(bytes, [&](const ProgressiveDecoder& d, const DecodedLevel& l) {
    if (!failed.ok()) return;
    // The canonical order: the figures' sums come out the same on every run.
    TetMesh dt = d.delaunay(IncrementalDelaunay::CellOrder::kCanonical);
    std::vector<uint8_t> kept = d.carving(dt);
    if (d.exact_level()) {  // level 0 of an exact stream: the input's cells, the fill's last
      ProgressiveDecoder::LevelCells exact = d.level_cells();
      dt = std::move(exact.mesh);
      kept = std::move(exact.kept);
    }
    if (!d.mesh_status().ok()) {
      failed = d.mesh_status();
      return;
    }
    auto level = analyze_level(d.points(), std::move(dt), {AlphaKind::kFixed, l.alpha}, kept);
    // Hostile points (too many cells) are refused by name.
    if (!level.ok())
      failed = level.status().with_context("level " + std::to_string(l.level));
    else
      rows.push_back({level->mesh_cells, mesh_quality(*level)});
  });
  if (!st.ok()) throw std::runtime_error(input + ": " + st.message());
  if (!failed.ok()) throw std::runtime_error(input + ": " + failed.message());
  return rows;
}

// Each field's share of the stream: its value sections in the complete layers.
std::vector<uint64_t> total_field_bytes(const StreamSummary& s) {
  std::vector<uint64_t> bytes(s.fields.size(), 0);
  for (const auto& l : s.layers)
    for (size_t f = 0; f < l.field_bytes.size(); ++f) bytes[f] += l.field_bytes[f];
  return bytes;
}

nlohmann::json summary_json(const std::string& input, const StreamSummary& s,
                            const std::vector<QualityRow>& quality) {
  const auto& h = s.header;
  const double step = h.grid.step;
  const bool truncated = s.status.code() == StatusCode::kTruncated;
  nlohmann::json j;
  j["input"] = input;
  j["version"] = std::to_string(h.version_major) + "." + std::to_string(h.version_minor);
  j["qbits"] = h.grid.qbits;
  j["origin"] = {h.grid.origin[0], h.grid.origin[1], h.grid.origin[2]};
  j["step"] = step;
  j["alpha_policy"] = to_string(h.alpha_policy);
  j["cell_hashes"] = (h.flags & kFlagCellHashes) != 0;
  j["carving_corrections"] = (h.flags & kFlagCarvingCorrections) != 0;
  j["bricks"] = (h.flags & kFlagBricks) != 0;
  j["vertex_order"] = (h.flags & kFlagVertexOrder) != 0;
  j["exact"] = (h.flags & kFlagExact) != 0;
  j["edge_nodes"] = (h.flags & kFlagEdgeNodes) != 0;
  j["node_labels"] = (h.flags & kFlagNodeLabels) != 0;
  j["level_count"] = h.level_count;
  j["vertices"] = h.vertex_count;
  j["bytes"] = s.bytes;
  j["bits_per_vertex"] = 8.0 * s.bytes / h.vertex_count;
  j["truncated"] = truncated;
  if (truncated) j["truncation"] = s.status.message();
  const std::vector<uint64_t> field_bytes = total_field_bytes(s);
  j["fields"] = nlohmann::json::array();
  for (size_t f = 0; f < s.fields.size(); ++f) {
    const FieldDescription& d = s.fields[f];
    j["fields"].push_back({{"name", d.name},
                           {"type", value_type_name(d.type)},
                           {"components", d.components},
                           {"mode", d.lossy ? "lossy" : "lossless"},
                           {"error_bound", d.error_bound},
                           {"bytes", field_bytes[f]}});
    // (19.0: its values at level 0's edge nodes.)
    uint64_t edge = 0;
    for (const auto& l : s.layers)
      if (f < l.edge_field_bytes.size()) edge += l.edge_field_bytes[f];
    if (s.header.flags & kFlagEdgeNodes) j["fields"].back()["edge_value_bytes"] = edge;
  }
  j["field_table_bytes"] = s.field_table_bytes;
  j["regions"] = nlohmann::json::array();
  for (const RegionLabel& r : s.regions) j["regions"].push_back({{"label", r.label}, {"name", r.name}});
  j["region_table_bytes"] = s.region_table_bytes;
  j["face_tags"] = nlohmann::json::array();
  for (const RegionLabel& t : s.face_tags) j["face_tags"].push_back({{"label", t.label}, {"name", t.name}});
  j["face_table_bytes"] = s.face_table_bytes;
  // Level 0's cell data (10.0): each array's share of its section.
  std::vector<uint64_t> cell_bytes(s.cell_fields.size(), 0);
  for (const auto& l : s.layers)
    for (size_t f = 0; f < l.cell_field_bytes.size() && f < cell_bytes.size(); ++f)
      cell_bytes[f] += l.cell_field_bytes[f];
  j["cell_fields"] = nlohmann::json::array();
  for (size_t f = 0; f < s.cell_fields.size(); ++f) {
    const FieldDescription& d = s.cell_fields[f];
    j["cell_fields"].push_back({{"name", d.name},
                                {"type", value_type_name(d.type)},
                                {"components", d.components},
                                {"mode", d.lossy ? "lossy" : "lossless"},
                                {"error_bound", d.error_bound},
                                {"bytes", cell_bytes[f]}});
  }
  j["cell_field_table_bytes"] = s.cell_field_table_bytes;
  j["levels"] = nlohmann::json::array();
  for (size_t i = 0; i < s.layers.size(); ++i) {
    const auto& l = s.layers[i];
    const uint64_t layer_bytes = l.size();
    nlohmann::json row = {{"level", l.header.level},
                          {"vertices", l.header.level_vertices},
                          {"new_vertices", l.header.new_vertices},
                          {"carving_bytes", l.header.carving_bytes},
                          {"value_bytes", l.header.value_bytes},
                          {"region_bytes", l.header.region_bytes},
                          {"face_bytes", l.header.face_bytes},
                          {"cell_value_bytes", l.header.cell_value_bytes},
                          {"order_bytes", l.header.order_bytes},
                          {"exact_bytes", l.header.exact_bytes},
                          {"edge_node_bytes", l.header.edge_node_bytes},
                          {"edge_value_bytes", l.header.edge_value_bytes},
                          {"node_order_bytes", l.header.node_order_bytes},
                          {"node_label_bytes", l.header.node_label_bytes},
                          {"candidate_kinds", l.header.candidate_kinds},
                          {"candidate_bytes", l.header.candidate_bytes},
                          {"alpha", l.header.alpha * step},
                          {"layer_bytes", layer_bytes},
                          {"layer_bits_per_new_vertex", 8.0 * layer_bytes / l.header.new_vertices},
                          {"complete", l.complete}};
    // (An incomplete layer's sizes are those its header announces; the
    // stream holds the first bytes_present of them.)
    if (!l.complete) row["bytes_present"] = std::min(layer_bytes, s.bytes - std::min(s.bytes, l.offset));
    if (l.header.bricked)
      row.update({{"brick_depth", l.header.brick_depth},
                  {"chunks", l.chunks},
                  {"index_bytes", l.header.index_bytes},
                  {"kept_radius", l.header.kept_radius * step}});
    if (!s.fields.empty() && l.complete) {
      nlohmann::json per_field = nlohmann::json::object();
      for (size_t f = 0; f < s.fields.size(); ++f) per_field[s.fields[f].name] = l.field_bytes[f];
      row["field_bytes"] = per_field;
    }
    if (h.flags & kFlagCellHashes) {
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

}  // namespace dtm
