// meshenc: reads a volume point set (a volume mesh, a point cloud or surface,
// or the solid of a voxel volume), builds its Delaunay level-of-detail
// hierarchy and prints the level table while it works.
#include <CLI/CLI.hpp>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <optional>

#include <unistd.h>

#include "codec/encoder.h"
#include "core/hierarchy.h"
#include "tools/atomic_file.h"
#include "tools/formats/input.h"
#include "tools/reference_shape.h"
#include "tools/report.h"

namespace {

constexpr const char* kExamples = R"(
Examples:
  meshenc torus_288.node --scale 25 --dmax 3
  meshenc bunny_10k.node -o bunny.dtm --box 256 --dmax 2 --report bunny.json
  meshenc mesh.node -o mesh.dtm --qbits 16 --levels 4 --quality-guard 0.05
  meshenc scan.ply -o scan.dtm --qbits 12
  meshenc ct.nhdr --threshold 300 --voxel-interior-step 2 -o ct.dtm --dmax 1.5

Inputs (by extension, or --format): TetGen .node (+ .ele), Medit .mesh, VTK
.vtk and .vtu, gmsh .msh (2.2, 4.1), PLY, OFF, OBJ, XYZ, NRRD .nrrd/.nhdr.
Only the vertices are encoded; per-vertex values in the file are read, checked
and kept aside; tetrahedra in the file are the reference shape that each
level's boundary is measured against (the line after the table, --report).

Voxel volumes: the solid is the voxels with value >= --threshold (or ==
--label); its points are every boundary voxel (a 6-neighbour outside the
solid) and the interior voxels whose indices are all multiples of
--voxel-interior-step. With isotropic axis-aligned spacing the voxel lattice
is the quantization grid (qbits = just enough for the selected extent, or
--qbits if larger): positions are coded losslessly. Anisotropic or oblique
spacing: voxel centres are placed at their physical positions and quantized
like any point set (lossy).

Dmax and --alpha values are in input units, after --scale/--box.)";

dtm::AlphaPolicy parse_alpha(const std::string& text, double step) {
  dtm::AlphaPolicy p;
  if (text == "paper") return p;
  if (text == "hull") {
    p.kind = dtm::AlphaPolicy::Kind::kConvexHull;
    return p;
  }
  size_t used = 0;
  double v = 0;
  try {
    v = std::stod(text, &used);
  } catch (...) {
    used = 0;
  }
  if (used != text.size() || !(v > 0))
    throw std::invalid_argument("--alpha must be 'paper', 'hull' or a positive number, got '" +
                                text + "'");
  p.kind = dtm::AlphaPolicy::Kind::kFixed;
  p.fixed_value = v / step;
  return p;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"meshenc: build the Delaunay level-of-detail hierarchy of a volume point set"};
  app.footer(kExamples);
  std::string input, output, report_path, alpha_text = "paper";
  int qbits = 14, levels = 0;
  double dmax = 0, scale = 0, box = 0, guard = 0;
  size_t min_base = 16;
  int level_step = 1;
  bool no_paper_stop = false, quiet = false, hash_cells = false, no_reference = false;
  std::string format_name;
  dtm::VolumeOptions volume;
  app.add_option("input", input, "input file: .node .mesh .vtk .vtu .msh .nrrd .nhdr .ply .off .obj .xyz")
      ->required();
  app.add_option("--format", format_name, std::string("input format, overriding the extension: ") +
                                              dtm::kInputFormatNames);
  auto* threshold_opt = app.add_option("--threshold", volume.threshold,
                                       "voxel volumes: the solid is the voxels with value >= T");
  app.add_option("--label", volume.label, "voxel volumes: the solid is the voxels with value == L")
      ->excludes(threshold_opt);
  app.add_option("--voxel-interior-step", volume.interior_step,
                 "voxel volumes: keep interior voxels whose indices are multiples of K (boundary voxels "
                 "are always kept)")
      ->capture_default_str()->check(CLI::PositiveNumber);
  app.add_option("-o,--output", output, "write the .dtm stream here ('-' = standard output)");
  app.add_flag("--no-reference", no_reference,
               "ignore the input's tetrahedra (no reference-shape error; a TetGen .ele is not even read)");
  app.add_flag("--hash-cells", hash_cells,
               "store each level's cell-set hash (lets meshdec --verify prove its meshes)");
  auto* qbits_opt = app.add_option("--qbits", qbits,
                                   "quantization bits per axis (1..24; voxel lattices: just enough by default)")
                        ->capture_default_str()->check(CLI::Range(1, 24));
  app.add_option("--dmax", dmax,
                 "boundary tolerance Dmax in input units (default: 0.5% of the largest extent)")
      ->check(CLI::PositiveNumber);
  auto* scale_opt = app.add_option("--scale", scale, "multiply input coordinates by this first")
                        ->check(CLI::PositiveNumber);
  app.add_option("--box", box, "scale the input so that its largest extent is this")
      ->check(CLI::PositiveNumber)->excludes(scale_opt);
  app.add_option("--levels", levels, "build at most this many coarser levels (0 = no limit)")
      ->check(CLI::NonNegativeNumber);
  app.add_option("--min-base", min_base, "never build a level with fewer vertices")
      ->capture_default_str();
  app.add_option("--alpha", alpha_text, "alpha policy: paper (eq. 2.1), hull, or a value")
      ->capture_default_str();
  app.add_option("--quality-guard", guard,
                 "accept a removal only if its new cells' smallest solid angle is >= "
                 "min(S, the star's); 0 = off")
      ->check(CLI::Range(0.0, 0.56));
  app.add_flag("--no-paper-stop", no_paper_stop,
               "do not stop at the first level that removes no boundary vertex");
  app.add_option("--level-step", level_step,
                 "stream every N-th level (and the coarsest): fewer levels of detail, fewer bits")
      ->capture_default_str()->check(CLI::Range(1, 1000));
  app.add_option("--report", report_path, "write the level table as JSON to this file");
  app.add_flag("-q,--quiet", quiet, "do not print the table");
  CLI11_PARSE(app, argc, argv);
  if (output == "-") quiet = true;  // standard output carries the stream

  try {
    std::optional<dtm::InputFormat> format;
    if (!format_name.empty()) {
      format = dtm::input_format_named(format_name);
      if (!format)
        throw std::invalid_argument("--format " + format_name + ": unknown (known: " + dtm::kInputFormatNames + ")");
    }
    const bool volume_options = volume.threshold || volume.label || volume.interior_step != 1;
    if (volume_options && (format ? *format : dtm::input_format_for_path(input)) != dtm::InputFormat::kNrrd)
      throw std::invalid_argument(input + ": --threshold, --label and --voxel-interior-step apply to voxel volumes only");
    auto in = dtm::read_input(input, format, volume, !no_reference);
    if (no_reference) in.tets.clear();
    if (box > 0) {
      const double extent = dtm::largest_extent(in.points);
      scale = extent > 0 ? box / extent : 1.0;
    }
    if (scale <= 0) scale = 1.0;
    if (scale != 1.0)
      for (auto& p : in.points) p = {p.x * scale, p.y * scale, p.z * scale};

    dtm::QuantizedPoints q;
    const bool lattice = in.on_grid.has_value();
    if (lattice) {
      // The voxel lattice is the grid: positions stay exact.
      q = std::move(*in.on_grid);
      const int needed = q.grid.qbits;
      if (qbits_opt->count() > 0) {
        if (qbits < needed)
          throw std::invalid_argument(input + ": the selected voxels span " + std::to_string((1 << needed) / 2) +
                                      " or more voxels on an axis: --qbits must be at least " + std::to_string(needed));
        q.grid.qbits = qbits;
      }
      qbits = q.grid.qbits;
      for (double& o : q.grid.origin) o *= scale;
      q.grid.step *= scale;
    } else {
      try {
        q = dtm::quantize(in.points, qbits);
      } catch (const std::invalid_argument& e) {
        throw std::runtime_error(input + ": " + e.what());
      }
    }
    const double extent = q.grid.step * ((1u << qbits) - 1);
    if (dmax <= 0) dmax = 0.005 * extent;

    dtm::HierarchyOptions opt;
    opt.alpha = parse_alpha(alpha_text, q.grid.step);
    opt.dmax = dmax / q.grid.step;
    opt.max_levels = levels;
    opt.min_base_vertices = min_base;
    opt.stop_when_boundary_is_final = !no_paper_stop;
    opt.quality_guard = guard;

    if (!quiet) {
      std::printf("%s: %zu points, %llu merged by quantization, q=%d, step=%.6g, Dmax=%g%s\n",
                  input.c_str(), in.points.size(), (unsigned long long)q.duplicates_merged,
                  qbits, q.grid.step, dmax, lattice ? " (the voxel lattice: lossless)" : "");
      if (!in.fields.empty()) {
        std::string names;
        for (const auto& f : in.fields) names += (names.empty() ? "'" : ", '") + f.name + "'";
        std::printf("%s: per-vertex fields kept aside (not coded yet): %s\n", input.c_str(), names.c_str());
      }
      dtm::print_table_header(stdout);
    }
    const bool progress = !quiet && isatty(STDERR_FILENO);
    const auto start = std::chrono::steady_clock::now();
    std::vector<dtm::LevelStats> stats;
    // The input's tetrahedra, when it has them, are the reference shape.
    std::optional<dtm::ReferenceShape> reference;
    if (!in.tets.empty()) reference.emplace(in.tets, q);
    std::vector<dtm::DistanceSummary> reference_errors;
    dtm::Hierarchy hierarchy;
    try {
      hierarchy = dtm::build_hierarchy(q.points, opt, [&](const dtm::Level& level) {
        stats.push_back(level.stats);
        if (reference) reference_errors.push_back(reference->distance(level.mesh, q.points));
        if (!quiet) dtm::print_table_row(stdout, level.stats, q.grid);
        if (progress) {
          const double s =
              std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
          std::fprintf(stderr, "\r  level %d done, %.0f vertices/s\033[K\r", level.stats.level,
                       q.points.size() / std::max(s, 1e-9));
        }
      });
    } catch (const dtm::DegenerateInput& e) {
      throw std::runtime_error(input + ": " + e.what());
    }
    if (progress) std::fprintf(stderr, "\033[K");
    if (reference && !quiet && !reference_errors.empty()) {
      const auto& first = reference_errors.front();
      const auto& last = reference_errors.back();
      std::printf("reference shape: the input's %zu tetrahedra (%zu boundary vertices); distance between its "
                  "boundary and each level's, both ways, max / mean: level 0 %.4g / %.4g, level %zu %.4g / %.4g "
                  "(all levels in --report)\n",
                  reference->tetrahedra(), reference->boundary_vertices(), first.max * q.grid.step,
                  first.mean * q.grid.step, reference_errors.size() - 1, last.max * q.grid.step,
                  last.mean * q.grid.step);
    }

    dtm::ReportContext ctx;
    ctx.input = input;
    ctx.grid = q.grid;
    ctx.duplicates_merged = q.duplicates_merged;
    ctx.scale = scale;
    // The stream and the report are written together or not at all.
    std::vector<std::pair<std::string, std::string>> files;
    if (!output.empty()) {
      dtm::EncoderOptions eo;
      eo.cell_hashes = hash_cells;
      eo.level_step = level_step;
      const auto stream = dtm::encode_stream(hierarchy, q.points, q.grid, opt.alpha.kind, eo);
      ctx.layer_bytes = stream.layer_bytes;
      ctx.streamed_levels = stream.streamed_levels;
      ctx.stream_bytes = stream.bytes.size();
      std::string bytes(stream.bytes.begin(), stream.bytes.end());
      if (output == "-") {
        if (std::fwrite(bytes.data(), 1, bytes.size(), stdout) != bytes.size() ||
            std::fflush(stdout) != 0)
          throw std::runtime_error("cannot write the stream to standard output");
      } else {
        files.emplace_back(output, std::move(bytes));
      }
      if (!quiet)
        std::printf("%s: %zu bytes, %.2f bits per vertex (%zu vertices, %zu levels)\n",
                    output.c_str(), stream.bytes.size(),
                    8.0 * stream.bytes.size() / q.points.size(), q.points.size(),
                    stream.streamed_levels.size());
    }
    if (!report_path.empty()) {
      auto j = dtm::report_json(ctx, stats);
      if (reference) {
        j["reference_tetrahedra"] = reference->tetrahedra();
        for (size_t l = 0; l < reference_errors.size() && l < j["levels"].size(); ++l) {
          j["levels"][l]["reference_max_error"] = reference_errors[l].max * q.grid.step;
          j["levels"][l]["reference_mean_error"] = reference_errors[l].mean * q.grid.step;
        }
      }
      files.emplace_back(report_path, j.dump(2) + "\n");
    }
    dtm::write_files_atomically(files);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "meshenc: error: %s\n", e.what());
    return 1;
  }
  return 0;
}
