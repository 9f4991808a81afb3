#include "codec/expert_encode.h"

#include <algorithm>
#include <cmath>
#include <future>
#include <iterator>
#include <optional>
#include <string>
#include <tuple>
#include <unordered_map>

#include "codec/sections/candidate_coder.h"
#include "codec/sections/carving_coder.h"
#include "codec/sections/cell_value_coder.h"
#include "codec/sections/edge_node_coder.h"
#include "codec/sections/face_coder.h"
#include "codec/sections/node_label_coder.h"
#include "codec/sections/node_order_coder.h"
#include "codec/sections/region_coder.h"
#include "codec/sections/vertex_order_coder.h"
#include "codec/stream/format.h"
#include "codec/stream/format_encoder.h"
#include "codec/stream/layer_coder.h"
#include "common/threads.h"
#include "mesh/carving.h"
#include "mesh/topology.h"

namespace dtm {

namespace {

// A layer's points as coded: the candidate kinds used (0: none), the
// candidate section, the payload and how many points the section sends.
struct LayerPoints {
  uint8_t kinds = 0;
  std::vector<uint8_t> section, payload;
  size_t sent = 0;
};

// Candidates cost the decoder a Delaunay tetrahedralization of the coarser
// level before the layer (instead of one of the finest level only: on
// bunny_1m 1.47x one construction to the finest mesh instead of 1.20x) and
// a pass over its cells (and, for midpoints, over its edges too, about twice
// the work): the finest layer uses them only where they save this share of
// its bytes, and midpoints, where centres alone already do, only where they
// save this share more than centres alone.
constexpr double kCandidateSaving = 0.04;
constexpr double kMidpointSaving = 0.03;

// The layer's points `fresh` through the set coder alone, or, when
// `coarse_cells` (DT of the coarser level, decoder ids) are given, those
// beside the coarser level's candidates through a candidate section: the
// option the rule above prefers. `models` are left as the chosen option's
// coding leaves them.
LayerPoints code_layer_points(std::span<const GridPoint> fresh, std::span<const GridPoint> coarse,
                              std::span<const std::array<uint32_t, 4>> coarse_cells,
                              std::span<const MortonCode> known, int qbits, SetCoderModels& models) {
  LayerPoints best;
  if (coarse_cells.empty()) {
    best.payload = encode_point_set(known, fresh, qbits, models);
    return best;
  }
  const SetCoderModels before = models.clone();
  best.payload = encode_point_set(known, fresh, qbits, models);
  const CandidateList both = layer_candidates(coarse_cells, coarse, known, qbits, kKnownCandidateKinds);
  const std::vector<CandidateHit> beside_both = points_beside(both, fresh);
  // The same list without the midpoints' own places (a place both a centre
  // and a midpoint has the centre's context), and its hits renumbered.
  CandidateList centres;
  centres.qbits = qbits;
  std::vector<uint32_t> index_in_centres(both.size(), UINT32_MAX);
  for (size_t i = 0; i < both.size(); ++i)
    if (both.context(i) < kCentreContexts) {
      index_in_centres[i] = static_cast<uint32_t>(centres.size());
      centres.keys.push_back(both.keys[i]);
    }
  std::vector<CandidateHit> beside_centres;
  for (CandidateHit h : beside_both)
    if (index_in_centres[h.candidate] != UINT32_MAX) {
      h.candidate = index_in_centres[h.candidate];
      beside_centres.push_back(h);
    }
  std::optional<SetCoderModels> chosen;
  double required = kCandidateSaving;
  const std::tuple<uint8_t, const CandidateList*, const std::vector<CandidateHit>*> options[] = {
      {kCandidateCellCentres, &centres, &beside_centres}, {kKnownCandidateKinds, &both, &beside_both}};
  for (const auto& [kinds, list, beside] : options) {
    LayerPoints option;
    option.kinds = kinds;
    std::vector<uint8_t> sent;
    option.section = encode_candidate_section(*list, *beside, fresh.size(), sent);
    std::vector<GridPoint> sent_points, rest;
    for (size_t i = 0; i < fresh.size(); ++i) (sent[i] ? sent_points : rest).push_back(fresh[i]);
    SetCoderModels trial = before.clone();
    trial.note_points(sent_points);
    std::vector<MortonCode> known_with_sent(known.begin(), known.end());
    merge_known(known_with_sent, sent_points, qbits);
    option.payload = encode_point_set(known_with_sent, rest, qbits, trial);
    option.sent = sent_points.size();
    const size_t bytes = option.section.size() + option.payload.size();
    if (option.sent > 0 &&
        bytes <= (1 - required) * static_cast<double>(best.section.size() + best.payload.size())) {
      best = std::move(option);
      chosen = std::move(trial);
    }
    // Midpoints must save the same share as centres do, and where centres
    // alone pay, their own share more than them.
    required = best.kinds == 0 ? kCandidateSaving : kMidpointSaving;
  }
  if (chosen) models = std::move(*chosen);
  return best;
}

// Level 0 of an exact stream (spec/FORMAT.md §3.10), in the decoder's
// numbering: which Delaunay cells are input cells (the carving section's
// verdicts), the exact cell section with the others, and the level as the
// regions, faces, cell values and vertex order are then coded on.
struct ExactLevel {
  // Per cell of dt, the carving's verdict: 1 when it is an input cell or,
  // in 14.0, one of the three that a flip of the section replaces.
  std::vector<uint8_t> delaunay_kept;
  std::vector<uint8_t> section;
  TetMesh mesh;                 // dt's cells, then the fill's
  std::vector<uint8_t> kept;    // per cell of mesh: its label, 0 if not kept
  std::vector<uint32_t> order;  // mesh's canonical order (the fill last)
  std::vector<uint32_t> input;  // per cell of mesh: its input cell, UINT32_MAX if none
  uint64_t delaunay_cells = 0;  // input cells that are Delaunay cells
  ExactStats stats;
};

StatusOr<ExactLevel> exact_level(const TetMesh& dt, std::span<const GridPoint> points, double alpha,
                                 std::span<const MeshCell> input, std::span<const uint8_t> labels,
                                 ApexRanks& ranks) {
  constexpr uint32_t kNone = UINT32_MAX;
  const auto label = [&](uint32_t i) -> uint8_t { return labels.empty() ? 1 : labels[i]; };
  std::vector<std::pair<MeshCell, uint32_t>> sorted;
  sorted.reserve(input.size());
  for (uint32_t i = 0; i < input.size(); ++i) {
    MeshCell c = input[i];
    std::sort(c.begin(), c.end());
    sorted.emplace_back(c, i);
  }
  std::sort(sorted.begin(), sorted.end());
  for (size_t i = 1; i < sorted.size(); ++i)
    if (sorted[i].first == sorted[i - 1].first)
      return invalid_input("two input cells have the same four corners: --exact needs a valid mesh");
  ExactLevel e;
  e.delaunay_kept.assign(dt.cells.size(), 0);
  e.input.assign(dt.cells.size(), kNone);
  std::vector<uint8_t> used(input.size(), 0);
  for (size_t c = 0; c < dt.cells.size(); ++c) {
    MeshCell q = dt.cells[c];
    std::sort(q.begin(), q.end());
    const auto it = std::lower_bound(sorted.begin(), sorted.end(), std::make_pair(q, uint32_t{0}));
    if (it == sorted.end() || it->first != q) continue;
    e.delaunay_kept[c] = 1;
    e.input[c] = it->second;
    used[it->second] = 1;
  }
  std::vector<MeshCell> rest;
  std::vector<uint32_t> rest_index;
  for (uint32_t i = 0; i < input.size(); ++i)
    if (!used[i]) rest.push_back(input[i]), rest_index.push_back(i);
  e.delaunay_cells = input.size() - rest.size();
  e.order = canonical_cell_order(dt.cells);
  ExactFill fill;
  std::vector<uint32_t> source;
  // 14.0: the carving keeps the cells the section's flips replace; the
  // fill's verdicts are those after the flips.
  const std::vector<uint8_t> input_cells = e.delaunay_kept;
  const ApexRanks asked = ranks;
  const uint64_t flips =
      ranks >= ApexRanks::kAfterFlips ? keep_flipped_cells(dt, points, rest, e.delaunay_kept) : 0;
  std::vector<uint8_t> filled = e.delaunay_kept;
  DTM_ASSIGN_OR_RETURN(
      e.section, encode_exact_cells(dt, points, alpha, filled, e.order, rest, ranks, fill, source, &e.stats));
  // Each flip replaced the three cells it was meant to, none an input cell
  // (an input whose cells overlap could ask for either); where the section
  // fell back to a version without flips (the fit tests' budget), it grew
  // their cells instead, and the carving keeps the input cells alone.
  bool apart = ranks != asked || e.stats.flips == flips;
  for (size_t c = 0; c < dt.cells.size() && apart; ++c) apart = filled[c] == input_cells[c];
  if (!apart)
    return invalid_input(
        "the input's cells overlap where two of them fill the place of three Delaunay "
        "cells: --exact needs a valid mesh");
  if (ranks != asked) e.delaunay_kept = input_cells;
  e.mesh = dt;
  extend_with_fill(e.mesh, fill);
  e.kept.resize(dt.cells.size());
  for (size_t c = 0; c < dt.cells.size(); ++c) e.kept[c] = filled[c] ? label(e.input[c]) : 0;
  for (size_t j = 0; j < fill.cells.size(); ++j) {
    const uint32_t i = rest_index[source[j]];
    e.kept.push_back(label(i));
    e.input.push_back(i);
    e.order.push_back(static_cast<uint32_t>(dt.cells.size() + j));
  }
  return e;
}

// The format of a stream with edge nodes: 18.0's coding, 19.0's, or 20.0's
// (the creases apart); 21.0's with the input's node numbering.
uint8_t edge_nodes_major(const StreamOptions& options) {
  return options.edge_nodes_v18           ? kVersionMajorEdgeNodes
         : options.edge_nodes_v19         ? kVersionMajorPredictedEdgeNodes
         : options.node_numbering.empty() ? kVersionMajorCreaseEdgeNodes
                                          : kVersionMajorNodeOrder;
}

// Level 0's edge node section (18.0, spec/FORMAT.md §3.11): its edges as the
// decoder walks them (`mesh`, `kept`, `order`: the exact level's cells, in
// the decoder's numbering; `level_points` its points), each one's node
// looked up by its corners' grid ids (`decode_order`), given as its offset
// from the edge's midpoint in half grid steps; and with `values`, the edge
// value section (19.0, §3.12): the nodes' values, whose rows in `values`
// follow the points' (the k-th node of `nodes` at row points + k). `major`:
// the stream's format (edge_nodes_major()), which says how the nodes are
// predicted. With `numbering` (StreamOptions::node_numbering), the node
// order section (21.0, §3.13) too.
struct EdgeNodeSections {
  std::vector<uint8_t> nodes, values, order;
};
StatusOr<EdgeNodeSections> edge_node_sections(const TetMesh& mesh, std::span<const uint8_t> kept,
                                              std::span<const uint32_t> order,
                                              std::span<const GridPoint> level_points,
                                              std::span<const GridEdgeNode> nodes,
                                              std::span<const uint32_t> decode_order, int qbits,
                                              uint8_t major, const FieldSectionEncoder* values, size_t points,
                                              std::span<const uint32_t> numbering, EncodedStream& out) {
  std::unordered_map<uint64_t, uint32_t> node_of;  // by the edge's grid ids, the first given
  node_of.reserve(nodes.size());
  for (size_t i = 0; i < nodes.size(); ++i)
    node_of.try_emplace(edge_key(nodes[i].corners[0], nodes[i].corners[1]), static_cast<uint32_t>(i));
  const LevelEdges edges = level_edges(mesh, kept, order);
  EdgeNodeOffsets offsets;
  offsets.present.assign(edges.corners.size(), 0);
  offsets.offset.assign(edges.corners.size(), {0, 0, 0});
  std::vector<uint32_t> node_rows;  // per present node, in the walk's order, its row in `values`
  std::vector<uint32_t> rank_of_node(nodes.size(), UINT32_MAX);  // each given node's among the present
  const int64_t reach = edge_node_reach(qbits);
  for (size_t e = 0; e < edges.corners.size(); ++e) {
    const uint32_t a = edges.corners[e][0], b = edges.corners[e][1];
    const auto it = node_of.find(edge_key(decode_order[a], decode_order[b]));
    if (it == node_of.end()) continue;
    const GridEdgeNode& node = nodes[it->second];
    offsets.present[e] = 1;
    rank_of_node[it->second] = static_cast<uint32_t>(node_rows.size());
    node_rows.push_back(static_cast<uint32_t>(points + it->second));
    ++out.edge_nodes;
    if (node.midpoint) continue;
    const std::array<int64_t, 3> sum = {int64_t{level_points[a].x} + level_points[b].x,
                                        int64_t{level_points[a].y} + level_points[b].y,
                                        int64_t{level_points[a].z} + level_points[b].z};
    auto& d = offsets.offset[e];
    for (size_t axis = 0; axis < 3; ++axis) {
      const double twice = 2 * node.at[axis];
      if (!std::isfinite(twice) ||
          std::abs(twice - static_cast<double>(sum[axis])) >= static_cast<double>(reach - 1))
        return invalid_input(
            "encode_stream: an edge node lies twice the grid's extent or more from its edge");
      d[axis] = std::llround(twice) - sum[axis];
    }
    out.moved_edge_nodes += d != std::array<int64_t, 3>{0, 0, 0};
  }
  EdgeNodeSections sections;
  std::optional<EdgeNodePredictor> predictor;
  if (major >= kVersionMajorPredictedEdgeNodes)
    predictor.emplace(mesh, kept, level_points, qbits, major >= kVersionMajorCreaseEdgeNodes);
  sections.nodes = encode_edge_nodes(edges, offsets, qbits, predictor ? &*predictor : nullptr);
  out.edge_node_bytes = sections.nodes.size();
  if (values) {
    std::vector<uint32_t> vertex_rows(decode_order.begin(), decode_order.begin() + level_points.size());
    sections.values = values->encode_chunk(
        vertex_rows, node_rows, edge_node_neighbours(edges, offsets.present), out.edge_node_field_bytes);
    out.edge_value_bytes = sections.values.size();
  }
  if (!numbering.empty()) {
    // Each entry as the decoder names it: a vertex by its number (the
    // vertex order section's, the input's), a node by its rank.
    std::vector<uint32_t> named;
    named.reserve(numbering.size());
    uint32_t next_vertex = 0;
    for (const uint32_t entry : numbering) {
      if (entry < points) {
        if (entry != next_vertex++)
          return invalid_input("encode_stream: the node numbering names the points out of their order");
        named.push_back(entry);
        continue;
      }
      const size_t node = entry - points;
      if (node >= nodes.size() || rank_of_node[node] == UINT32_MAX)
        return invalid_input(
            "encode_stream: the node numbering names an edge node twice or one the level has not");
      named.push_back(static_cast<uint32_t>(points + rank_of_node[node]));
      rank_of_node[node] = UINT32_MAX;
    }
    if (next_vertex != points || level_points.size() != points || named.size() != points + node_rows.size())
      return invalid_input("encode_stream: the node numbering does not name every vertex and edge node");
    sections.order = encode_node_order(edges, node_order_frame(edges, offsets.present), points, named);
    out.node_order_bytes = sections.order.size();
  }
  return sections;
}

}  // namespace

StatusOr<EncodedStream> encode_stream(const Hierarchy& hierarchy, std::span<const GridPoint> points,
                                      const Grid& grid, AlphaKind alpha_policy, const StreamOptions& options,
                                      std::vector<FieldValues> fields) {
  if (options.level_step < 1) return invalid_input("encode_stream: level_step < 1");
  std::vector<int> streamed;
  for (size_t i = 0; i < hierarchy.levels.size(); ++i)
    if (i % options.level_step == 0 || i + 1 == hierarchy.levels.size())
      streamed.push_back(static_cast<int>(i));
  if (streamed.empty() || streamed.size() > 0xFFFF)
    return invalid_input("encode_stream: level count out of range");
  StreamHeader h;
  h.grid = grid;
  h.alpha_policy = alpha_policy;
  // The hierarchy carries its verdicts when it was carved to a reference:
  // then every layer corrects alpha's prediction.
  const bool corrections = !hierarchy.levels[0].kept.empty();
  const bool values = !fields.empty();
  std::vector<FieldDescription> descriptions;
  std::vector<size_t> value_counts;
  for (const FieldValues& f : fields)
    descriptions.push_back(f.description), value_counts.push_back(f.bits.size());
  // (With edge nodes, a row of values for each after the points'.)
  DTM_RETURN_IF_ERROR(check_fields(descriptions, value_counts, points.size() + options.edge_nodes.size())
                          .with_context("encode_stream"));
  std::optional<FieldSectionEncoder> value_coder;
  if (values) {
    auto made = FieldSectionEncoder::make(std::move(fields));
    if (!made.ok()) return made.status();
    value_coder.emplace(std::move(*made));
  }
  const bool regions = !options.regions.empty();
  if (regions) {
    DTM_RETURN_IF_ERROR(check_region_table(options.regions).with_context("encode_stream"));
    if (!corrections) return invalid_input("encode_stream: regions need a hierarchy carved to a reference");
  }
  const bool faces = options.faces != nullptr;
  if (faces) {
    DTM_RETURN_IF_ERROR(check_region_table(options.face_tags).with_context("encode_stream: face tags"));
    if (options.face_tags.size() > kMaxFaceTags)
      return invalid_input("encode_stream: more than " + std::to_string(kMaxFaceTags) + " face tags");
    if (!corrections) return invalid_input("encode_stream: face tags need a hierarchy carved to a reference");
  }
  const bool exact = !options.exact_cells.empty();
  const bool edge_nodes = exact && !options.edge_nodes.empty();
  if (!options.edge_nodes.empty()) {
    if (!exact) return invalid_input("encode_stream: edge nodes need exact cells");
    if (options.exact_ranks < ApexRanks::kAfterFlips)
      return invalid_input("encode_stream: edge nodes need format 14.0's exact cells or later (format 18.0)");
    if (options.exact_ranks == ApexRanks::kClosingFirst && (options.edge_nodes_v18 || options.edge_nodes_v19))
      return invalid_input("encode_stream: edge nodes of format 18.0 or 19.0 need format 14.0's exact cells");
    for (const GridEdgeNode& e : options.edge_nodes)
      if (e.corners[0] >= points.size() || e.corners[1] >= points.size() || e.corners[0] == e.corners[1])
        return invalid_input("encode_stream: an edge node on an edge whose corners are not two points");
  }
  if (!options.node_numbering.empty() &&
      (!edge_nodes || options.input_order.empty() || options.edge_nodes_v18 || options.edge_nodes_v19))
    return invalid_input(
        "encode_stream: a node numbering needs edge nodes of format 20.0 and a vertex order");
  const bool labels = !options.node_labels.empty();
  if (labels) {
    if (options.input_order.empty()) return invalid_input("encode_stream: node labels need a vertex order");
    if (edge_nodes && options.node_numbering.empty())
      return invalid_input(
          "encode_stream: the node labels of a mesh with edge nodes need its node numbering");
    const size_t nodes = options.node_numbering.empty() ? points.size() : options.node_numbering.size();
    if (options.node_labels.size() != nodes)
      return invalid_input("encode_stream: " + std::to_string(options.node_labels.size()) +
                           " node labels for " + std::to_string(nodes) + " nodes");
    if (!valid_node_labels(options.node_labels))
      return invalid_input("encode_stream: node labels out of [1, 2^62 - 1] or given twice");
  }
  if (exact) {
    if (!corrections)
      return invalid_input("encode_stream: exact cells need a hierarchy carved to a reference");
    if (!options.exact_labels.empty() && options.exact_labels.size() != options.exact_cells.size())
      return invalid_input("encode_stream: a label is needed for every exact cell");
    for (uint8_t r : options.exact_labels)
      if (r == 0 || r > std::max<size_t>(options.regions.size(), 1))
        return invalid_input("encode_stream: an exact cell's region is not in the table");
    for (const auto& c : options.exact_cells)
      for (uint32_t v : c)
        if (v >= points.size())
          return invalid_input("encode_stream: an exact cell names a point that does not exist");
  }
  // Level 0's kept cells and their values, before the header: the cell
  // field table's scales are the values'. (Of an exact level 0: the input's
  // cells, in the order given.)
  const bool cell_data = static_cast<bool>(options.cell_values);
  std::optional<FieldSectionEncoder> cell_coder;
  std::vector<uint32_t> kept_rank;  // per cell of level 0's DT: its index among the kept, or UINT32_MAX
  if (cell_data) {
    if (!corrections)
      return invalid_input("encode_stream: cell data needs a hierarchy carved to a reference");
    const Level& finest = hierarchy.levels[0];
    std::vector<std::array<uint32_t, 4>> kept_cells;
    if (exact) {
      kept_cells.assign(options.exact_cells.begin(), options.exact_cells.end());
    } else {
      kept_rank.assign(finest.delaunay.cells.size(), UINT32_MAX);
      for (size_t c = 0; c < finest.delaunay.cells.size(); ++c)
        if (c < finest.kept.size() && finest.kept[c]) {
          kept_rank[c] = static_cast<uint32_t>(kept_cells.size());
          kept_cells.push_back(finest.delaunay.cells[c]);
        }
    }
    DTM_ASSIGN_OR_RETURN(std::vector<FieldValues> cell_values, options.cell_values(kept_cells));
    std::vector<FieldDescription> cell_descriptions;
    std::vector<size_t> cell_value_counts;
    for (const FieldValues& f : cell_values)
      cell_descriptions.push_back(f.description), cell_value_counts.push_back(f.bits.size());
    DTM_RETURN_IF_ERROR(check_fields(cell_descriptions, cell_value_counts, kept_cells.size(), "cells")
                            .with_context("encode_stream: cell data"));
    DTM_ASSIGN_OR_RETURN(FieldSectionEncoder made, FieldSectionEncoder::make(std::move(cell_values)));
    cell_coder.emplace(std::move(made));
  }
  const bool keep_order = !options.input_order.empty();
  if (keep_order) {
    if (!corrections)
      return invalid_input("encode_stream: a vertex order needs a hierarchy carved to a reference");
    if (options.input_order.size() != points.size() || hierarchy.levels[0].vertices.size() != points.size())
      return invalid_input("encode_stream: the vertex order is not one of level 0's vertices");
    std::vector<uint8_t> seen(points.size(), 0);
    for (uint32_t p : options.input_order)
      if (p >= points.size() || seen[p]++)
        return invalid_input("encode_stream: the vertex order is not a permutation of the points");
  }
  // (An exact stream's version is settled when its section is: 11.0 where
  // its apexes are ranked among all the candidates.)
  ApexRanks exact_ranks = options.exact_ranks;
  h.version_major = exact && exact_ranks == ApexRanks::kClosingFirst ? kVersionMajorExactClosing
                    : labels                                         ? kVersionMajorNodeLabels
                    : edge_nodes                                     ? edge_nodes_major(options)
                    : exact                                          ? kVersionMajorExact
                    : cell_data || keep_order                        ? kVersionMajorCellData
                    : regions || faces                               ? kVersionMajorRegions
                    : corrections                                    ? kVersionMajorUnbricked
                    : values                                         ? kVersionMajorWithValues
                                                                     : kVersionMajorWithoutValues;
  h.flags = (options.cell_hashes ? kFlagCellHashes : 0) | (corrections ? kFlagCarvingCorrections : 0) |
            (values ? kFlagValues : 0) | (regions ? kFlagRegions : 0) | (faces ? kFlagFaces : 0) |
            (cell_data ? kFlagCellData : 0) | (keep_order ? kFlagVertexOrder : 0) | (exact ? kFlagExact : 0) |
            (edge_nodes ? kFlagEdgeNodes : 0) | (labels ? kFlagNodeLabels : 0);
  h.level_count = static_cast<uint16_t>(streamed.size());
  h.vertex_count = static_cast<uint32_t>(hierarchy.levels[0].vertices.size());

  EncodedStream out;
  out.bytes = write_header(h);
  if (value_coder) {
    out.fields = value_coder->descriptions();
    const auto table = write_field_table(out.fields);
    out.field_table_bytes = table.size();
    out.bytes.insert(out.bytes.end(), table.begin(), table.end());
  }
  if (regions) {
    const auto table = write_region_table(options.regions);
    out.region_table_bytes = table.size();
    out.bytes.insert(out.bytes.end(), table.begin(), table.end());
  }
  if (faces) {
    const auto table = write_region_table(options.face_tags);
    out.face_table_bytes = table.size();
    out.bytes.insert(out.bytes.end(), table.begin(), table.end());
  }
  if (cell_coder) {
    out.cell_fields = cell_coder->descriptions();
    const auto table = write_field_table(out.cell_fields);
    out.cell_field_table_bytes = table.size();
    out.bytes.insert(out.bytes.end(), table.begin(), table.end());
  }
  out.region_bytes.assign(hierarchy.levels.size(), 0);
  out.face_bytes.assign(hierarchy.levels.size(), 0);
  out.layer_bytes.assign(hierarchy.levels.size(), 0);
  out.carving_bytes.assign(hierarchy.levels.size(), 0);
  out.value_bytes.assign(hierarchy.levels.size(), 0);
  out.candidate_bytes.assign(hierarchy.levels.size(), 0);
  out.candidate_points.assign(hierarchy.levels.size(), 0);
  // The decoder's vertex index of each grid point, and its points in order:
  // each layer's new points come out of the set coder in ascending Morton
  // order, after the coarser levels' (all layers first, for the work below).
  std::vector<uint32_t> decoder_index(points.size(), UINT32_MAX);
  std::vector<GridPoint> decoded;
  out.streamed_levels = streamed;
  // Per layer, where its new points lie in `decoded` (and their grid ids in
  // out.decode_order).
  struct Layer {
    size_t first = 0, count = 0;
  };
  std::vector<Layer> layers(streamed.size());
  {
    std::vector<uint32_t> coarser;  // V_{l+1}, ascending
    for (size_t l = streamed.size(); l-- > 0;) {
      const Level& level = hierarchy.levels[streamed[l]];
      std::vector<uint32_t> added;
      std::set_difference(level.vertices.begin(), level.vertices.end(), coarser.begin(), coarser.end(),
                          std::back_inserter(added));
      if (added.size() + coarser.size() != level.vertices.size())
        return invalid_input("encode_stream: levels are not nested");
      std::vector<std::pair<MortonCode, uint32_t>> by_code;
      by_code.reserve(added.size());
      for (uint32_t i : added) by_code.emplace_back(morton_encode(points[i], grid.qbits), i);
      std::sort(by_code.begin(), by_code.end());
      layers[l] = {decoded.size(), added.size()};
      for (const auto& [code, i] : by_code) {
        decoder_index[i] = static_cast<uint32_t>(out.decode_order.size());
        out.decode_order.push_back(i);
        decoded.push_back(points[i]);
      }
      coarser = level.vertices;
    }
  }

  // Per layer, its sections. Those of the level's cells (carving, regions,
  // faces, cell values, vertex order, exact cells, the cell hash) read that
  // level alone; the point coder's and the value coder's models adapt layer
  // after layer, each coder on its own. So two chains run side by side over
  // the layers, coarsest first, each on its share of the threads: the cell
  // sections, and the point coder followed by the value coder (on
  // bunny_1m, 2 cores: 5.4 s against 4.6 + 2.2 s).
  struct LayerSections {
    std::vector<uint8_t> carving, regions, faces, cells, order, exact, edge_nodes, edge_values, node_order,
        node_labels, values;
    uint64_t cell_hash = 0;
    LayerPoints points;
  };
  std::vector<LayerSections> sections(streamed.size());
  const auto cell_sections = [&](size_t l) -> Status {
    const Level& level = hierarchy.levels[streamed[l]];
    LayerSections& out_l = sections[l];
    // The decoder's points up to this level's.
    const std::span<const GridPoint> level_points(decoded.data(), layers[l].first + layers[l].count);
    if (options.cell_hashes)
      out_l.cell_hash = exact && streamed[l] == 0 ? cell_set_hash(points, options.exact_cells)
                                                  : cell_set_hash(points, level.carved_cells());
    if (!corrections) return Status::Ok();
    if (level.kept.size() != level.delaunay.cells.size())
      return invalid_input("encode_stream: a level without its carving verdicts");
    TetMesh dt = level.delaunay;
    for (auto& c : dt.cells)
      for (uint32_t& v : c) v = decoder_index[v];
    // What the sections below see: the level's cells (an exact level 0's
    // are the Delaunay cells that are input cells and the fill), each
    // kept one's label, the canonical order, and per kept cell its rank
    // among the cell values.
    std::optional<ExactLevel> exact_cells;
    if (exact && streamed[l] == 0) {
      std::vector<MeshCell> input(options.exact_cells.begin(), options.exact_cells.end());
      for (auto& c : input)
        for (uint32_t& v : c) v = decoder_index[v];
      DTM_ASSIGN_OR_RETURN(ExactLevel made, exact_level(dt, level_points, level.alpha, input,
                                                        options.exact_labels, exact_ranks));
      exact_cells.emplace(std::move(made));
      // (Its version as its exact cell section settled it: 11.0's contexts
      // where that fell back to 11.0's ranks.)
      out_l.carving = encode_carving(dt, level_points, level.alpha, exact_cells->delaunay_kept,
                                     exact_carving_contexts(format_major_of(exact_ranks)));
      out_l.exact = std::move(exact_cells->section);
      out.exact_bytes = out_l.exact.size();
      out.exact_delaunay_cells = exact_cells->delaunay_cells;
      out.exact = exact_cells->stats;
    } else {
      out_l.carving =
          encode_carving(dt, level_points, level.alpha, level.kept, carving_contexts(h.version_major));
    }
    const TetMesh& cells_mesh = exact_cells ? exact_cells->mesh : dt;
    const std::vector<uint8_t>& kept = exact_cells ? exact_cells->kept : level.kept;
    const std::vector<uint32_t> order = exact_cells ? exact_cells->order : canonical_cell_order(dt.cells);
    if (regions) {
      for (uint8_t r : kept)
        if (r > options.regions.size())
          return invalid_input("encode_stream: a cell's region is not in the table");
      out_l.regions = encode_regions(cells_mesh, order, kept, options.regions.size());
    }
    if (faces) {
      // The level's surface in the decoder's numbering, its faces named by
      // grid ids for the tagger.
      const SurfaceFaces surface = surface_faces(cells_mesh, kept);
      std::vector<std::array<uint32_t, 3>> by_grid_id;
      by_grid_id.reserve(surface.faces.size());
      for (const SurfaceFace& f : surface.faces)
        by_grid_id.push_back(
            {out.decode_order[f.key[0]], out.decode_order[f.key[1]], out.decode_order[f.key[2]]});
      out_l.faces = encode_face_tags(surface, options.faces->labels(by_grid_id), options.face_tags.size());
      if (streamed[l] == 0) out.tagged_faces_kept = options.faces->tagged_among(by_grid_id);
    }
    if (cell_coder && streamed[l] == 0) {
      // The kept cells in the canonical order, each standing at its centroid.
      std::vector<uint32_t> ranks;
      std::vector<std::array<uint32_t, 4>> cells;
      for (uint32_t c : order)
        if (kept[c])
          ranks.push_back(exact_cells ? exact_cells->input[c] : kept_rank[c]),
              cells.push_back(cells_mesh.cells[c]);
      out_l.cells =
          cell_coder->encode_layer(ranks, cell_positions(level_points, cells), out.cell_field_bytes);
      out.level0_cells = cells.size();
    }
    // (Written whatever the exact cells' coding; dropped below if that
    // fell back to 11.0's.)
    if (edge_nodes && streamed[l] == 0 && exact_cells) {
      DTM_ASSIGN_OR_RETURN(
          EdgeNodeSections edge,
          edge_node_sections(cells_mesh, kept, order, level_points, options.edge_nodes, out.decode_order,
                             grid.qbits, edge_nodes_major(options),
                             value_coder && !options.edge_nodes_v18 ? &*value_coder : nullptr, points.size(),
                             options.node_numbering, out));
      out_l.edge_nodes = std::move(edge.nodes);
      out_l.edge_values = std::move(edge.values);
      out_l.node_order = std::move(edge.order);
    }
    if (keep_order && streamed[l] == 0) {
      // Each input vertex's number in the decoder's order.
      std::vector<uint32_t> numbering;
      numbering.reserve(options.input_order.size());
      for (uint32_t p : options.input_order) numbering.push_back(decoder_index[p]);
      out_l.order = encode_vertex_order(vertex_neighbours(level_points.size(), cells_mesh.cells), numbering);
      out.order_bytes = out_l.order.size();
    }
    if (labels && streamed[l] == 0) {
      out_l.node_labels = encode_node_labels(options.node_labels);
      out.node_label_bytes = out_l.node_labels.size();
    }
    return Status::Ok();
  };
  const auto values_of = [&](size_t l) {
    std::vector<uint64_t> layer_field_bytes;
    const Layer& layer = layers[l];
    sections[l].values = value_coder->encode_layer(
        std::span<const uint32_t>(out.decode_order).subspan(layer.first, layer.count),
        std::span<const GridPoint>(decoded).subspan(layer.first, layer.count), layer_field_bytes);
    out.field_bytes.resize(layer_field_bytes.size(), 0);
    for (size_t f = 0; f < layer_field_bytes.size(); ++f) out.field_bytes[f] += layer_field_bytes[f];
    out.level_field_bytes.resize(hierarchy.levels.size());
    out.level_field_bytes[streamed[l]] = std::move(layer_field_bytes);
  };
  // The cells' sections on one side, the points' and then the values' on
  // the other, each on its share of the threads; once one side is done, the
  // other takes its threads too (the finest layer's values, whose neighbour
  // searches are most of their time, come last and would otherwise run on
  // half of them, on one thread of two).
  const int threads = thread_count();
  ThreadShares shares(threads, 2);
  constexpr int kCellsSide = 0, kPointsSide = 1;
  const auto every_level_cells = [&]() -> Status {
    const ThreadShares::Use mine(shares, kCellsSide);
    for (size_t l = streamed.size(); l-- > 0;) DTM_RETURN_IF_ERROR(cell_sections(l));
    return Status::Ok();
  };
  const auto points_then_values = [&]() -> Status {
    const ThreadShares::Use mine(shares, kPointsSide);
    std::vector<MortonCode> known;  // Morton codes of V_{l+1}, ascending
    SetCoderModels models;          // adapted layer after layer, as the decoder's
    models.enable_coordinate_reuse(grid.qbits);
    for (size_t l = streamed.size(); l-- > 0;) {
      const Layer& layer = layers[l];
      const std::span<const GridPoint> coarse_points(decoded.data(), layer.first);
      const std::span<const GridPoint> layer_points(decoded.data() + layer.first, layer.count);
      std::vector<std::array<uint32_t, 4>> coarse_cells;
      // Only the finest layer: there the mesh generator's last refinement
      // round put its points, and only there is the decoder's price one more
      // tetrahedralization (of level 1) whatever the number of levels.
      const bool may_use_candidates = options.candidates && h.version_major >= 7 && l == 0 &&
                                      !coarse_points.empty() && grid.qbits <= kMaxCandidateQBits;
      if (may_use_candidates) {
        const Level& coarse = hierarchy.levels[streamed[l + 1]];
        if (coarse.delaunay.cells.empty()) {  // the paper preset keeps no tetrahedralization
          DTM_ASSIGN_OR_RETURN(TetMesh dt, delaunay_tetrahedralize(coarse_points));
          coarse_cells = std::move(dt.cells);
        } else {
          coarse_cells = coarse.delaunay.cells;
          for (auto& c : coarse_cells)
            for (uint32_t& v : c) v = decoder_index[v];
        }
      }
      sections[l].points =
          code_layer_points(layer_points, coarse_points, coarse_cells, known, grid.qbits, models);
      merge_known(known, layer_points, grid.qbits);
    }
    if (value_coder)
      for (size_t l = streamed.size(); l-- > 0;) values_of(l);
    return Status::Ok();
  };
  if (threads < 2) {
    DTM_RETURN_IF_ERROR(every_level_cells());
    DTM_RETURN_IF_ERROR(points_then_values());
  } else {
    auto cells = std::async(std::launch::async, every_level_cells);
    const Status points_status = points_then_values();
    DTM_RETURN_IF_ERROR(cells.get());
    DTM_RETURN_IF_ERROR(points_status);
  }
  // (The exact cells fell back to 11.0's coding, which has no edge nodes:
  // the stream is 11.0's, without them, and says so.)
  if (edge_nodes && exact_ranks < ApexRanks::kAfterFlips) {
    out.edge_nodes_dropped = out.edge_nodes;
    out.edge_nodes = out.moved_edge_nodes = out.edge_node_bytes = out.edge_value_bytes = 0;
    out.node_order_bytes = 0;
    out.edge_node_field_bytes.clear();
    sections[0].edge_nodes.clear();
    sections[0].edge_values.clear();
    sections[0].node_order.clear();
    h.flags = static_cast<uint16_t>(h.flags & ~kFlagEdgeNodes);
  }
  // (Nor node labels, which 22.0 brought: they are dropped, and said so.)
  if (labels && exact && exact_ranks < ApexRanks::kAfterFlips) {
    out.node_labels_dropped = true;
    out.node_label_bytes = 0;
    sections[0].node_labels.clear();
    h.flags = static_cast<uint16_t>(h.flags & ~kFlagNodeLabels);
  }
  // (An exact stream's version, and flags, as its sections settled them.)
  if (exact) {
    const uint8_t major = exact_ranks == ApexRanks::kClosingFirst ? kVersionMajorExactClosing
                          : (h.flags & kFlagNodeLabels)           ? kVersionMajorNodeLabels
                          : !(h.flags & kFlagEdgeNodes)           ? format_major_of(exact_ranks)
                                                                  : edge_nodes_major(options);
    if (major != h.version_major || (edge_nodes && !(h.flags & kFlagEdgeNodes)) ||
        (labels && !(h.flags & kFlagNodeLabels))) {
      h.version_major = major;
      const std::vector<uint8_t> header = write_header(h);
      std::copy(header.begin(), header.end(), out.bytes.begin());
    }
  }

  for (size_t l = streamed.size(); l-- > 0;) {
    const Level& level = hierarchy.levels[streamed[l]];
    LayerSections& s = sections[l];
    out.candidate_points[streamed[l]] = s.points.sent;
    out.candidate_bytes[streamed[l]] = s.points.section.size();
    // (A section's length is a u32: a stream past it would not decode.)
    for (const auto& [name, bytes] : {std::pair<const char*, size_t>{"payload", s.points.payload.size()},
                                      {"carving", s.carving.size()},
                                      {"value", s.values.size()},
                                      {"candidate", s.points.section.size()},
                                      {"region", s.regions.size()},
                                      {"face", s.faces.size()},
                                      {"cell value", s.cells.size()},
                                      {"vertex order", s.order.size()},
                                      {"exact cell", s.exact.size()},
                                      {"edge node", s.edge_nodes.size()},
                                      {"edge value", s.edge_values.size()},
                                      {"node order", s.node_order.size()},
                                      {"node label", s.node_labels.size()}})
      if (bytes > UINT32_MAX)
        return Status{StatusCode::kLimitExceeded,
                      "encode_stream: level " + std::to_string(l) + "'s " + name + " section of " +
                          std::to_string(bytes) +
                          " bytes is beyond the format's 4 GiB a section (fewer fields, or lossy ones)"};
    LayerHeader lh;
    lh.format_major = h.version_major;
    lh.stream_flags = h.flags;
    lh.candidate_kinds = s.points.kinds;
    lh.level = static_cast<uint16_t>(l);
    lh.new_vertices = static_cast<uint32_t>(layers[l].count);
    lh.level_vertices = static_cast<uint32_t>(level.vertices.size());
    lh.alpha = level.alpha;
    lh.cell_hash = s.cell_hash;
    const auto layer =
        write_layer(lh, s.points.payload, s.carving, s.values, s.points.section, s.regions, s.faces, s.cells,
                    s.order, s.exact, s.edge_nodes, s.edge_values, s.node_order, s.node_labels);
    out.cell_value_bytes += s.cells.size();
    out.face_bytes[streamed[l]] = s.faces.size();
    out.carving_bytes[streamed[l]] = s.carving.size();
    out.region_bytes[streamed[l]] = s.regions.size();
    out.value_bytes[streamed[l]] = s.values.size();
    out.layer_bytes[streamed[l]] = layer.size();
    out.bytes.insert(out.bytes.end(), layer.begin(), layer.end());
    s = {};
  }
  return out;
}

}  // namespace dtm
