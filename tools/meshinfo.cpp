// meshinfo: what a .dtm stream holds, read from its headers (checksums
// verified, no mesh rebuilt); with --stats, each level decoded and measured.
#include <CLI/CLI.hpp>
#include <algorithm>
#include <charconv>
#include <cstdio>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "codec/stream/format.h"
#include "tools/huge_pages.h"
#include "tools/stream_info.h"
#include "tools/stream_input.h"
#include "tools/thread_budget.h"
#include "tools/tool_main.h"

namespace {

// An error bound as its shortest exact text (1e-305 and 1e290 as they are,
// not as %f's zeros or digits).
std::string bound_text(double bound) {
  char text[32];
  const auto end = std::to_chars(text, text + sizeof text, bound).ptr;
  return std::string(text, end);
}

constexpr const char* kExamples = R"(
Examples:
  meshinfo bunny.dtm
  meshinfo bunny.dtm --json
  meshinfo bunny.dtm --stats      # also decodes every level: tetrahedra, solid angles)";

void print_table(const std::string& input, const dtm::StreamSummary& s,
                 const std::vector<dtm::QualityRow>& quality, bool stats) {
  const auto& h = s.header;
  const double step = h.grid.step;
  // (23.0: a stream with both flags may have no node order section.)
  const bool level0_numbers_nodes =
      h.version_major < dtm::kVersionMajorLayerSizesByFlags ||
      (!s.layers.empty() && s.layers.back().header.level == 0 && s.layers.back().header.node_order_bytes > 0);
  const bool numbered_nodes = (h.flags & dtm::kFlagEdgeNodes) && (h.flags & dtm::kFlagVertexOrder) &&
                              h.version_major >= dtm::kVersionMajorNodeOrder && level0_numbers_nodes;
  std::printf("%s: .dtm %u.%u, %u vertices in %u level%s, q=%d, step=%.6g, alpha policy %s%s%s%s%s%s%s%s%s\n",
              input.c_str(), h.version_major, h.version_minor, h.vertex_count, h.level_count,
              h.level_count == 1 ? "" : "s", h.grid.qbits, step, dtm::to_string(h.alpha_policy),
              (h.flags & dtm::kFlagCarvingCorrections) ? ", carving corrections" : ", alpha carving (paper)",
              (h.flags & dtm::kFlagCellHashes) ? ", cell hashes" : "",
              (h.flags & dtm::kFlagBricks) ? ", bricked layers" : "",
              (h.flags & dtm::kFlagVertexOrder) ? ", the input's vertex order" : "",
              (h.flags & dtm::kFlagExact) ? ", level 0 the input's own cells (exact)" : "",
              (h.flags & dtm::kFlagEdgeNodes) ? ", with their edges' nodes (second order)" : "",
              numbered_nodes ? ", in the input's numbering" : "",
              (h.flags & dtm::kFlagNodeLabels) ? ", the input's node ids" : "");
  const bool truncated = s.status.code() == dtm::StatusCode::kTruncated;
  std::printf("%llu bytes, %.2f bits per vertex%s\n", static_cast<unsigned long long>(s.bytes),
              8.0 * s.bytes / h.vertex_count,
              truncated ? (", TRUNCATED: " + s.status.message()).c_str() : "");
  const std::vector<uint64_t> field_bytes = dtm::total_field_bytes(s);
  for (size_t f = 0; f < s.fields.size(); ++f) {
    const dtm::FieldDescription& d = s.fields[f];
    // (19.0: and its values at level 0's edge nodes.)
    uint64_t edge = 0;
    for (const auto& l : s.layers)
      if (f < l.edge_field_bytes.size()) edge += l.edge_field_bytes[f];
    std::printf("field '%s': %s%s, %s, %llu bytes%s\n", d.name.c_str(), dtm::value_type_name(d.type),
                d.components > 1 ? (" x " + std::to_string(d.components)).c_str() : "",
                d.lossy ? ("within " + bound_text(d.error_bound)).c_str() : "lossless",
                static_cast<unsigned long long>(field_bytes[f]),
                edge ? (", and " + std::to_string(edge) + " bytes at the edge nodes").c_str() : "");
  }
  // 9.0: the region table; each layer's region section in its own column.
  for (const dtm::RegionLabel& r : s.regions)
    std::printf("region %d%s\n", r.label, r.name.empty() ? "" : (" \"" + r.name + "\"").c_str());
  for (const dtm::RegionLabel& t : s.face_tags)
    std::printf("face tag %d%s\n", t.label, t.name.empty() ? "" : (" \"" + t.name + "\"").c_str());
  // 10.0: level 0's cell data, from level 0's layer.
  for (size_t f = 0; f < s.cell_fields.size(); ++f) {
    const dtm::FieldDescription& d = s.cell_fields[f];
    uint64_t bytes = 0;
    for (const auto& l : s.layers)
      if (f < l.cell_field_bytes.size()) bytes += l.cell_field_bytes[f];
    std::printf("cell data '%s' (level 0): %s%s, %s, %llu bytes\n", d.name.c_str(),
                dtm::value_type_name(d.type),
                d.components > 1 ? (" x " + std::to_string(d.components)).c_str() : "",
                d.lossy ? ("within " + bound_text(d.error_bound)).c_str() : "lossless",
                static_cast<unsigned long long>(bytes));
  }
  const bool regions = !s.regions.empty();
  const bool faces = !s.face_tags.empty();
  const bool cells = !s.cell_fields.empty();  // level 0's cell values (in its layer's bytes)
  // 7.0: the candidate section's bytes (points sent beside the coarser
  // level's circumcentres and edge midpoints).
  // 8.0 bricked: each layer's chunks and its index's bytes instead.
  const bool bricks = s.header.flags & dtm::kFlagBricks;
  const bool candidates = s.header.version_major >= 7 && !bricks;
  // Level 0's sections of --exact and --keep-order (11.0-22.0), each a
  // column where some layer has its bytes.
  struct Column {
    const char* title;
    uint32_t dtm::LayerHeader::*bytes;
  };
  std::vector<Column> level0_columns;
  for (const Column& c :
       {Column{"exact", &dtm::LayerHeader::exact_bytes}, Column{"order", &dtm::LayerHeader::order_bytes},
        Column{"edge_nodes", &dtm::LayerHeader::edge_node_bytes},
        Column{"edge_values", &dtm::LayerHeader::edge_value_bytes},
        Column{"node_order", &dtm::LayerHeader::node_order_bytes},
        Column{"node_labels", &dtm::LayerHeader::node_label_bytes}})
    if (std::any_of(s.layers.begin(), s.layers.end(), [&](const auto& l) { return l.header.*c.bytes > 0; }))
      level0_columns.push_back(c);
  std::string level0_titles;
  for (const Column& c : level0_columns) {
    char title[16];
    std::snprintf(title, sizeof title, " %11s", c.title);
    level0_titles += title;
  }
  std::printf("%5s %9s %9s %11s %11s %9s %9s%s%s%s%s%s%s%s\n", "level", "vertices", "new", "alpha",
              "layer_bytes", "bits/new", "carving",
              candidates ? " candidate"
              : bricks   ? "    chunks     index"
                         : "",
              s.fields.empty() ? "" : "    values", regions ? "   regions" : "", faces ? "     faces" : "",
              cells ? " cell_data" : "", level0_titles.c_str(),
              stats ? "      tets  boundary avg_minSA    min_SA" : "");
  for (size_t i = 0; i < s.layers.size(); ++i) {
    const auto& l = s.layers[i];
    // (An incomplete layer's columns are what its header announces, as the
    // JSON's; the bytes the stream holds of it are said after the row.)
    const uint64_t layer_bytes = l.size();
    const uint64_t present = std::min(l.size(), s.bytes - std::min(s.bytes, l.offset));
    std::printf("%5u %9u %9u %11.5g %11llu %9.2f %9u", l.header.level, l.header.level_vertices,
                l.header.new_vertices, l.header.alpha * step, static_cast<unsigned long long>(layer_bytes),
                8.0 * layer_bytes / l.header.new_vertices, l.header.carving_bytes);
    if (candidates) std::printf(" %9u", l.header.candidate_bytes);
    if (bricks) std::printf(" %9llu %9u", static_cast<unsigned long long>(l.chunks), l.header.index_bytes);
    if (!s.fields.empty()) std::printf(" %9u", l.header.value_bytes);
    if (regions) std::printf(" %9u", l.header.region_bytes);
    if (faces) std::printf(" %9u", l.header.face_bytes);
    if (cells) std::printf(" %9u", l.header.cell_value_bytes);
    for (const Column& c : level0_columns) std::printf(" %11u", l.header.*c.bytes);
    if (i < quality.size())
      std::printf(" %9llu %9llu %9.6f %9.3g", static_cast<unsigned long long>(quality[i].tetrahedra),
                  static_cast<unsigned long long>(quality[i].quality.boundary_vertices),
                  quality[i].quality.avg_min_solid_angle, quality[i].quality.min_solid_angle);
    if (l.complete)
      std::printf("\n");
    else
      std::printf("  (incomplete: %llu of the %llu bytes its header announces)\n",
                  static_cast<unsigned long long>(present), static_cast<unsigned long long>(l.size()));
  }
}

struct Command {
  std::string input;
  bool json = false, stats = false;
  int threads = 0;  // --threads; 0: the cores this process was given
};

void add_options(CLI::App& app, Command& c) {
  app.add_option("input", c.input, ".dtm stream ('-' = standard input)")->required();
  app.add_flag("--json", c.json, "print JSON");
  app.add_flag("--stats", c.stats, "decode every level and add its quality figures");
  dtm::add_threads_option(app, c.threads);
}

int run(const Command& c) {
  const dtm::ThreadBudget threads(c.threads, dtm::cores_given());
  if (const std::string note = dtm::threads_held_note(c.threads); !note.empty())
    std::fprintf(stderr, "meshinfo: %s\n", note.c_str());
  const std::string& input = c.input;
  std::vector<uint8_t> bytes;
  dtm::read_in_chunks(input, [&](std::span<const uint8_t> chunk) {
    bytes.insert(bytes.end(), chunk.begin(), chunk.end());
    return true;
  });
  const dtm::StreamSummary s = dtm::scan_for_info(input, bytes);
  const std::vector<dtm::QualityRow> quality =
      c.stats ? dtm::decode_quality(input, bytes) : std::vector<dtm::QualityRow>{};
  if (c.json)
    std::printf("%s\n", dtm::summary_json(input, s, quality)
                            .dump(2, ' ', false, nlohmann::json::error_handler_t::replace)
                            .c_str());
  else
    print_table(input, s, quality, c.stats);
  // (A full disk, a closed pipe: an error, not a table half written and exit 0.)
  if (std::fflush(stdout) != 0 || std::ferror(stdout))
    throw std::runtime_error("cannot write to standard output");
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  dtm::ask_for_huge_pages(argv);  // before MPI and any thread: it may start the tool again
  return dtm::tool_main<Command>("meshinfo", "describe a .dtm stream", kExamples, argc, argv, add_options,
                                 run);
}
