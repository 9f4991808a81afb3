#include "codec/encode.h"

#include <algorithm>
#include <cmath>
#include <optional>
#include <string>

#include "codec/blocks/block_runs.h"
#include "codec/blocks/bricked_encoder.h"
#include "codec/blocks/reference_share.h"
#include "codec/encode_exact_level0.h"
#include "codec/expert_encode.h"
#include "codec/sections/face_coder.h"
#include "common/byte_io.h"
#include "common/release.h"
#include "core/cell_sources.h"
#include "core/reference_shape.h"
#include "core/region_solid.h"
#include "mesh/predicates.h"

namespace dtm {
namespace {

// The distinct labels of a region or tag list, ascending: the table's order.
std::vector<int32_t> distinct_labels(std::span<const int32_t> labels) {
  std::vector<int32_t> distinct(labels.begin(), labels.end());
  std::sort(distinct.begin(), distinct.end());
  distinct.erase(std::unique(distinct.begin(), distinct.end()), distinct.end());
  return distinct;
}

// The labels of every rank's tetrahedra (`mine`: this rank's share's,
// distinct), distinct and ascending: the same table on every rank.
std::vector<int32_t> labels_of_every_rank(RankExchange& exchange, std::span<const int32_t> mine) {
  ByteWriter w;
  w.u64(mine.size());
  for (int32_t label : mine) w.u32(static_cast<uint32_t>(label));
  std::vector<int32_t> all;
  for (const auto& bytes : exchange.all_gather(w.take())) {
    BlockReader r(bytes);
    for (uint64_t i = r.u64(); i > 0; --i) all.push_back(static_cast<int32_t>(r.u32()));
  }
  return distinct_labels(all);
}

// A region or face tag table: each label with its name, if the input has
// one (cut to what a table holds).
// The first label that `names` names and `distinct` lacks: a name rides on
// its label's cells or faces, so one with none would be lost in silence.
std::optional<int32_t> name_without_label(const std::map<int32_t, std::string>& names,
                                          std::span<const int32_t> distinct) {
  for (const auto& entry : names)
    if (!std::binary_search(distinct.begin(), distinct.end(), entry.first)) return entry.first;
  return std::nullopt;
}

// The table of `distinct` labels and their names, each as the stream holds
// it (held_label_name()); a name cut is added to `cut`, as it was given.
std::vector<RegionLabel> label_table(std::span<const int32_t> distinct,
                                     const std::map<int32_t, std::string>& names,
                                     std::vector<std::string>& cut) {
  std::vector<RegionLabel> table;
  for (int32_t label : distinct) {
    const auto name = names.find(label);
    if (name == names.end()) {
      table.push_back({label, ""});
      continue;
    }
    if (name->second.size() > kMaxRegionNameBytes) cut.push_back(name->second);
    table.push_back({label, held_label_name(name->second)});
  }
  return table;
}

// The input's lattice as the grid: positions stay exact.
StatusOr<QuantizedPoints> lattice_grid(const QuantizedPoints& lattice, int qbits) {
  QuantizedPoints q = lattice;
  const int needed = q.grid.qbits;
  if (qbits > 0) {
    if (qbits < needed)
      return invalid_input("the lattice spans " + std::to_string((1 << needed) / 2) +
                           " or more points on an axis: qbits must be at least " + std::to_string(needed));
    q.grid.qbits = qbits;
  }
  return q;
}

// `grid` with its origin and step multiplied by `scale`, or divided by it.
Grid scaled(Grid grid, double scale) {
  for (double& o : grid.origin) o *= scale;
  grid.step *= scale;
  return grid;
}
Grid unscaled(Grid grid, double scale) {
  for (double& o : grid.origin) o /= scale;
  grid.step /= scale;
  return grid;
}

HierarchyOptions hierarchy_options(const EncodeOptions& o, const Grid& grid, double dmax) {
  HierarchyOptions h;
  h.alpha.kind = o.alpha;
  h.alpha.fixed_value = o.fixed_alpha / grid.step;
  h.dmax = dmax / grid.step;
  h.max_levels = o.max_levels;
  h.min_base_vertices = o.min_base_vertices;
  h.stop_when_boundary_is_final = o.paper_stop;
  h.quality_guard = o.quality_guard;
  h.quality_ratio = o.quality_ratio;
  h.average_quality_floor = o.average_quality_floor;
  h.quality_floor_cap = o.quality_floor_cap;
  h.carve_to_reference = o.carve_to_reference;
  h.removal_share = o.removal_share;
  h.measure_boundary_error = o.measure_boundary_error;
  h.on_phase = o.on_phase;
  return h;
}

Status check_options(const EncodeOptions& o) {
  if (o.qbits != 0 && (o.qbits < kMinQBits || o.qbits > kMaxQBits))
    return invalid_input("qbits must be in [1, 24], got " + std::to_string(o.qbits));
  if (!(o.scale > 0) || !std::isfinite(o.scale))
    return invalid_input("the scale must be positive and finite");
  if (!(o.box >= 0) || !std::isfinite(o.box)) return invalid_input("the box must be positive and finite");
  if (!(o.dmax >= 0) || !std::isfinite(o.dmax)) return invalid_input("D_max must be positive and finite");
  if (o.alpha == AlphaKind::kFixed && !(o.fixed_alpha > 0))
    return invalid_input("a fixed alpha must be positive");
  if (o.max_levels < 0) return invalid_input("the level count must not be negative");
  if (o.quality_guard < 0) return invalid_input("the quality guard must not be negative");
  if (!(o.average_quality_floor >= 0 && o.average_quality_floor <= 1))
    return invalid_input("the average quality floor must be in [0, 1]");
  if (!(o.quality_floor_cap >= 0 && o.quality_floor_cap <= 0.56))
    return invalid_input("the quality floor's cap must be in [0, 0.56] (0.551 is the regular tetrahedron's)");
  if (o.level_step < 1) return invalid_input("the level step must be at least 1");
  if (!(o.removal_share >= 0 && o.removal_share < 1))
    return invalid_input("the removal share must be in [0, 1)");
  return Status::Ok();
}

// How the stream's table describes an input array (a per-vertex field or a
// cell array): lossy where --field-error names it.
FieldDescription described(const EncodeInput::Field& f, const EncodeOptions& options) {
  FieldDescription d;
  d.name = f.name;
  d.type = f.type;
  d.components = f.components;
  if (const auto e = options.field_errors.find(f.name); e != options.field_errors.end()) {
    d.lossy = true;
    d.error_bound = e->second;
  }
  return d;
}

// The fields' values per grid point (the first input point's, where
// quantization merged several), checked against the points and the options.
StatusOr<std::vector<FieldValues>> grid_point_fields(const EncodeInput& input, const EncodeOptions& options,
                                                     const QuantizedPoints& q, uint64_t& merged_differing) {
  for (const auto& [name, error] : options.field_errors) {
    bool found = false;
    for (const auto& f : input.fields) found = found || f.name == name;
    for (const auto& f : input.cell_fields) found = found || f.name == name;
    if (!found)
      return invalid_input("an error bound names '" + name + "', which is not a field of the input");
  }
  std::vector<FieldDescription> descriptions;
  std::vector<size_t> value_counts;
  for (const auto& f : input.fields) {
    descriptions.push_back(described(f, options));
    value_counts.push_back(f.values.size());
  }
  DTM_RETURN_IF_ERROR(check_fields(descriptions, value_counts, q.input_to_point.size()));
  for (size_t k = 0; k < input.fields.size(); ++k) {
    DTM_RETURN_IF_ERROR(check_field_values(descriptions[k], input.fields[k].values, "point"));
    DTM_RETURN_IF_ERROR(check_field_values(descriptions[k], input.fields[k].edge_values, "edge node"));
  }

  std::vector<FieldValues> out;
  std::vector<uint8_t> differs(q.points.size(), 0);
  for (size_t k = 0; k < input.fields.size(); ++k) {
    const auto& f = input.fields[k];
    FieldValues& v = out.emplace_back(FieldValues{descriptions[k], {}});
    if (v.description.lossy)
      for (size_t i = 0; i < f.values.size(); ++i)
        if (!std::isfinite(f.values[i]))
          return invalid_input("field '" + f.name + "': point " + std::to_string(i / f.components) +
                               " holds " + (std::isnan(f.values[i]) ? "NaN" : "an infinity") +
                               ", which a lossy field cannot keep (code it losslessly)");
    const size_t n = f.components;
    v.bits.resize(q.points.size() * n);
    std::vector<uint8_t> seen(q.points.size(), 0);
    for (size_t i = 0; i < q.input_to_point.size(); ++i) {
      const uint32_t p = q.input_to_point[i];
      for (size_t c = 0; c < n; ++c) {
        const uint64_t bits = bits_of(f.values[i * n + c], f.type);
        if (!seen[p])
          v.bits[p * n + c] = bits;
        else if (v.bits[p * n + c] != bits)
          differs[p] = 1;
      }
      seen[p] = 1;
    }
  }
  merged_differing = static_cast<uint64_t>(std::count(differs.begin(), differs.end(), 1));
  return out;
}

// The fields' values at the edge nodes (`nodes`: input.edge_nodes on the
// grid), a row for each after the grid points' (the edge value section,
// format 19.0): a field's edge_values, or where it has none its value at
// the edge's corners' mean (a float field's; an integer field's the lesser,
// as a decoder of an 18.0 stream makes it).
Status append_edge_node_values(const EncodeInput& input, std::span<const GridEdgeNode> nodes,
                               std::vector<FieldValues>& fields) {
  for (size_t k = 0; k < fields.size(); ++k) {
    const EncodeInput::Field& f = input.fields[k];
    FieldValues& v = fields[k];
    const auto n = static_cast<size_t>(f.components);
    if (!f.edge_values.empty() && f.edge_values.size() != nodes.size() * n)
      return invalid_input("field '" + f.name + "' has " + std::to_string(f.edge_values.size()) +
                           " values for " + std::to_string(nodes.size()) + " edge nodes of " +
                           std::to_string(n) + " components");
    const size_t points = v.bits.size() / n;
    v.bits.reserve(v.bits.size() + nodes.size() * n);
    for (size_t e = 0; e < nodes.size(); ++e)
      for (size_t c = 0; c < n; ++c) {
        if (!f.edge_values.empty()) {
          const double value = f.edge_values[e * n + c];
          if (v.description.lossy && !std::isfinite(value))
            return invalid_input("field '" + f.name + "': the edge node at (" +
                                 std::to_string(input.edge_nodes[e].at.x) + ", " +
                                 std::to_string(input.edge_nodes[e].at.y) + ", " +
                                 std::to_string(input.edge_nodes[e].at.z) + ") holds " +
                                 (std::isnan(value) ? "NaN" : "an infinity") +
                                 ", which a lossy field cannot keep (code it losslessly)");
          v.bits.push_back(bits_of(value, f.type));
          continue;
        }
        const uint32_t a = nodes[e].corners[0], b = nodes[e].corners[1];
        if (a >= points || b >= points)
          return invalid_input("an edge node on an edge whose corner is not a point");
        const double va = value_of(v.bits[a * n + c], f.type), vb = value_of(v.bits[b * n + c], f.type);
        v.bits.push_back(bits_of(is_float(f.type) ? (va + vb) / 2 : std::min(va, vb), f.type));
      }
  }
  return Status::Ok();
}

// Each input point's vertex in the decoder's order (`decode_order`: the
// grid point of each decoded vertex).
std::vector<uint32_t> vertex_of_input(const QuantizedPoints& q, std::span<const uint32_t> decode_order) {
  std::vector<uint32_t> vertex_of_point(q.points.size());
  for (uint32_t v = 0; v < decode_order.size(); ++v) vertex_of_point[decode_order[v]] = v;
  std::vector<uint32_t> out;
  out.reserve(q.input_to_point.size());
  for (uint32_t p : q.input_to_point) out.push_back(vertex_of_point[p]);
  return out;
}

// Input cells that are flat on the grid, and those turned the other way
// than most (a mesh's cells all turn one way).
struct CellTurns {
  uint64_t flat = 0, turned = 0;
  size_t first = SIZE_MAX;  // the first cell flat or turned, where there is one
};
CellTurns cell_turns(std::span<const GridPoint> points, std::span<const std::array<uint32_t, 4>> tets) {
  uint64_t positive = 0, negative = 0, flat = 0;
  const auto turn = [&](const std::array<uint32_t, 4>& t) {
    return orientation(points[t[0]], points[t[1]], points[t[2]], points[t[3]]);
  };
  for (const auto& t : tets) {
    const int o = turn(t);
    (o > 0 ? positive : o < 0 ? negative : flat) += 1;
  }
  CellTurns out{flat, std::min(positive, negative)};
  const int most = positive >= negative ? 1 : -1;
  if (out.flat + out.turned > 0)
    for (size_t i = 0; i < tets.size() && out.first == SIZE_MAX; ++i)
      if (turn(tets[i]) != most) out.first = i;
  return out;
}
uint64_t turned_cells(std::span<const GridPoint> points, std::span<const std::array<uint32_t, 4>> tets) {
  const CellTurns turns = cell_turns(points, tets);
  return turns.flat + turns.turned;
}

// The input's cell data of `count` reference tetrahedra, the k-th being
// tet_at(k) (`source` maps a reference tetrahedron to the input's own
// numbering, or is empty), one FieldValues per array, cell-major.
template <class TetAt>
std::vector<FieldValues> reference_cell_values(const EncodeInput& input,
                                               std::span<const FieldDescription> descriptions,
                                               std::span<const int32_t> source, size_t count,
                                               TetAt&& tet_at) {
  std::vector<FieldValues> out;
  out.reserve(input.cell_fields.size());
  for (size_t k = 0; k < input.cell_fields.size(); ++k) {
    const auto& f = input.cell_fields[k];
    FieldValues& v = out.emplace_back(FieldValues{descriptions[k], {}});
    const size_t n = static_cast<size_t>(f.components);
    v.bits.reserve(count * n);
    for (size_t j = 0; j < count; ++j) {
      const size_t t = tet_at(j);
      const size_t i = source.empty() ? t : static_cast<size_t>(source[t]);
      for (size_t c = 0; c < n; ++c) v.bits.push_back(bits_of(f.values[i * n + c], f.type));
    }
  }
  return out;
}

// A bricked stream: the levels built block by block, on the ranks of
// options.exchange if given (codec/blocks/bricked_encoder.h).
StatusOr<EncodedMesh> encode_in_bricks(const EncodeInput& input, const EncodeOptions& options,
                                       const EncodePlan& plan, std::span<const std::array<uint32_t, 4>> tets,
                                       std::span<const uint8_t> tet_regions, const Solid* voxels,
                                       std::vector<FieldValues> fields, std::vector<FieldValues> cell_fields,
                                       const FaceTagger* faces, EncodedMesh out, const LevelReady& on_level) {
  if (!options.carve_to_reference)
    return invalid_input(
        "bricked layers (--bricks) need the codec preset: its levels carve to the input's solid");
  if (options.level_step != 1)
    return invalid_input("bricked layers (--bricks) stream every level (no --level-step)");
  const QuantizedPoints& q = plan.quantized;
  EncodeReport& report = out.report;
  // On the ranks of a run each may hold only its share of the tetrahedra
  // (codec/blocks/reference_share.h): the count is of every rank's own.
  std::optional<ReferenceShare> made;
  const ReferenceShare* share = options.reference_share;
  if (options.exchange && options.exchange->size() > 1) {
    if (!share)
      share = &made.emplace(q.points, q.grid.qbits, options.exchange->rank(), options.exchange->size());
    ByteWriter w;
    w.u64(static_cast<uint64_t>(
        std::count_if(tets.begin(), tets.end(), [&](const auto& t) { return share->owns(t); })));
    report.reference_tetrahedra = 0;
    for (const auto& bytes : options.exchange->all_gather(w.take())) {
      uint64_t own = 0;
      ByteReader(bytes).u64(own);
      report.reference_tetrahedra += own;
    }
  }
  const bool has_tets = report.reference_tetrahedra > 0;
  BrickedEncodeInput in;
  in.points = q.points;
  in.grid = plan.stream_grid;
  in.reference_tets = tets;
  in.reference_regions = tet_regions;
  in.regions = report.regions;
  in.reference_tets_done = input.tetrahedra_done;
  in.voxels = voxels;
  in.share = share;
  in.faces = faces;
  if (faces) in.face_tags = report.face_tags;
  // The value tables (a lossy field's bound may be too small for its values:
  // on ranks, refused by all of them together).
  Status tables = Status::Ok();
  const auto make_table = [&](std::vector<FieldValues> of, std::optional<FieldSectionEncoder>& table,
                              const FieldSectionEncoder*& used) {
    if (of.empty() || !tables.ok()) return;
    auto made = FieldSectionEncoder::make(std::move(of));
    if (!made.ok()) {
      tables = made.status();
      return;
    }
    table.emplace(std::move(made).value());
    used = &*table;
  };
  std::optional<FieldSectionEncoder> values, cell_values;  // cell_values: per reference tetrahedron
  make_table(std::move(fields), values, in.values);
  make_table(std::move(cell_fields), cell_values, in.cell_values);
  if (options.exchange && options.exchange->size() > 1) tables = agreed(*options.exchange, tables);
  DTM_RETURN_IF_ERROR(tables);
  BrickedEncodeOptions o;
  o.hierarchy = hierarchy_options(options, q.grid, plan.dmax);
  o.brick_points = options.brick_points;
  o.block_points = options.block_points;
  o.blocks_at_once = options.blocks_at_once;
  o.check_parts = options.check_parts;
  o.reuse_build_mesh = options.reuse_build_mesh;
  o.cell_hashes = options.cell_hashes;
  o.decode_order = options.vertex_of_input;  // what it is made for
  o.exchange = options.exchange;
  DTM_ASSIGN_OR_RETURN(BrickedEncoding encoded, encode_bricked(in, o, [&](const LevelStats& stats) {
                         LevelReport r;
                         r.stats = stats;
                         if (has_tets && stats.reference_shape) {
                           r.reference_to_level = stats.reference_shape->to_level;
                           r.level_to_reference = stats.reference_shape->to_reference;
                           r.reference_error = stats.reference_shape->both;
                         }
                         report.levels.push_back(r);
                         if (on_level) on_level(report.levels.back());
                       }));
  const size_t L = encoded.levels.size();
  report.layer_bytes = std::move(encoded.layer_bytes);
  report.carving_bytes = std::move(encoded.carving_bytes);
  if (!report.regions.empty()) report.region_bytes = std::move(encoded.region_bytes);
  report.region_table_bytes = encoded.region_table_bytes;
  if (faces) {
    report.face_bytes = std::move(encoded.face_bytes);
    report.face_table_bytes = encoded.face_table_bytes;
    report.tagged_faces_kept = encoded.tagged_faces_kept;
  }
  report.candidate_bytes.assign(L, 0);
  report.candidate_points.assign(L, 0);
  report.value_bytes = std::move(encoded.value_bytes);
  report.level_field_bytes = std::move(encoded.level_field_bytes);
  report.field_table_bytes = encoded.field_table_bytes;
  if (cell_values) {
    for (size_t f = 0; f < cell_values->descriptions().size(); ++f)
      report.cell_fields.push_back({cell_values->descriptions()[f],
                                    f < encoded.cell_field_bytes.size() ? encoded.cell_field_bytes[f] : 0});
    report.cell_field_table_bytes = encoded.cell_field_table_bytes;
    report.cell_value_bytes = encoded.cell_value_bytes;
    report.level0_cells = encoded.levels.empty() ? 0 : encoded.levels[0].tetrahedra;
    report.cells_from_input = encoded.cells_from_input;
    report.cells_from_nearest = encoded.cells_from_nearest;
  }
  if (values)
    for (size_t f = 0; f < values->descriptions().size(); ++f) {
      uint64_t bytes = 0;
      for (const auto& level : report.level_field_bytes)
        if (f < level.size()) bytes += level[f];
      report.fields.push_back({values->descriptions()[f], bytes});
    }
  for (size_t l = 0; l < L; ++l) report.streamed_levels.push_back(static_cast<int>(l));
  report.stream_bytes = encoded.bytes.size();
  report.reference_boundary_vertices = encoded.reference_boundary_vertices;
  report.reference_questions = encoded.reference_questions;
  report.reference_question_runs = encoded.reference_question_runs;
  report.blocks_built_again = encoded.blocks_built_again;
  report.blocks_checked_in_parts = encoded.blocks_checked_in_parts;
  report.levels_analysed_from_build = encoded.levels_analysed_from_build;
  report.level0_spacing_kept_radius = encoded.level0_spacing_kept_radius;
  report.level0_kept_radius = encoded.level0_kept_radius;
  report.level0_cells_dropped = encoded.level0_cells_dropped;
  report.reference_questions_at_once = encoded.reference_questions_at_once;
  out.bytes = std::move(encoded.bytes);
  if (options.vertex_of_input) out.vertex_of_input = vertex_of_input(q, encoded.decode_order);
  return out;
}

}  // namespace

namespace {

// The input's edge nodes (a second-order mesh's) named by their corners'
// grid ids, in `grid`'s units.
StatusOr<std::vector<GridEdgeNode>> edge_nodes_on_grid(const EncodeInput& input, const QuantizedPoints& q,
                                                       const Grid& grid) {
  // Each corner's grid id and input point (exact mode: no two points share
  // a grid point, so the grid ids name the input's points one to one).
  const size_t n = q.input_to_point.size();
  std::vector<uint32_t> input_of_grid;
  if (input.tetrahedra_on_grid) {
    input_of_grid.assign(q.points.size(), UINT32_MAX);
    for (size_t i = 0; i < n; ++i) input_of_grid[q.input_to_point[i]] = static_cast<uint32_t>(i);
  }
  std::vector<GridEdgeNode> out;
  out.reserve(input.edge_nodes.size());
  for (const EncodeInput::EdgeNode& e : input.edge_nodes) {
    GridEdgeNode g;
    std::array<InputPoint, 2> ends;
    for (size_t k = 0; k < 2; ++k) {
      const uint32_t v = e.corners[k];
      const uint32_t in =
          input.tetrahedra_on_grid ? (v < input_of_grid.size() ? input_of_grid[v] : UINT32_MAX) : v;
      if (in >= n || in >= input.points.size())
        return invalid_input("an edge node on an edge whose corner is not a point");
      g.corners[k] = q.input_to_point[in];
      ends[k] = input.points[in];
    }
    const std::array<double, 3> at = {e.at.x, e.at.y, e.at.z};
    const std::array<double, 3> a = {ends[0].x, ends[0].y, ends[0].z}, b = {ends[1].x, ends[1].y, ends[1].z};
    // (The midpoint as a mesher computes it, to within rounding.)
    double length = 0, off = 0;
    for (size_t axis = 0; axis < 3; ++axis) {
      length = std::max(length, std::abs(b[axis] - a[axis]));
      off = std::max(off, std::abs(at[axis] - (a[axis] + b[axis]) / 2));
      g.at[axis] = (at[axis] - grid.origin[axis]) / grid.step;
    }
    g.midpoint = off <= 1e-9 * length;
    out.push_back(g);
  }
  return out;
}

}  // namespace

Status check_exact_grid(std::span<const InputPoint> points,
                        std::span<const std::array<uint32_t, 4>> tetrahedra, const EncodePlan& plan) {
  const QuantizedPoints& q = plan.quantized;
  // (Named as given: in the order given, from 0, as meshenc's file lists them.)
  const auto cell_named = [](size_t i) {
    return "input cell " + std::to_string(i) + " (from 0, in the order given)";
  };
  // A cell naming a point twice is no tetrahedron on any grid.
  for (size_t i = 0; i < tetrahedra.size(); ++i) {
    std::array<uint32_t, 4> t = tetrahedra[i];
    std::sort(t.begin(), t.end());
    if (t[0] == t[1] || t[1] == t[2] || t[2] == t[3])
      return invalid_input(cell_named(i) +
                           " names a point twice: it cannot be kept as a tetrahedron (mend the "
                           "input)");
  }
  // What goes wrong on a grid of `bits` bits, if anything, with the first
  // points or cell it happens to; `turns` (if given) the cells' turns
  // there, where every cell keeps its corners.
  const auto problem = [&](const QuantizedPoints& grid, CellTurns* turns = nullptr) -> std::string {
    if (grid.duplicates_merged > 0) {
      std::vector<uint32_t> first_at(grid.points.size(), UINT32_MAX);
      for (uint32_t i = 0; i < grid.input_to_point.size(); ++i) {
        uint32_t& first = first_at[grid.input_to_point[i]];
        if (first != UINT32_MAX)
          return std::to_string(grid.duplicates_merged) +
                 " points share a grid point with another (the first: " + "points " + std::to_string(first) +
                 " and " + std::to_string(i) + ", from 0, in the order given)";
        first = i;
      }
    }
    // The cells on the grid in the order given (grid_tetrahedra_in_place()
    // would sort them: the first named would not be the input's), each
    // keeping its corners (no two points share a grid point here).
    std::vector<std::array<uint32_t, 4>> tets(tetrahedra.size());
    for (size_t i = 0; i < tets.size(); ++i)
      for (size_t k = 0; k < 4; ++k) tets[i][k] = grid.input_to_point[tetrahedra[i][k]];
    const CellTurns found = cell_turns(grid.points, tets);
    if (turns) *turns = found;
    if (found.flat + found.turned > 0)
      return std::to_string(found.flat + found.turned) +
             " input cells are flat or turned over (the first: " + cell_named(found.first) + ")";
    return {};
  };
  const std::string now = problem(q);
  if (now.empty()) return Status::Ok();
  // (Where no grid does, the input itself: points that coincide there, or
  // cells flat there.)
  std::string fix = q.duplicates_merged > 0 ? "no grid of up to 24 bits does: do they coincide in the input?"
                                            : "no grid of up to 24 bits does: are they flat in the input?";
  for (int bits = q.grid.qbits + 1; bits <= 24; ++bits) {
    const auto finer = quantize(points, bits, plan.scale);
    if (!finer.ok()) continue;
    CellTurns turns;
    if (problem(*finer, &turns).empty()) {
      fix = "--qbits " + std::to_string(bits) + " keeps them apart";
      break;
    }
    // (On the finest grid, cells that turn the other way and none flat: the
    // input's own orientation, which no grid mends.)
    if (bits == 24 && turns.flat == 0 && turns.turned > 0)
      return invalid_input(
          std::to_string(turns.turned) +
          " input cells turn the other way from the rest (the first: " + cell_named(turns.first) +
          "; the input's own orientation, not the grid's): reorient them to keep the cells "
          "exactly");
  }
  return invalid_input(now + " on the grid of q=" + std::to_string(q.grid.qbits) +
                       ": the input's cells cannot be kept exactly (" + fix + ")");
}

StatusOr<EncodePlan> plan_encoding(const EncodeInput& input, const EncodeOptions& options) {
  DTM_RETURN_IF_ERROR(check_options(options));
  if (input.lattice && input.lattice->input_to_point.size() != input.points.size())
    return invalid_input("the lattice and the points differ in count");
  EncodePlan plan;
  plan.scale = options.scale;
  if (options.box > 0) {
    const double extent = largest_extent(input.points);
    plan.scale = extent > 0 ? options.box / extent : 1.0;
  }
  if (input.lattice) {
    // The lattice's own grid is the stream's: its positions stay exact.
    DTM_ASSIGN_OR_RETURN(plan.quantized, lattice_grid(*input.lattice, options.qbits));
    plan.stream_grid = plan.quantized.grid;
    plan.quantized.grid = scaled(plan.stream_grid, plan.scale);
  } else {
    DTM_ASSIGN_OR_RETURN(plan.quantized,
                         quantize(input.points, options.qbits > 0 ? options.qbits : 14, plan.scale));
    plan.stream_grid = unscaled(plan.quantized.grid, plan.scale);
  }
  const Grid& grid = plan.quantized.grid;
  // By default 0.5% of the input's largest extent: a point set's spans the
  // grid; a lattice's grid is the volume's (and --qbits may widen it), so
  // there the extent is that of its points, the solid's voxels.
  double extent = (1u << grid.qbits) - 1;
  if (input.lattice && !plan.quantized.points.empty()) {
    GridPoint lo = plan.quantized.points.front(), hi = lo;
    for (const GridPoint& p : plan.quantized.points) {
      lo = {std::min(lo.x, p.x), std::min(lo.y, p.y), std::min(lo.z, p.z)};
      hi = {std::max(hi.x, p.x), std::max(hi.y, p.y), std::max(hi.z, p.z)};
    }
    extent = std::max({hi.x - lo.x, hi.y - lo.y, hi.z - lo.z, 1});
  }
  plan.dmax = options.dmax > 0 ? options.dmax : 0.005 * grid.step * extent;
  return plan;
}

namespace {

// encode() from `plan`; `input_map`: the plan's map from input points, to
// free once it is read no more when the caller wants no vertex_of_input
// (null: kept).
StatusOr<EncodedMesh> encode_planned(const EncodeInput& input, const EncodeOptions& options,
                                     const EncodePlan& plan, std::vector<uint32_t>* input_map,
                                     const LevelReady& on_level) {
  const QuantizedPoints& q = plan.quantized;
  EncodedMesh out;
  EncodeReport& report = out.report;
  report.grid = q.grid;
  report.stream_grid = plan.stream_grid;
  report.scale = plan.scale;
  report.dmax = plan.dmax;
  report.lattice = input.lattice != nullptr;
  // The input's points are counted by the plan's map (a caller may free
  // them once the plan is made: they are read no more).
  report.input_points = q.input_to_point.size();
  report.duplicates_merged = q.duplicates_merged;

  // The fields are checked before the (long) hierarchy is built.
  DTM_ASSIGN_OR_RETURN(std::vector<FieldValues> fields,
                       grid_point_fields(input, options, q, report.merged_points_with_other_values));

  // The input's tetrahedra on the grid: the reference solid.
  std::vector<std::array<uint32_t, 4>> converted;
  std::span<const std::array<uint32_t, 4>> reference_tets;
  std::vector<int32_t> labels;  // per reference tetrahedron, with regions
  // Per reference tetrahedron, its index in input.tetrahedra (with cell
  // data, when the encoder puts them on the grid itself).
  std::vector<int32_t> source;
  const bool with_cells = !input.cell_fields.empty();
  const bool with_regions = !input.tetrahedron_regions.empty();
  const bool with_faces = !input.tagged_faces.empty();
  std::vector<FieldDescription> cell_descriptions;  // checked here, before the long work
  // The input checked, and on the ranks of a bricked run every rank's
  // verdict shared (a rank given other tetrahedra or arrays than the others
  // may refuse alone, and leave them waiting in their next exchange).
  Status checked = [&]() -> Status {
    if (with_cells) {
      if (input.tetrahedra.empty()) return invalid_input("cell data needs the tetrahedra it belongs to");
      if (!options.carve_to_reference)
        return invalid_input("cell data needs the levels carved to the input's solid (not the paper preset)");
      std::vector<size_t> value_counts;
      for (const auto& f : input.cell_fields) {
        cell_descriptions.push_back(described(f, options));
        value_counts.push_back(f.values.size());
      }
      DTM_RETURN_IF_ERROR(check_fields(cell_descriptions, value_counts, input.tetrahedra.size(), "tetrahedra")
                              .with_context("cell data"));
      for (size_t k = 0; k < input.cell_fields.size(); ++k) {
        const auto& f = input.cell_fields[k];
        DTM_RETURN_IF_ERROR(
            check_field_values(cell_descriptions[k], f.values, "cell").with_context("cell data"));
        // (Named here by the input's cell: the coder's own check counts
        // level 0's cells.)
        if (cell_descriptions[k].lossy)
          for (size_t i = 0; i < f.values.size(); ++i)
            if (!std::isfinite(f.values[i]))
              return invalid_input("cell data: field '" + f.name + "': cell " +
                                   std::to_string(i / f.components) + " holds " +
                                   (std::isnan(f.values[i]) ? "NaN" : "an infinity") +
                                   ", which a lossy field cannot keep (code it losslessly)");
      }
    }
    if (with_regions) {
      if (input.tetrahedron_regions.size() != input.tetrahedra.size())
        return invalid_input("a region is needed for every tetrahedron");
      if (!options.carve_to_reference)
        return invalid_input("regions need the levels carved to the input's solid (not the paper preset)");
    }
    if (with_faces) {
      if (input.face_tags.size() != input.tagged_faces.size())
        return invalid_input("a tag is needed for every face");
      if (input.tetrahedra.empty()) return invalid_input("tagged faces need the tetrahedra they bound");
      if (!options.carve_to_reference)
        return invalid_input(
            "tagged faces need the levels carved to the input's solid (not the paper preset)");
      for (const auto& f : input.tagged_faces)
        for (uint32_t v : f)
          if (v >= q.input_to_point.size())
            return invalid_input("a tagged face names a point that does not exist");
    }
    if (!input.tetrahedra.empty()) {
      const size_t points = input.tetrahedra_on_grid ? q.points.size() : q.input_to_point.size();
      for (const auto& t : input.tetrahedra)
        for (uint32_t v : t)
          if (v >= points) return invalid_input("a tetrahedron names a point that does not exist");
      if (with_regions) labels.assign(input.tetrahedron_regions.begin(), input.tetrahedron_regions.end());
      if (input.tetrahedra_on_grid) {
        reference_tets = input.tetrahedra;
      } else {
        converted.assign(input.tetrahedra.begin(), input.tetrahedra.end());
        if (with_cells) {
          // The index travels (and the regions follow it).
          source.resize(converted.size());
          for (size_t i = 0; i < source.size(); ++i) source[i] = static_cast<int32_t>(i);
          grid_tetrahedra_in_place(converted, q, &source);
          if (with_regions)
            for (size_t i = 0; i < source.size(); ++i)
              labels[i] = input.tetrahedron_regions[static_cast<size_t>(source[i])];
          if (with_regions) labels.resize(source.size());
        } else {
          grid_tetrahedra_in_place(converted, q, with_regions ? &labels : nullptr);
        }
        reference_tets = converted;
      }
      report.reference_tetrahedra = reference_tets.size();
    }
    if (options.keep_order) {
      if (options.bricks) return invalid_input("bricked streams do not keep the input's vertex order yet");
      if (!options.carve_to_reference)
        return invalid_input("keeping the vertex order needs the codec preset (not the paper preset)");
      if (q.duplicates_merged > 0)
        return invalid_input(std::to_string(q.duplicates_merged) +
                             " points share a grid point with another at q=" + std::to_string(q.grid.qbits) +
                             ": the input's numbering cannot be kept (raise --qbits, or merge them first)");
    }
    if (options.exact) {
      if (options.bricks) return invalid_input("bricked streams do not keep the input's cells exactly yet");
      if (!options.carve_to_reference)
        return invalid_input("exact cells need the codec preset (not the paper preset)");
      if (reference_tets.empty()) return invalid_input("--exact needs the input's tetrahedra");
      if (input.tetrahedra_on_grid) {
        // (The caller put them on the grid: it checked them there, check_exact_grid.)
        if (q.duplicates_merged > 0 || turned_cells(q.points, reference_tets) > 0)
          return invalid_input("the input's points or cells do not stay apart on the grid of q=" +
                               std::to_string(q.grid.qbits) +
                               ": they cannot be kept exactly (raise --qbits)");
      } else {
        DTM_RETURN_IF_ERROR(check_exact_grid(input.points, input.tetrahedra, plan));
      }
    }
    return Status::Ok();
  }();
  if (options.bricks && options.exchange && options.exchange->size() > 1)
    checked = agreed(*options.exchange, checked);
  DTM_RETURN_IF_ERROR(checked);
  // --exact of a second-order mesh: its edge nodes on the grid, read
  // before the points may be let go.
  std::vector<GridEdgeNode> grid_edge_nodes;
  if (options.exact && !input.edge_nodes.empty()) {
    DTM_ASSIGN_OR_RETURN(grid_edge_nodes, edge_nodes_on_grid(input, q, plan.stream_grid));
    DTM_RETURN_IF_ERROR(append_edge_node_values(input, grid_edge_nodes, fields));
  }
  if (input.points_done) input.points_done();
  // The paper preset does not carve to the reference: it is only measured.
  std::optional<ReferenceShape> measured_only;
  if (!reference_tets.empty() && !options.carve_to_reference) measured_only.emplace(q.points, reference_tets);
  HierarchyOptions hierarchy = hierarchy_options(options, q.grid, plan.dmax);
  hierarchy.reference_cells = reference_tets;
  // The regions: the labels in ascending order make the table; each
  // tetrahedron holds its label's index + 1. One region needs no solid of
  // its own: every kept cell is in it.
  std::vector<uint8_t> region_index;
  std::vector<int32_t> distinct = distinct_labels(labels);
  // Each rank of a bricked run holds a share of the tetrahedra: the table
  // is of all of them (every rank asks, holding regions or not).
  if (options.bricks && options.exchange && options.exchange->size() > 1)
    distinct = labels_of_every_rank(*options.exchange, distinct);
  if (!distinct.empty()) {
    if (distinct.size() > kMaxRegionCount)
      return invalid_input("the input has " + std::to_string(distinct.size()) +
                           " regions; a stream holds at most " + std::to_string(kMaxRegionCount));
    report.regions = label_table(distinct, input.region_names, report.names_cut);
    if (distinct.size() > 1) {
      region_index.reserve(labels.size());
      for (int32_t label : labels)
        region_index.push_back(static_cast<uint8_t>(
            std::lower_bound(distinct.begin(), distinct.end(), label) - distinct.begin() + 1));
      hierarchy.reference_regions = region_index;
    }
    release(labels);
  }
  // The tagged faces: the tags in ascending order make the table; each face
  // is labelled 2 + its tag's index (1: no tag), on the grid.
  std::optional<FaceTagger> tagger;
  std::vector<int32_t> face_distinct = distinct_labels(input.face_tags);
  // (On the ranks of a bricked run, the table is of every rank's tags, and
  // every rank asks: one given no tagged face refuses with the others, in
  // encode_bricked()'s check.)
  if (options.bricks && options.exchange && options.exchange->size() > 1)
    face_distinct = labels_of_every_rank(*options.exchange, face_distinct);
  // Names of labels nothing has are refused (on the ranks of a bricked run,
  // all of them refuse, none waits: the tables are every rank's).
  Status named = Status::Ok();
  if (const auto label = name_without_label(input.region_names, distinct))
    named =
        invalid_input("region_names names region " + std::to_string(*label) + ", which no tetrahedron has");
  else if (const auto tag = name_without_label(input.face_tag_names, face_distinct))
    named = invalid_input("face_tag_names names tag " + std::to_string(*tag) + ", which no tagged face has");
  if (options.bricks && options.exchange && options.exchange->size() > 1)
    named = agreed(*options.exchange, named);
  DTM_RETURN_IF_ERROR(named);
  // (The same on every rank: all of them refuse, none waits.)
  if (face_distinct.size() > kMaxFaceTags)
    return invalid_input("the input's faces have " + std::to_string(face_distinct.size()) +
                         " tags; a stream holds at most " + std::to_string(kMaxFaceTags));
  if (with_faces) {
    const std::vector<int32_t>& distinct = face_distinct;
    report.face_tags = label_table(distinct, input.face_tag_names, report.names_cut);
    std::vector<std::array<uint32_t, 3>> faces;
    std::vector<uint8_t> face_label;
    for (size_t i = 0; i < input.tagged_faces.size(); ++i) {
      std::array<uint32_t, 3> g;
      for (int k = 0; k < 3; ++k)  // (each point checked above)
        g[static_cast<size_t>(k)] = q.input_to_point[input.tagged_faces[i][static_cast<size_t>(k)]];
      if (g[0] == g[1] || g[1] == g[2] || g[0] == g[2]) continue;  // collapsed by quantization
      faces.push_back(g);
      face_label.push_back(static_cast<uint8_t>(
          std::lower_bound(distinct.begin(), distinct.end(), input.face_tags[i]) - distinct.begin() + 2));
    }
    report.tagged_faces = faces.size();
    tagger.emplace(q.points, region_surface_triangles(reference_tets, region_index), faces, face_label);
  }
  // A scan's voxels are its solid (without tetrahedra to say otherwise).
  std::optional<VoxelSolid> voxels;
  if (input.voxels && reference_tets.empty() && options.carve_to_reference) {
    hierarchy.reference_solid = &voxels.emplace(*input.voxels, q.grid, plan.scale);
    report.reference_voxels = static_cast<uint64_t>(
        std::count(input.voxels->inside.begin(), input.voxels->inside.end(), uint8_t{1}));
  }
  // The map from input points is read no more unless it makes the caller's
  // vertex_of_input, or the stream keeps the input's order.
  if (input_map && !options.vertex_of_input && !options.keep_order) release(*input_map);
  if (options.bricks) {
    // Cell data travels with the tetrahedra: each reference tetrahedron's
    // values, which the blocks give the level-0 cells they own.
    std::vector<FieldValues> tet_values = reference_cell_values(
        input, cell_descriptions, source, reference_tets.size(), [](size_t t) { return t; });
    return encode_in_bricks(input, options, plan, reference_tets, region_index, voxels ? &*voxels : nullptr,
                            std::move(fields), std::move(tet_values), tagger ? &*tagger : nullptr,
                            std::move(out), on_level);
  }
  // Under --exact the decoded level 0 is the input's cells, not the carving
  // the builder measured: its row gives theirs.
  std::optional<ExactLevel0> exact_level0;
  if (options.exact)
    exact_level0 = measure_exact_level0(q.points, reference_tets, !hierarchy.reference_regions.empty());
  DTM_ASSIGN_OR_RETURN(const Hierarchy h, build_hierarchy(q.points, hierarchy, [&](const Level& level) {
                         LevelReport r;
                         r.stats = level.stats;
                         if (measured_only) {
                           const ShapeMeasurement d = measured_only->distance(level.carved_cells(), q.points);
                           r.reference_error = d.both;
                           r.reference_to_level = d.to_level;
                           r.level_to_reference = d.to_reference;
                         } else if (!reference_tets.empty() && level.stats.reference_shape) {
                           // The codec's builder measured it, to check the level.
                           r.reference_to_level = level.stats.reference_shape->to_level;
                           r.level_to_reference = level.stats.reference_shape->to_reference;
                           r.reference_error = level.stats.reference_shape->both;
                         }
                         if (exact_level0 && level.stats.level == 0) exact_level0->describe(r);
                         report.levels.push_back(r);
                         if (on_level) on_level(report.levels.back());
                       }));

  if (!reference_tets.empty())
    report.reference_boundary_vertices =
        measured_only ? measured_only->boundary_vertices() : h.reference_boundary_vertices;
  if (exact_level0)
    report.level0_difference = exact_level0->difference();
  else if (h.level0_difference)
    report.level0_difference = h.level0_difference;
  else if (!reference_tets.empty() && !h.levels.empty())
    report.level0_difference = solid_difference(q.points, h.levels.front().carved_cells(), reference_tets);

  report_phase(options.on_phase, "writing the stream");
  give_back_free_heap();  // what the levels' builds freed
  StreamOptions stream_options;
  stream_options.cell_hashes = options.cell_hashes;
  stream_options.level_step = options.level_step;
  stream_options.candidates = options.candidates;
  stream_options.regions = report.regions;
  stream_options.face_tags = report.face_tags;
  stream_options.faces = tagger ? &*tagger : nullptr;
  if (options.keep_order) stream_options.input_order = q.input_to_point;
  if (options.exact) {
    stream_options.exact_cells = reference_tets;
    stream_options.exact_ranks = options.exact_ranks;
    // (Edge nodes written for decoders older than 21.0 come with the exact
    // cells those decoders read: 14.0's.)
    if ((options.edge_nodes_v18 || options.edge_nodes_v19 || options.edge_nodes_v20) &&
        options.exact_ranks == ApexRanks::kClosingFirst)
      stream_options.exact_ranks = ApexRanks::kAfterFlips;
    stream_options.edge_nodes_v18 = options.edge_nodes_v18;
    stream_options.edge_nodes_v19 = options.edge_nodes_v19;
    if (region_index.size() == reference_tets.size()) stream_options.exact_labels = region_index;
    stream_options.edge_nodes = grid_edge_nodes;
    // (21.0's: 18.0 and 19.0 streams, asked for by name, put the nodes after
    // the vertices.)
    if (options.keep_order && !grid_edge_nodes.empty() && !options.edge_nodes_v18 &&
        !options.edge_nodes_v19 && !options.edge_nodes_v20)
      stream_options.node_numbering = input.node_numbering;
  }
  // The input's node labels (22.0) where the stream keeps the nodes they
  // name: the points, and the edge nodes only with their numbering.
  if (options.keep_order && !input.node_labels.empty() &&
      (stream_options.edge_nodes.empty() || !stream_options.node_numbering.empty()))
    stream_options.node_labels = input.node_labels;
  if (with_cells)
    stream_options.cell_values =
        [&](std::span<const std::array<uint32_t, 4>> cells) -> StatusOr<std::vector<FieldValues>> {
      const CellSources from = cell_sources(q.points, reference_tets, cells);
      report.level0_cells = cells.size();
      report.cells_from_input = from.exact;
      report.cells_from_nearest = from.nearest;
      std::vector<FieldValues> out = reference_cell_values(input, cell_descriptions, source, cells.size(),
                                                           [&](size_t k) { return from.tetrahedron[k]; });
      return out;
    };
  DTM_ASSIGN_OR_RETURN(EncodedStream stream, encode_stream(h, q.points, plan.stream_grid, options.alpha,
                                                           stream_options, std::move(fields)));
  report.layer_bytes = std::move(stream.layer_bytes);
  report.carving_bytes = std::move(stream.carving_bytes);
  report.region_bytes = std::move(stream.region_bytes);
  report.region_table_bytes = stream.region_table_bytes;
  report.face_bytes = std::move(stream.face_bytes);
  report.face_table_bytes = stream.face_table_bytes;
  report.tagged_faces_kept = stream.tagged_faces_kept;
  report.candidate_bytes = std::move(stream.candidate_bytes);
  report.candidate_points = std::move(stream.candidate_points);
  report.value_bytes = std::move(stream.value_bytes);
  report.level_field_bytes = std::move(stream.level_field_bytes);
  for (size_t f = 0; f < stream.fields.size(); ++f)
    report.fields.push_back({stream.fields[f], stream.field_bytes[f],
                             f < stream.edge_node_field_bytes.size() ? stream.edge_node_field_bytes[f] : 0});
  report.field_table_bytes = stream.field_table_bytes;
  for (size_t f = 0; f < stream.cell_fields.size(); ++f)
    report.cell_fields.push_back({stream.cell_fields[f], stream.cell_field_bytes[f]});
  report.cell_field_table_bytes = stream.cell_field_table_bytes;
  report.cell_value_bytes = stream.cell_value_bytes;
  report.order_bytes = stream.order_bytes;
  report.exact_bytes = stream.exact_bytes;
  report.edge_node_bytes = stream.edge_node_bytes;
  report.node_order_bytes = stream.node_order_bytes;
  report.node_label_bytes = stream.node_label_bytes;
  report.node_labels_dropped = stream.node_labels_dropped;
  report.edge_nodes = stream.edge_nodes;
  report.moved_edge_nodes = stream.moved_edge_nodes;
  report.edge_value_bytes = stream.edge_value_bytes;
  report.edge_nodes_dropped = stream.edge_nodes_dropped;
  report.exact_delaunay_cells = stream.exact_delaunay_cells;
  report.exact = stream.exact;
  report.streamed_levels = std::move(stream.streamed_levels);
  report.stream_bytes = stream.bytes.size();
  out.bytes = std::move(stream.bytes);

  if (options.vertex_of_input) out.vertex_of_input = vertex_of_input(q, stream.decode_order);
  return out;
}

}  // namespace

StatusOr<EncodedMesh> encode(const EncodeInput& input, const EncodeOptions& options,
                             const LevelReady& on_level) {
  DTM_ASSIGN_OR_RETURN(EncodePlan plan, plan_encoding(input, options));
  return encode(input, options, std::move(plan), on_level);
}

StatusOr<EncodedMesh> encode(const EncodeInput& input, const EncodeOptions& options, const EncodePlan& plan,
                             const LevelReady& on_level) {
  return encode_planned(input, options, plan, nullptr, on_level);
}

StatusOr<EncodedMesh> encode(const EncodeInput& input, const EncodeOptions& options, EncodePlan&& plan,
                             const LevelReady& on_level) {
  return encode_planned(input, options, plan, &plan.quantized.input_to_point, on_level);
}

}  // namespace dtm
