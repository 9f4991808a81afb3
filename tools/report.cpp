#include "tools/report.h"

namespace dtm {

void print_table_header(std::FILE* out, bool reference) {
  std::fprintf(out, "%5s %9s %9s %8s %8s %9s %9s %9s %9s %9s %9s%s\n", "level", "vertices", "boundary",
               "rm_int", "rm_bnd", "alpha", "tets", "avg_minSA", "min_SA", "max_err", "mean_err",
               reference ? "   ref>lvl max/mean   lvl>ref max/mean" : "");
}

void print_table_row(std::FILE* out, const LevelReport& level, const Grid& g) {
  const LevelStats& s = level.stats;
  std::fprintf(out, "%5d %9llu %9llu %8llu %8llu %9.5g %9llu %9.6f %9.3g %9.4g %9.4g", s.level,
               static_cast<unsigned long long>(s.vertices),
               static_cast<unsigned long long>(s.boundary_vertices),
               static_cast<unsigned long long>(s.removed_interior),
               static_cast<unsigned long long>(s.removed_boundary), s.alpha * g.step,
               static_cast<unsigned long long>(s.tetrahedra), s.avg_min_solid_angle, s.min_solid_angle,
               s.max_boundary_error * g.step, s.mean_boundary_error * g.step);
  if (level.reference_to_level && level.level_to_reference)
    std::fprintf(out, "   %8.4g / %-7.4g   %8.4g / %-7.4g", level.reference_to_level->max * g.step,
                 level.reference_to_level->mean * g.step, level.level_to_reference->max * g.step,
                 level.level_to_reference->mean * g.step);
  std::fprintf(out, "\n");
  std::fflush(out);
}

nlohmann::json level_json(const LevelStats& s, const Grid& g) {
  return {{"level", s.level},
          {"vertices", s.vertices},
          {"boundary_vertices", s.boundary_vertices},
          {"removed_interior", s.removed_interior},
          {"removed_boundary", s.removed_boundary},
          {"rejected_by_quality", s.rejected_by_quality},
          {"passes", s.passes},
          {"chosen", s.chosen},
          {"put_back", s.put_back},
          {"repair_rounds", s.repair_rounds},
          {"alpha", s.alpha * g.step},
          {"tetrahedra", s.tetrahedra},
          {"avg_min_solid_angle", s.avg_min_solid_angle},
          {"min_solid_angle", s.min_solid_angle},
          {"max_boundary_error", s.max_boundary_error * g.step},
          {"mean_boundary_error", s.mean_boundary_error * g.step}};
}

nlohmann::json report_json(const std::string& input, const EncodeReport& r) {
  const Grid& g = r.grid;
  nlohmann::json j;
  j["input"] = input;
  j["qbits"] = g.qbits;
  j["origin"] = {g.origin[0], g.origin[1], g.origin[2]};
  j["step"] = g.step;
  // The stream's grid, in the input's units (the decoded mesh's).
  j["stream_origin"] = {r.stream_grid.origin[0], r.stream_grid.origin[1], r.stream_grid.origin[2]};
  j["stream_step"] = r.stream_grid.step;
  j["scale"] = r.scale;
  j["dmax"] = r.dmax;
  j["duplicates_merged"] = r.duplicates_merged;
  j["input_points"] = r.input_points;
  if (r.reference_tetrahedra > 0) j["reference_tetrahedra"] = r.reference_tetrahedra;
  if (r.reference_voxels > 0) j["reference_voxels"] = r.reference_voxels;
  if (r.level0_kept_radius > 0)  // bricked, scaled input units
    j["level0_kept_radius"] = {{"from_spacing", r.level0_spacing_kept_radius * g.step},
                               {"used", r.level0_kept_radius * g.step},
                               {"cells_of_the_solid_dropped", r.level0_cells_dropped}};
  if (r.level0_difference) {
    const SolidDifference& d = *r.level0_difference;
    const double cube = g.step * g.step * g.step;
    j["level0_difference"] = {{"only_level0", d.only_first * cube},
                              {"only_input", d.only_second * cube},
                              {"input_volume", d.second_volume * cube},
                              {"share", d.second_volume > 0 ? d.symmetric() / d.second_volume : 0.0},
                              {"shared_tetrahedra", d.shared_cells}};
  }
  j["fields"] = nlohmann::json::array();
  for (const FieldReport& f : r.fields) {
    const FieldDescription& d = f.description;
    j["fields"].push_back({{"name", d.name},
                           {"type", value_type_name(d.type)},
                           {"components", d.components},
                           {"mode", d.lossy ? "lossy" : "lossless"},
                           {"error_bound", d.error_bound},
                           {"bytes", f.bytes}});
    if (r.edge_value_bytes > 0) j["fields"].back()["edge_value_bytes"] = f.edge_value_bytes;
  }
  if (!r.names_cut.empty()) j["names_cut"] = r.names_cut;
  if (!r.fields.empty()) {
    j["field_table_bytes"] = r.field_table_bytes;
    j["merged_points_with_other_values"] = r.merged_points_with_other_values;
  }
  if (!r.cell_fields.empty()) {
    j["cell_fields"] = nlohmann::json::array();
    for (const FieldReport& f : r.cell_fields) {
      const FieldDescription& d = f.description;
      j["cell_fields"].push_back({{"name", d.name},
                                  {"type", value_type_name(d.type)},
                                  {"components", d.components},
                                  {"mode", d.lossy ? "lossy" : "lossless"},
                                  {"error_bound", d.error_bound},
                                  {"bytes", f.bytes}});
    }
    j["cell_field_table_bytes"] = r.cell_field_table_bytes;
    j["cell_value_bytes"] = r.cell_value_bytes;
    j["level0_cells"] = r.level0_cells;
    j["cells_from_input"] = r.cells_from_input;
    j["cells_from_nearest"] = r.cells_from_nearest;
  }
  if (r.order_bytes > 0) j["order_bytes"] = r.order_bytes;
  if (r.node_order_bytes > 0) j["node_order_bytes"] = r.node_order_bytes;
  if (r.node_label_bytes > 0) j["node_label_bytes"] = r.node_label_bytes;
  if (r.edge_nodes > 0)
    j["edge_nodes"] = {{"bytes", r.edge_node_bytes},
                       {"nodes", r.edge_nodes},
                       {"moved", r.moved_edge_nodes},
                       {"value_bytes", r.edge_value_bytes}};
  if (r.edge_nodes_dropped > 0) j["edge_nodes_dropped"] = r.edge_nodes_dropped;
  if (r.node_labels_dropped) j["node_labels_dropped"] = true;
  if (r.exact_bytes > 0 || r.exact_delaunay_cells > 0)
    j["exact"] = {{"bytes", r.exact_bytes},
                  {"delaunay_cells", r.exact_delaunay_cells},
                  {"fill_cells", r.exact.fill_cells},
                  {"open_faces", r.exact.open_faces},
                  {"rank_zero", r.exact.rank_zero},
                  {"escapes", r.exact.escapes},
                  {"second_ring", r.exact.second_ring},
                  {"seeds", r.exact.seeds},
                  {"fit_work", r.exact.fit_work},
                  {"flip_candidates", r.exact.flip_candidates},
                  {"flips", r.exact.flips}};
  if (!r.regions.empty()) {
    j["regions"] = nlohmann::json::array();
    for (const RegionLabel& region : r.regions)
      j["regions"].push_back({{"label", region.label}, {"name", region.name}});
    j["region_table_bytes"] = r.region_table_bytes;
  }
  if (!r.face_tags.empty()) {
    j["face_tags"] = nlohmann::json::array();
    for (const RegionLabel& t : r.face_tags) j["face_tags"].push_back({{"label", t.label}, {"name", t.name}});
    j["face_table_bytes"] = r.face_table_bytes;
    j["tagged_faces"] = r.tagged_faces;
    j["tagged_faces_kept"] = r.tagged_faces_kept;
  }
  j["levels"] = nlohmann::json::array();
  for (const LevelReport& level : r.levels) {
    const LevelStats& s = level.stats;
    nlohmann::json row = level_json(s, g);
    if (static_cast<size_t>(s.level) < r.layer_bytes.size()) row["layer_bytes"] = r.layer_bytes[s.level];
    for (size_t k = 0; k < r.streamed_levels.size(); ++k)
      if (r.streamed_levels[k] == s.level) row["stream_level"] = k;
    if (level.reference_error) {
      row["reference_max_error"] = level.reference_error->max * g.step;
      row["reference_mean_error"] = level.reference_error->mean * g.step;
      row["reference_to_level_max"] = level.reference_to_level->max * g.step;
      row["reference_to_level_mean"] = level.reference_to_level->mean * g.step;
      row["level_to_reference_max"] = level.level_to_reference->max * g.step;
      row["level_to_reference_mean"] = level.level_to_reference->mean * g.step;
    }
    if (static_cast<size_t>(s.level) < r.carving_bytes.size())
      row["carving_bytes"] = r.carving_bytes[s.level];
    if (static_cast<size_t>(s.level) < r.value_bytes.size()) row["value_bytes"] = r.value_bytes[s.level];
    if (static_cast<size_t>(s.level) < r.region_bytes.size()) row["region_bytes"] = r.region_bytes[s.level];
    if (static_cast<size_t>(s.level) < r.face_bytes.size()) row["face_bytes"] = r.face_bytes[s.level];
    if (static_cast<size_t>(s.level) < r.candidate_bytes.size()) {
      row["candidate_bytes"] = r.candidate_bytes[s.level];
      row["candidate_points"] = r.candidate_points[s.level];
    }
    if (static_cast<size_t>(s.level) < r.level_field_bytes.size() && !r.level_field_bytes[s.level].empty()) {
      nlohmann::json per_field = nlohmann::json::object();
      for (size_t f = 0; f < r.fields.size(); ++f)
        per_field[r.fields[f].description.name] = r.level_field_bytes[s.level][f];
      row["field_bytes"] = per_field;
    }
    j["levels"].push_back(row);
  }
  if (r.stream_bytes > 0 && !r.levels.empty()) {
    j["stream_bytes"] = r.stream_bytes;
    j["bits_per_vertex"] = 8.0 * r.stream_bytes / r.levels.front().stats.vertices;
  }
  return j;
}

}  // namespace dtm
