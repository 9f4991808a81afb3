#include "report.h"

namespace dtm {

void print_table_header(std::FILE* out) {
  std::fprintf(out, "%5s %9s %9s %8s %8s %9s %9s %9s %9s %9s %9s\n", "level", "vertices",
               "boundary", "rm_int", "rm_bnd", "alpha", "tets", "avg_minSA", "min_SA",
               "max_err", "mean_err");
}

void print_table_row(std::FILE* out, const LevelStats& s, const Grid& g) {
  std::fprintf(out, "%5d %9llu %9llu %8llu %8llu %9.5g %9llu %9.6f %9.3g %9.4g %9.4g\n", s.level,
               (unsigned long long)s.vertices, (unsigned long long)s.boundary_vertices,
               (unsigned long long)s.removed_interior, (unsigned long long)s.removed_boundary,
               s.alpha * g.step, (unsigned long long)s.tetrahedra, s.avg_min_solid_angle,
               s.min_solid_angle, s.max_boundary_error * g.step, s.mean_boundary_error * g.step);
  std::fflush(out);
}

nlohmann::json level_json(const LevelStats& s, const Grid& g) {
  return {{"level", s.level},
          {"vertices", s.vertices},
          {"boundary_vertices", s.boundary_vertices},
          {"removed_interior", s.removed_interior},
          {"removed_boundary", s.removed_boundary},
          {"rejected_by_quality", s.rejected_by_quality},
          {"alpha", s.alpha * g.step},
          {"tetrahedra", s.tetrahedra},
          {"avg_min_solid_angle", s.avg_min_solid_angle},
          {"min_solid_angle", s.min_solid_angle},
          {"max_boundary_error", s.max_boundary_error * g.step},
          {"mean_boundary_error", s.mean_boundary_error * g.step}};
}

nlohmann::json report_json(const ReportContext& ctx, const std::vector<LevelStats>& levels) {
  nlohmann::json j;
  j["input"] = ctx.input;
  j["qbits"] = ctx.grid.qbits;
  j["origin"] = {ctx.grid.origin[0], ctx.grid.origin[1], ctx.grid.origin[2]};
  j["step"] = ctx.grid.step;
  j["scale"] = ctx.scale;
  j["duplicates_merged"] = ctx.duplicates_merged;
  j["levels"] = nlohmann::json::array();
  for (const auto& s : levels) {
    j["levels"].push_back(level_json(s, ctx.grid));
    if (static_cast<size_t>(s.level) < ctx.layer_bytes.size())
      j["levels"].back()["layer_bytes"] = ctx.layer_bytes[s.level];
    for (size_t k = 0; k < ctx.streamed_levels.size(); ++k)
      if (ctx.streamed_levels[k] == s.level) j["levels"].back()["stream_level"] = k;
  }
  if (ctx.stream_bytes > 0 && !levels.empty()) {
    j["stream_bytes"] = ctx.stream_bytes;
    j["bits_per_vertex"] = 8.0 * ctx.stream_bytes / levels.front().vertices;
  }
  return j;
}

}  // namespace dtm
