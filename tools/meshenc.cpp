// meshenc: reads a volume point set (a volume mesh, a point cloud or surface,
// or the solid of a voxel volume), builds its Delaunay level-of-detail
// hierarchy and prints the level table while it works.
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <iostream>
#include <map>
#include <numeric>
#include <optional>
#include <unordered_set>

#include "codec/blocks/reference_share.h"
#include "codec/encode.h"
#include "codec/sections/edge_node_coder.h"
#include "codec/sections/region_coder.h"
#include "codec/sections/value_fields.h"
#include "common/byte_io.h"
#include "common/parallel_for.h"
#include "common/release.h"
#include "core/reference_shape.h"
#include "tools/atomic_file.h"
#include "tools/field_types.h"
#include "tools/formats/files_read.h"
#include "tools/formats/input.h"
#include "tools/formats/mesh_writers.h"
#include "tools/formats/node_labels.h"
#include "tools/formats/second_order.h"
#include "tools/formats/tagged_faces.h"
#include "tools/formats/tetgen.h"
#include "tools/huge_pages.h"
#include "tools/mpi_session.h"
#include "tools/phase_display.h"
#include "tools/report.h"
#include "tools/same_command.h"
#include "tools/thread_budget.h"
#include "tools/tool_main.h"

namespace {

constexpr const char* kExamples = R"(
Examples:
  meshenc torus_288.node --scale 25 --dmax 3
  meshenc bunny_10k.node -o bunny.dtm --box 256 --dmax 2 --report bunny.json
  meshenc mesh.node -o mesh.dtm --preset paper --qbits 16 --levels 4 --quality-guard 0.05
  meshenc scan.ply -o scan.dtm --qbits 12
  meshenc ct.nhdr --threshold 300 --voxel-interior-step 2 -o ct.dtm --dmax 1.5
  meshenc flow.vtu -o flow.dtm --field-error pressure=0.01

Inputs (by extension, or --format): TetGen .node (+ .ele), Medit .mesh, Netgen .vol(.gz), VTK
.vtk, .vtu and .pvtu, gmsh .msh (2.0, 2.2, 4.1), Abaqus/CalculiX .inp, Exodus II .e/.exo,
PLY, OFF, OBJ, XYZ, NRRD .nrrd/.nhdr.
The vertices are encoded with every per-vertex field of the file (VTK/VTU
PointData, gmsh $NodeData, PLY vertex properties, TetGen .node attributes and
markers, a volume's voxel values): losslessly, or a float field within
--field-error NAME=E of its values; --no-fields leaves them out. Tetrahedra in
the file are the reference shape: each level's cells are the Delaunay cells
inside it, and its boundary is measured against it (the line after the table,
--report).

Voxel volumes: the solid is the voxels with value >= --threshold (or ==
--label), whose values are the field 'value'; a 0/1 mask needs neither (its
solid is the 1s, and it has no field). Its points are every boundary voxel (a 6-neighbour outside the
solid) and the interior voxels whose indices are all multiples of
--voxel-interior-step. With isotropic axis-aligned spacing the voxel lattice
is the quantization grid (qbits = just enough for the selected extent, or
--qbits if larger): positions are coded losslessly. Anisotropic or oblique
spacing: voxel centres are placed at their physical positions and quantized
like any point set (lossy).

Dmax and --alpha values are in input units, after --scale/--box; the stream
and the decoded mesh are in the input's own units whatever they say.)";

std::string format_number(double v) {
  char text[32];
  std::snprintf(text, sizeof text, "%g", v);
  return text;
}

// What the command line asks for.
struct Command {
  std::string input, output, report_path, alpha_text = "paper", format_name, preset = "codec";
  std::optional<double> removal_share, quality_ratio, quality_guard, quality_floor, quality_floor_cap;
  bool quiet = false, no_reference = false, no_fields = false, no_regions = false, no_face_tags = false,
       no_cell_data = false, strict = false, verbose = false;
  std::string region_array;
  int time_step = 0;                      // --time-step; 0: the last
  int threads = 0;                        // --threads; 0: the process's share of its cores
  std::vector<std::string> field_errors;  // NAME=E
  dtm::VolumeOptions volume;
  // meshenc writes the stream alone: no caller of its wants each input
  // point's vertex, and the encoder frees its map from input points early.
  dtm::EncodeOptions encode = [] {
    dtm::EncodeOptions o;
    o.vertex_of_input = false;
    return o;
  }();
};

// --alpha paper|hull|VALUE into the options.
void parse_alpha(const std::string& text, dtm::EncodeOptions& o) {
  if (text == "paper" || text == "hull") {
    o.alpha = text == "paper" ? dtm::AlphaKind::kPaper : dtm::AlphaKind::kConvexHull;
    return;
  }
  const std::optional<double> v = dtm::finite_decimal(text);
  if (!v || !(*v > 0))
    throw dtm::UsageError("--alpha must be 'paper', 'hull' or a finite number above 0, got '" + text + "'");
  o.alpha = dtm::AlphaKind::kFixed;
  o.fixed_alpha = *v;
}

void add_options(CLI::App& app, Command& c) {
  dtm::EncodeOptions& e = c.encode;
  app.add_option(
         "input", c.input,
         "input file: .node .mesh .vtk .vtu .pvtu .msh .vol .inp .e .exo .nrrd .nhdr .ply .off .obj .xyz")
      ->required();
  app.add_option("--format", c.format_name,
                 std::string("input format, overriding the extension: ") + dtm::kInputFormatNames);
  auto* threshold_opt = app.add_option("--threshold", c.volume.threshold,
                                       "voxel volumes: the solid is the voxels with value >= T");
  app.add_option("--label", c.volume.label, "voxel volumes: the solid is the voxels with value == L")
      ->excludes(threshold_opt);
  app.add_option("--voxel-interior-step", c.volume.interior_step,
                 "voxel volumes: keep interior voxels whose indices are multiples of K (boundary voxels "
                 "are always kept)")
      ->capture_default_str()
      ->check(dtm::finite_number(false));
  app.add_option("-o,--output", c.output, "write the .dtm stream here ('-' = standard output)");
  app.add_flag("--no-reference", c.no_reference,
               "ignore the input's tetrahedra (no reference-shape error; a TetGen .ele is not even read)");
  app.add_flag("--hash-cells", e.cell_hashes,
               "store each level's cell-set hash (lets meshdec --verify prove its meshes)");
  app.add_option("--qbits", e.qbits,
                 "quantization bits per axis (1..24; default 14; voxel lattices: just enough)")
      ->check(CLI::Range(1, 24));
  app.add_option(
         "--dmax", e.dmax,
         "boundary tolerance Dmax in input units (default: 0.5% of the largest extent; a volume's: its "
         "solid's)")
      ->check(dtm::finite_number(false));
  auto* scale_opt =
      app.add_option(
             "--scale", e.scale,
             "measure in the input's coordinates times this: the units of --dmax, --alpha and the table "
             "(the stream keeps the input's units)")
          ->check(dtm::finite_number(false));
  app.add_option("--box", e.box,
                 "measure as if the input's largest extent were this: the units of --dmax, --alpha and the "
                 "table (the stream keeps the input's units)")
      ->check(dtm::finite_number(false))
      ->excludes(scale_opt);
  app.add_option("--levels", e.max_levels, "build at most this many coarser levels (0 = no limit)")
      ->check(dtm::finite_number(true));
  app.add_option("--min-base", e.min_base_vertices, "never build a level with fewer vertices (0 to 2^32)")
      ->capture_default_str()
      ->check(CLI::Range(size_t{0}, size_t{1} << 32));
  app.add_option("--preset", c.preset,
                 "codec: levels carved to the input's solid (alpha predicts, the stream corrects), about "
                 "half the vertices each; paper: the seed paper's (alpha carving, one independent set per "
                 "level, as many removals as keep the average quality, its stopping rule)")
      ->capture_default_str()
      ->check(CLI::IsMember({"codec", "paper"}));
  app.add_option("--removal-share", c.removal_share,
                 "each level removes about this share of the finer level's vertices (codec: 0.5; 0 = one "
                 "independent set per level)")
      ->check(dtm::finite_number(true))
      ->check(CLI::Range(0.0, 0.95));
  app.add_option("--alpha", c.alpha_text, "alpha policy: paper (eq. 2.1), hull, or a value")
      ->capture_default_str();
  app.add_option("--quality-guard", c.quality_guard,
                 "accept a removal only if its new cells' smallest solid angle is >= "
                 "min(S, the star's) (--preset paper only; 0 = off)")
      ->check(dtm::finite_number(true))
      ->check(CLI::Range(0.0, 0.56));
  app.add_option("--quality-ratio", c.quality_ratio,
                 "accept a removal only if its new cells' smallest solid angle is >= R x the star's "
                 "(--preset paper only; 0 = off)")
      ->check(dtm::finite_number(true))
      ->check(CLI::Range(0.0, 1.0));
  app.add_option("--quality-floor", c.quality_floor,
                 "keep every level's average smallest solid angle >= F x level 0's, removing as many "
                 "vertices as that allows (codec: 0.85, paper: 1; 0 = off)")
      ->check(dtm::finite_number(true))
      ->check(CLI::Range(0.0, 1.0));
  app.add_option("--quality-floor-cap", c.quality_floor_cap,
                 "the quality floor is at most this average smallest solid angle, so that a "
                 "best-shaped input gets levels too (codec: 0.25, what Delaunay levels of well-spaced points "
                 "reach; paper: none; 0 = none)")
      ->check(dtm::finite_number(true))
      ->check(CLI::Range(0.0, 0.56));
  app.add_flag(
      "--no-paper-stop", [&e](int64_t) { e.paper_stop = false; },
      "do not stop at the first level that removes no boundary vertex");
  app.add_flag(
      "--no-candidates", [&e](int64_t) { e.candidates = false; },
      "send no point beside the coarser level's circumcentres and edge midpoints: a larger stream, whose "
      "finest level decodes faster");
  CLI::Option* bricks = app.add_flag(
      "--bricks", e.bricks,
      "bricked layers (format 8.0; 15.0 with regions, 16.0 with cell data, 17.0 with tagged faces): each "
      "layer's points and corrections in one chunk per octree brick, so that meshdec --box decodes a region "
      "from the chunks around it, values, regions, tagged faces and level 0's cell data included; the levels "
      "are built in blocks, the same bytes alone or under mpirun (no candidates)");
  app.add_option("--brick-points", e.brick_points,
                 "with --bricks: each layer's bricks are the smallest that hold this many of its new points "
                 "on average (smaller: regions read fewer bytes, the stream grows)")
      ->capture_default_str()
      ->check(CLI::Range(uint64_t{1}, uint64_t{1} << 32))
      ->needs(bricks);
  app.add_option("--block-points", e.block_points,
                 "with --bricks: the levels are built in blocks of at most this many points (boxes halved "
                 "where points crowd), each on its own (and, under mpirun, on the ranks in turn): "
                 "smaller takes less memory and more time; the stream depends on it, not on the ranks")
      ->capture_default_str()
      ->check(CLI::Range(uint64_t{64}, uint64_t{1} << 32))
      ->needs(bricks);
  app.add_option(
         "--blocks-at-once", e.blocks_at_once,
         "with --bricks: build up to N blocks side by side in each process, each on its share of the "
         "threads (default: one per thread, as many as a quarter of the memory holds at about 1 KB a block "
         "point); each holds its region's tetrahedralization, so 1 takes "
         "the least memory; the stream is the same")
      ->check(CLI::Range(1, 4096))
      ->needs(bricks);
  app.add_option("--level-step", e.level_step,
                 "stream every N-th level (and the coarsest): fewer levels of detail, fewer bits")
      ->capture_default_str()
      ->check(CLI::Range(1, 1000));
  app.add_option("--field-error", c.field_errors,
                 "code float field NAME lossily, every decoded value within E of its own (repeatable)")
      ->type_name("NAME=E");
  app.add_flag("--no-fields", c.no_fields, "leave the input's per-vertex fields out of the stream");
  app.add_flag(
      "--no-regions", c.no_regions,
      "leave the input's regions (gmsh physical volumes, Medit refs, TetGen region attributes, Abaqus "
      "element sets) out of the stream");
  app.add_flag(
      "--no-face-tags", c.no_face_tags,
      "leave the input's tagged triangles (gmsh physical surfaces, Medit triangle refs, Abaqus surfaces) "
      "out of the stream");
  app.add_option("--time-step", c.time_step,
                 "Exodus II: the time step whose variables to keep (1 = the first; default: the last)")
      ->check(CLI::Range(1, INT32_MAX));
  app.add_flag("--no-cell-data", c.no_cell_data,
               "leave the input's per-cell arrays (VTU/VTK cell data, gmsh $ElementData) out of the stream");
  app.add_flag(
      "--keep-order", c.encode.keep_order,
      "decode level 0's vertices in the input's numbering (their order coded; needs every input point "
      "its own grid point)");
  app.add_flag("--exact", c.encode.exact,
               "decode level 0 as the input's own tetrahedra, cell for cell (the cells that are not Delaunay "
               "cells coded beside the levels; needs a valid mesh whose points stay apart on the grid)");
  // An older decoder's format: --exact with that version's symbols (one
  // of them at most).
  std::vector<CLI::Option*> older;
  const auto exact_for_older = [&app, &c, &older](const char* flag, dtm::ApexRanks ranks, const char* help) {
    older.push_back(app.add_flag_function(
        flag,
        [&c, ranks](int64_t) {
          c.encode.exact = true;
          c.encode.exact_ranks = ranks;
        },
        help));
  };
  exact_for_older(
      "--exact-v11", dtm::ApexRanks::kAmongCandidates,
      "--exact, written as format 11.0 for decoders older than 12.0 (the apexes ranked among all "
      "their candidates, and the carving without the cells' shapes: 0.02-0.69 bits a vertex more)");
  exact_for_older(
      "--exact-v12", dtm::ApexRanks::kAmongFitting,
      "--exact, written as format 12.0 for decoders older than 13.0 (without 13.0's contexts of the "
      "filled faces and of the carving's flips, no second ring: up to 0.5 bits a vertex more)");
  exact_for_older(
      "--exact-v13", dtm::ApexRanks::kAmongFittingInContext,
      "--exact, written as format 13.0 for decoders older than 14.0 (without 14.0's flip flags: up "
      "to 0.4 bits a vertex more)");
  exact_for_older(
      "--exact-v22", dtm::ApexRanks::kAfterFlips,
      "--exact, written for decoders older than 23.0: as format 14.0 (18.0 to 22.0 with edge nodes "
      "or node ids), without 23.0's order of the apexes and contexts of the filled faces (up to "
      "0.46 bits a vertex more)");
  older.push_back(app.add_flag_function(
      "--exact-v19",
      [&c](int64_t) {
        c.encode.exact = true;
        c.encode.edge_nodes_v19 = true;
      },
      "--exact, a second-order mesh's edge nodes written as format 19.0 for decoders older than 20.0 "
      "(without 20.0's creases: up to 2.4 bits a vertex more)"));
  older.push_back(app.add_flag_function(
      "--exact-v20",
      [&c](int64_t) {
        c.encode.exact = true;
        c.encode.edge_nodes_v20 = true;
      },
      "--exact, written as format 20.0 for decoders older than 21.0: with --keep-order, a second-order "
      "mesh's edge nodes after its vertices, not where it numbered them"));
  for (CLI::Option* a : older)
    for (CLI::Option* b : older)
      if (a != b) a->excludes(b);
  app.add_flag("--strict", c.strict,
               "refuse an input of which the stream would leave something out (each thing is named)");
  app.add_option("--region-array", c.region_array,
                 "a .vtu's integer cell array holding the regions (default: the first of gmsh:physical, "
                 "medit:ref, netgen:index, region, material, MaterialIds, CellEntityIds it has)");
  app.add_option("--report", c.report_path, "write the level table as JSON to this file");
  app.add_flag("-q,--quiet", c.quiet, "do not print the table (nor the progress line on a terminal)");
  app.add_flag("-v,--verbose", c.verbose,
               "print each phase of the work on standard error, with how long it took and the memory in use "
               "(under mpirun, every rank its own, each line begun 'rank R/P:')");
  dtm::add_threads_option(app, c.threads);
}

// The first error of the ranks' (the lowest rank's: the earliest in the
// file), thrown on every rank, so that none waits for the others in vain,
// and printed by rank 0 alone.
void agree_on_errors(dtm::MpiSession& mpi, const std::string& problem) {
  for (const auto& p : mpi.all_gather({reinterpret_cast<const uint8_t*>(problem.data()), problem.size()}))
    if (!p.empty()) throw dtm::AgreedError(std::string(p.begin(), p.end()), mpi.rank() == 0);
}

// Every rank's part of `values` (trivially copyable), joined in rank order.
template <class T>
std::vector<T> joined(dtm::MpiSession& mpi, const std::vector<T>& values) {
  return mpi.all_gather_of(std::span<const T>(values));
}

// Under mpirun, a TetGen .node read in parts: each rank parses its range of
// the file's bytes, and the parts, joined in rank order, are every rank's
// points, as reading the whole file would give them. The joining checks
// what no part can alone: that each part's first index follows the parts
// before it (the first part's is 0 or 1), and that the parts hold the
// header's count. Errors inside a part come first (the lowest rank's), then
// those of the joining (the earliest part's): each a real error at the line
// named, though of a file with several not always the one a single process
// names.
dtm::NodeFile read_node_in_parts(const std::string& path, dtm::MpiSession& mpi) {
  dtm::NodePart part;
  std::string problem;
  try {
    part = dtm::read_tetgen_node_part(path, mpi.rank(), mpi.size());
  } catch (const std::exception& e) {
    problem = e.what();
  }
  agree_on_errors(mpi, problem);
  struct Head {
    uint64_t records;
    int64_t first_index;
  };
  const std::vector<Head> heads = joined(mpi, std::vector<Head>{{part.node.points.size(), part.first_index}});
  int64_t base = 0;
  for (const Head& h : heads)
    if (h.records > 0) {
      base = h.first_index;
      break;
    }
  // The first part (in file order) whose joining fails, and where: each
  // rank finds the same and re-reads that part for the line.
  uint64_t start = 0;
  try {
    for (size_t r = 0; r < heads.size(); ++r) {
      const Head& h = heads[r];
      const int p = static_cast<int>(r);
      if (h.records > 0 && start == 0 && base != 0 && base != 1)
        dtm::fail_at_node_record(path, p, mpi.size(), 0, "the first point index must be 0 or 1");
      if (h.records > 0 && h.first_index != base + static_cast<int64_t>(start))
        dtm::fail_at_node_record(path, p, mpi.size(), 0,
                                 "point index " + std::to_string(h.first_index) + " out of sequence");
      if (start + h.records > part.header_count)
        dtm::fail_at_node_record(
            path, p, mpi.size(), part.header_count - start,
            "unexpected data after the " + std::to_string(part.header_count) + " points");
      start += h.records;
    }
  } catch (const std::exception& e) {
    problem = e.what();
  }
  agree_on_errors(mpi, problem);
  if (start < part.header_count)
    throw dtm::AgreedError(path + ": file ends after " + std::to_string(start) + " of " +
                               std::to_string(part.header_count) + " points",
                           mpi.rank() == 0);
  dtm::NodeFile out;
  out.points = joined(mpi, part.node.points);
  dtm::release(part.node.points);
  out.attributes = joined(mpi, part.node.attributes);
  dtm::release(part.node.attributes);
  if (part.has_markers) out.markers = joined(mpi, part.node.markers);
  out.attribute_count = part.node.attribute_count;
  out.index_base = static_cast<int>(base);
  return out;
}

dtm::InputMesh read(const Command& c) {
  std::optional<dtm::InputFormat> format;
  if (!c.format_name.empty()) {
    format = dtm::input_format_named(c.format_name);
    if (!format)
      throw dtm::UsageError("--format " + c.format_name + ": unknown (known: " + dtm::kInputFormatNames +
                            ")");
  }
  if (c.time_step > 0 &&
      (format ? *format : dtm::input_format_for_path(c.input)) != dtm::InputFormat::kExodus)
    throw dtm::UsageError(c.input + ": --time-step applies to Exodus II files only");
  const bool volume_options = c.volume.threshold || c.volume.label || c.volume.interior_step != 1;
  if (volume_options && (format ? *format : dtm::input_format_for_path(c.input)) != dtm::InputFormat::kNrrd)
    throw dtm::UsageError(c.input +
                          ": --threshold, --label and --voxel-interior-step apply to voxel volumes only");
  // Under mpirun a TetGen .node is read in parts (read_node_in_parts()), its
  // .ele after the points are on the grid, each rank keeping its share
  // (hold_share()).
  dtm::MpiSession& mpi = dtm::mpi_session();
  dtm::InputMesh in;
  if (mpi.size() == 1) {
    in = dtm::read_input(c.input, format, c.volume, !c.no_reference, {}, c.time_step);
  } else {
    // Every rank reads the input, and meets the same error: agreed on, it
    // is printed once. (Those of the .node's parts are agreed on already.)
    std::string problem;
    try {
      // (A .face whose markers tag faces needs every tetrahedron on every
      // rank, as a gmsh file's tagged faces do: its .ele is read whole.)
      const bool whole_ele =
          !c.no_reference &&
          (format ? *format : dtm::input_format_for_path(c.input)) == dtm::InputFormat::kTetgen &&
          dtm::tetgen_face_is_marked(c.input);
      in = dtm::read_input(
          c.input, format, c.volume, whole_ele,
          [&mpi](const std::string& path) { return read_node_in_parts(path, mpi); }, c.time_step);
    } catch (const dtm::AgreedError&) {
      throw;
    } catch (const std::exception& e) {
      problem = e.what();
    }
    agree_on_errors(mpi, problem);
  }
  if (c.no_reference) in.tets.clear(), in.tet_edge_nodes.clear(), in.tetgen_ele.clear();
  return in;
}

using Tet = std::array<uint32_t, 4>;

// --exact of a second-order mesh: the nodes on its tetrahedra's edges, each
// edge once (the first tetrahedron's that names it), its corners the grid
// ids the encoder's tetrahedra name (`input_to_point`), and each field's
// values there (`fields`: in.fields', in their order).
struct TetrahedraEdgeNodes {
  std::vector<dtm::EncodeInput::EdgeNode> nodes;
  std::vector<std::vector<double>> values;
  std::vector<uint32_t> points;  // each node's edge point
};
TetrahedraEdgeNodes tetrahedra_edge_nodes(const dtm::InputMesh& in, std::span<const uint32_t> input_to_point,
                                          bool fields) {
  TetrahedraEdgeNodes out;
  std::vector<uint32_t>& points = out.points;
  std::unordered_set<uint64_t> seen;
  for (size_t t = 0; t < in.tet_edge_nodes.size() && t < in.tets.size(); ++t)
    for (size_t k = 0; k < 6; ++k) {
      const uint32_t node = in.tet_edge_nodes[t][k];
      if (node == dtm::InputMesh::kNoEdgeNode) continue;
      const uint32_t a = input_to_point[in.tets[t][static_cast<size_t>(dtm::kTetEdges[k][0])]],
                     b = input_to_point[in.tets[t][static_cast<size_t>(dtm::kTetEdges[k][1])]];
      if (seen.insert(dtm::edge_key(a, b)).second) {
        out.nodes.push_back({{a, b}, in.edge_points[node]});
        points.push_back(node);
      }
    }
  if (!fields) return out;
  for (const dtm::VertexField& f : in.fields) {
    const auto n = static_cast<size_t>(f.components);
    std::vector<double>& values = out.values.emplace_back();
    if (f.edge_values.size() != in.edge_points.size() * n) continue;  // (none: the corners' mean)
    values.reserve(points.size() * n);
    for (uint32_t p : points)
      values.insert(values.end(), f.edge_values.begin() + static_cast<std::ptrdiff_t>(p * n),
                    f.edge_values.begin() + static_cast<std::ptrdiff_t>((p + 1) * n));
  }
  return out;
}

// --keep-order of a second-order mesh (format 21.0): the file's numbering
// of its points and of the edge nodes the stream keeps, together
// (EncodeInput::node_numbering); empty where the reader kept no record of
// it.
std::vector<uint32_t> node_numbering(const dtm::InputMesh& in, const TetrahedraEdgeNodes& kept) {
  const auto on_edges =
      static_cast<size_t>(std::count(in.node_is_edge_point.begin(), in.node_is_edge_point.end(), uint8_t{1}));
  if (in.node_is_edge_point.empty() || on_edges != in.edge_points.size() ||
      in.node_is_edge_point.size() - on_edges != in.points.size())
    return {};
  std::vector<uint32_t> node_of_point(in.edge_points.size(), UINT32_MAX);
  for (size_t k = 0; k < kept.points.size(); ++k) node_of_point[kept.points[k]] = static_cast<uint32_t>(k);
  std::vector<uint32_t> out;
  out.reserve(in.points.size() + kept.points.size());
  uint32_t point = 0, edge_point = 0;
  const auto points = static_cast<uint32_t>(in.points.size());
  for (const uint8_t is_edge_point : in.node_is_edge_point)
    if (!is_edge_point)
      out.push_back(point++);
    else if (const uint32_t node = node_of_point[edge_point++]; node != UINT32_MAX)
      out.push_back(points + node);
  return out;
}

// --keep-order of a second-order mesh: a node the file puts on two edges
// of its tetrahedra is two nodes of the stream, which no numbering of the
// file's nodes names. Throws naming the first (its place in the file, and
// its id where the file has its own).
void check_no_node_shared(const dtm::InputMesh& in, const TetrahedraEdgeNodes& kept,
                          const std::string& input) {
  std::vector<uint32_t> held(in.edge_points.size(), 0);  // per edge point, the nodes it is
  for (const uint32_t p : kept.points) ++held[p];
  for (size_t k = 0, edge_point = 0; k < in.node_is_edge_point.size(); ++k) {
    if (!in.node_is_edge_point[k] || held[edge_point++] < 2) continue;
    throw std::runtime_error(
        input + ": --keep-order: node " + std::to_string(k + 1) + " of the file" +
        (in.node_labels.size() == in.node_is_edge_point.size()
             ? " (id " + std::to_string(in.node_labels[k]) + ")"
             : "") +
        " is the node of more than one edge of its tetrahedra: no numbering of the file's nodes names the "
        "stream's; leave out --keep-order to encode it");
  }
}

// --keep-order of a file with its own node ids (format 22.0): each kept
// node's id in the stream's numbering of them (`numbering`, node_numbering()'s,
// or, empty, the points'); empty where the reader's record does not fit.
std::vector<int64_t> node_labels_in_order(const dtm::InputMesh& in, std::span<const uint32_t> numbering,
                                          const TetrahedraEdgeNodes& kept) {
  std::vector<int64_t> point_label, edge_label;
  if (in.node_is_edge_point.empty()) {
    if (in.node_labels.size() != in.points.size()) return {};
    point_label = in.node_labels;
  } else {
    if (in.node_labels.size() != in.node_is_edge_point.size()) return {};
    for (size_t k = 0; k < in.node_labels.size(); ++k)
      (in.node_is_edge_point[k] ? edge_label : point_label).push_back(in.node_labels[k]);
    if (point_label.size() != in.points.size() || edge_label.size() != in.edge_points.size()) return {};
  }
  if (numbering.empty()) return point_label;
  std::vector<int64_t> out;
  out.reserve(numbering.size());
  for (const uint32_t entry : numbering)
    out.push_back(entry < in.points.size() ? point_label[entry]
                                           : edge_label[kept.points[entry - in.points.size()]]);
  return out;
}

// Under mpirun, a TetGen .ele read in parts: each rank parses its range of
// the file's bytes and sends each tetrahedron to the ranks that hold it
// (those of its two least corners, ReferenceShare), so that the ranks share the parsing and
// none holds more than its share. Each rank gets its tetrahedra in the
// file's order, as reading the whole file keeping them would give.
std::vector<Tet> read_ele_in_parts(const dtm::InputMesh& in, const dtm::QuantizedPoints& q,
                                   const dtm::ReferenceShare& share, dtm::MpiSession& mpi,
                                   std::vector<int32_t>* regions) {
  // A tetrahedron goes to the ranks of its two least corners, each found
  // when asked (a search of the ranks' cuts), not held for every point (4
  // bytes a point, 38 MiB at bunny_10m, held while the part was read: the
  // .ele phase's peak).
  // What goes to each rank, in pieces of a size (grown by doubling, a
  // rank's share was held up to twice, and three times while copied),
  // sent a piece at a time. DTM_MPI_PIECE sets the tetrahedra a piece,
  // 1 to 2^24, the same on every rank (tests/mpi_encode.sh: many pieces of
  // a small input); another value is not taken.
  size_t piece = size_t{1} << 16;  // tetrahedra: 1 MiB
  if (const char* e = std::getenv("DTM_MPI_PIECE")) {
    char* end = nullptr;
    const unsigned long long asked = std::strtoull(e, &end, 10);
    if (end != e && *end == '\0' && asked >= 1 && asked <= (1ull << 24)) piece = static_cast<size_t>(asked);
  }
  std::vector<std::vector<std::vector<Tet>>> to(static_cast<size_t>(mpi.size()));
  // With regions (TetGen -A), each tetrahedron's goes with it, in pieces
  // of the same sizes.
  std::vector<std::vector<std::vector<int32_t>>> regions_to(regions ? static_cast<size_t>(mpi.size()) : 0);
  const auto send = [&](uint32_t rank, const Tet& t, std::span<const int32_t> region) {
    auto& pieces = to[rank];
    if (pieces.empty() || pieces.back().size() == piece) {
      pieces.emplace_back().reserve(piece);
      if (regions) regions_to[rank].emplace_back().reserve(piece);
    }
    pieces.back().push_back(t);
    if (regions) regions_to[rank].back().push_back(region.empty() ? 0 : region.front());
  };
  // A block of the part: each tetrahedron's ranks found on every core, then
  // the tetrahedra put in order in what goes to each rank.
  std::vector<std::array<uint32_t, 2>> ranks;
  const auto take = [&](std::span<const Tet> block, std::span<const int32_t> block_regions) {
    ranks.resize(block.size());
    dtm::parallel_ranges(block.size(), size_t{1} << 14, [&](size_t first, size_t last) {
      for (size_t i = first; i < last; ++i) {
        // (Its corners on the grid.)
        const std::array<uint32_t, 4> t = {q.input_to_point[block[i][0]], q.input_to_point[block[i][1]],
                                           q.input_to_point[block[i][2]], q.input_to_point[block[i][3]]};
        const std::array<int, 2> holders = share.holding_ranks(t);
        ranks[i] = {static_cast<uint32_t>(holders[0]), static_cast<uint32_t>(holders[1])};
      }
    });
    for (size_t i = 0; i < block.size(); ++i) {
      const std::span<const int32_t> region =
          block_regions.empty() ? block_regions : block_regions.subspan(i, 1);
      send(ranks[i][0], block[i], region);
      if (ranks[i][1] != ranks[i][0]) send(ranks[i][1], block[i], region);
    }
  };
  dtm::ElePart counts;
  std::string problem;
  try {
    counts = dtm::read_tetgen_ele_part(in.tetgen_ele, q.input_to_point.size(), in.tetgen_index_base,
                                       mpi.rank(), mpi.size(), regions != nullptr, take);
  } catch (const std::exception& e) {
    problem = e.what();
    // (On one process such an attribute is kept as cell data.)
    if (problem.find("a region attribute that is not") != std::string::npos)
      problem +=
          " (under mpirun the first attribute is read as the region: give --no-regions, or encode on "
          "one process, which keeps it as cell data)";
  }
  agree_on_errors(mpi, problem);
  const uint64_t total = mpi.sum(counts.records);
  if (total < counts.header_count)
    throw dtm::AgreedError(in.tetgen_ele + ": file ends after " + std::to_string(total) + " of " +
                               std::to_string(counts.header_count) + " tetrahedra",
                           mpi.rank() == 0);
  if (total > counts.header_count)
    throw dtm::AgreedError(in.tetgen_ele + ": unexpected data after the " +
                               std::to_string(counts.header_count) + " tetrahedra (the file holds " +
                               std::to_string(total) + ")",
                           mpi.rank() == 0);
  try {
    std::vector<Tet> tets = mpi.all_to_all_in_pieces(std::move(to), piece);
    if (regions) *regions = mpi.all_to_all_in_pieces(std::move(regions_to), piece);
    return tets;
  } catch (const std::runtime_error& e) {  // on every rank alike: said once
    throw dtm::AgreedError(
        in.tetgen_ele + ": " + e.what() + " (DTM_MPI_PIECE must be the same on every rank)", mpi.rank() == 0);
  }
}

// Under mpirun, on 2 ranks or more: the input's tetrahedra this rank holds
// for the reference (codec/blocks/reference_share.h), on the grid, and
// their regions. A TetGen .ele is read in parts (its regions unless
// `regions` is false); other formats' are filtered in place.
void hold_share(dtm::InputMesh& in, const dtm::QuantizedPoints& q, const dtm::ReferenceShare& share,
                bool regions) {
  const auto on_grid = [&](const std::array<uint32_t, 4>& t) {
    return std::array<uint32_t, 4>{q.input_to_point[t[0]], q.input_to_point[t[1]], q.input_to_point[t[2]],
                                   q.input_to_point[t[3]]};
  };
  if (!in.tetgen_ele.empty()) {
    const bool with_regions = regions && dtm::tetgen_ele_attributes(in.tetgen_ele) > 0;
    in.tets = read_ele_in_parts(in, q, share, dtm::mpi_session(), with_regions ? &in.tet_regions : nullptr);
    return;
  }
  const bool with_regions = !in.tet_regions.empty();
  size_t held = 0;
  for (size_t i = 0; i < in.tets.size(); ++i) {
    if (!share.holds(on_grid(in.tets[i]))) continue;
    if (with_regions) in.tet_regions[held] = in.tet_regions[i];
    in.tets[held++] = in.tets[i];
  }
  if (held == in.tets.size()) return;
  in.tets.resize(held);
  in.tets.shrink_to_fit();
  if (with_regions) in.tet_regions.resize(held), in.tet_regions.shrink_to_fit();
}

// The input's arrays as the plan lists them: 'name' (type x components,
// lossless or within E), ...
std::string array_list(const std::vector<dtm::VertexField>& arrays,
                       const std::map<std::string, double>& errors) {
  std::string names;
  for (const auto& f : arrays) {
    names += (names.empty() ? "'" : ", '") + f.name + "' (" + dtm::scalar_name(f.type) +
             (f.components > 1 ? " x " + std::to_string(f.components) : "");
    const auto e = errors.find(f.name);
    names += e == errors.end() ? ", lossless)" : ", within " + format_number(e->second) + ")";
  }
  return names;
}

// Each region's tetrahedra; under mpirun (`share`) each counted by the one
// rank that owns it, added over the ranks (every rank must call this).
std::map<int32_t, uint64_t> region_cells(const dtm::InputMesh& in, const dtm::QuantizedPoints& q,
                                         const dtm::ReferenceShare* share) {
  std::map<int32_t, uint64_t> cells;
  for (size_t i = 0; i < in.tet_regions.size(); ++i) {
    const Tet& t = in.tets[i];
    if (!share || share->owns({q.input_to_point[t[0]], q.input_to_point[t[1]], q.input_to_point[t[2]],
                               q.input_to_point[t[3]]}))
      ++cells[in.tet_regions[i]];
  }
  if (!share) return cells;
  dtm::ByteWriter w;
  for (const auto& [label, count] : cells) w.u32(static_cast<uint32_t>(label)), w.u64(count);
  std::map<int32_t, uint64_t> all;
  for (const auto& bytes : dtm::mpi_session().all_gather(w.take())) {
    dtm::ByteReader r(bytes);
    uint32_t label = 0;
    uint64_t count = 0;
    while (r.u32(label) && r.u64(count)) all[static_cast<int32_t>(label)] += count;
  }
  return all;
}

void print_plan(const Command& c, const dtm::InputMesh& in, const dtm::EncodePlan& plan,
                const std::map<int32_t, uint64_t>& regions) {
  const auto& q = plan.quantized;
  std::printf("%s: %zu points, %llu merged by quantization, q=%d, step=%.6g, Dmax=%g%s\n", c.input.c_str(),
              q.input_to_point.size(), static_cast<unsigned long long>(q.duplicates_merged), q.grid.qbits,
              q.grid.step, plan.dmax, in.on_grid ? " (the voxel lattice: lossless)" : "");
  if (!in.fields.empty())
    std::printf("%s: per-vertex fields %s: %s\n", c.input.c_str(), c.no_fields ? "left out" : "coded",
                array_list(in.fields, c.encode.field_errors).c_str());
  if (!in.cell_fields.empty())
    std::printf("%s: cell data (level 0's cells): %s\n", c.input.c_str(),
                array_list(in.cell_fields, c.encode.field_errors).c_str());
  if (!regions.empty()) {
    std::string list;
    for (const auto& [label, count] : regions) {
      const auto name = in.region_names.find(label);
      list += (list.empty() ? "" : ", ") + std::to_string(label) +
              (name == in.region_names.end() ? "" : " \"" + name->second + "\"") + " (" +
              std::to_string(count) + " tetrahedra)";
    }
    std::printf("%s: regions (%s), %zu: %s\n", c.input.c_str(), in.region_source.c_str(), regions.size(),
                list.c_str());
  }
  if (!in.face_tags.empty()) {
    std::map<int32_t, uint64_t> faces;
    for (int32_t t : in.face_tags) ++faces[t];
    std::string list;
    for (const auto& [tag, count] : faces) {
      const auto name = in.face_tag_names.find(tag);
      list += (list.empty() ? "" : ", ") + std::to_string(tag) +
              (name == in.face_tag_names.end() ? "" : " \"" + name->second + "\"") + " (" +
              std::to_string(count) + " triangles)";
    }
    std::printf("%s: tagged faces (%s), %zu: %s\n", c.input.c_str(), in.face_tag_source.c_str(), faces.size(),
                list.c_str());
  }
}

// NAME=E arguments into the options.
void parse_field_errors(const std::vector<std::string>& args, dtm::EncodeOptions& o) {
  for (const std::string& a : args) {
    const size_t eq = a.rfind('=');
    const std::optional<double> bound = eq != std::string::npos && eq > 0
                                            ? dtm::finite_decimal(std::string_view(a).substr(eq + 1))
                                            : std::nullopt;
    const double e = bound.value_or(0);
    if (!bound || !(e > 0))
      throw dtm::UsageError("--field-error expects NAME=E with E a finite number above 0, got '" + a + "'");
    const auto [at, added] = o.field_errors.emplace(a.substr(0, eq), e);
    if (!added && at->second != e)
      throw dtm::UsageError("--field-error gives '" + at->first + "' two bounds (" +
                            format_number(at->second) + " and " + format_number(e) + "): give one");
  }
}

// One coded array's line after the table: its bytes and bits per value over
// `items` (vertices, or level 0's cells).
void print_array_bytes(const char* what, const dtm::FieldReport& f, uint64_t items) {
  const auto& d = f.description;
  std::printf("  %s '%s' (%s%s): %llu bytes, %.2f bits per value, %s\n", what, d.name.c_str(),
              dtm::value_type_name(d.type),
              d.components > 1 ? (" x " + std::to_string(d.components)).c_str() : "",
              static_cast<unsigned long long>(f.bytes),
              items ? 8.0 * static_cast<double>(f.bytes) / static_cast<double>(items * d.components) : 0.0,
              d.lossy ? ("every value within " + format_number(d.error_bound)).c_str() : "lossless");
}

void print_fields(const dtm::EncodeReport& r, size_t vertices) {
  for (const dtm::FieldReport& f : r.fields) print_array_bytes("field", f, vertices);
  if (r.merged_points_with_other_values > 0)
    std::printf("  %llu vertices merged points with different values: each keeps its first point's\n",
                static_cast<unsigned long long>(r.merged_points_with_other_values));
}

void print_reference_line(const dtm::EncodeReport& r) {
  if (r.reference_voxels > 0)
    std::printf(
        "reference solid: the volume's %llu solid voxels (every level keeps the cells whose centroid "
        "lies in one)\n",
        static_cast<unsigned long long>(r.reference_voxels));
  if (r.reference_tetrahedra == 0 || r.levels.empty()) return;
  const auto& first = *r.levels.front().reference_error;
  const auto& last = *r.levels.back().reference_error;
  double worst_to_level = 0, worst_to_reference = 0;
  for (const auto& l : r.levels) {
    worst_to_level = std::max(worst_to_level, l.reference_to_level->max);
    worst_to_reference = std::max(worst_to_reference, l.level_to_reference->max);
  }
  const double step = r.grid.step;
  std::printf(
      "reference shape: the input's %llu tetrahedra (%llu boundary vertices); distance between its "
      "boundary and each level's, both ways, max / mean: level 0 %.4g / %.4g, level %zu %.4g / %.4g; "
      "worst level: %.4g from the input's boundary to the level's, %.4g from the level's to the input's\n",
      static_cast<unsigned long long>(r.reference_tetrahedra),
      static_cast<unsigned long long>(r.reference_boundary_vertices), first.max * step, first.mean * step,
      r.levels.size() - 1, last.max * step, last.mean * step, worst_to_level * step,
      worst_to_reference * step);
  if (r.level0_difference) {
    const dtm::SolidDifference& d = *r.level0_difference;
    std::printf(
        "level 0's solid vs the input's: %llu tetrahedra shared; symmetric difference %.4g%% of the "
        "input's volume (%.4g only in level 0, %.4g only in the input)\n",
        static_cast<unsigned long long>(d.shared_cells),
        d.second_volume > 0 ? 100 * d.symmetric() / d.second_volume : 0.0, d.only_first * step * step * step,
        d.only_second * step * step * step);
  }
  if (r.reference_questions_at_once > 0)
    std::printf("reference in parts on the ranks: %llu points answered by the ranks while they worked\n",
                static_cast<unsigned long long>(r.reference_questions_at_once));
  if (r.reference_question_runs > 0)
    std::printf(
        "reference in parts on the ranks: %llu points answered by the ranks together, for %llu block runs "
        "(each run again)\n",
        static_cast<unsigned long long>(r.reference_questions),
        static_cast<unsigned long long>(r.reference_question_runs));
  if (r.level0_kept_radius > r.level0_spacing_kept_radius)
    std::printf(
        "level 0's kept radius raised from %.4g to %.4g to keep the input's larger cells (a graded "
        "mesh's coarse inside): every block's region and every region read grow with it\n",
        r.level0_spacing_kept_radius * r.grid.step, r.level0_kept_radius * r.grid.step);
  if (r.blocks_built_again + r.blocks_checked_in_parts > 0)
    std::printf("blocks a neighbour put points back in: %llu checked where it did, %llu built again\n",
                static_cast<unsigned long long>(r.blocks_checked_in_parts),
                static_cast<unsigned long long>(r.blocks_built_again));
}

// The stream and the report are written together or not at all.
void write_outputs(const Command& c, const dtm::EncodedMesh& encoded,
                   const std::vector<std::string>& left_out) {
  std::vector<std::pair<std::string, std::string>> files;
  if (!c.output.empty()) {
    std::string bytes(encoded.bytes.begin(), encoded.bytes.end());
    if (c.output == "-") {
      if (std::fwrite(bytes.data(), 1, bytes.size(), stdout) != bytes.size() || std::fflush(stdout) != 0)
        throw std::runtime_error("cannot write the stream to standard output");
    } else {
      files.emplace_back(c.output, std::move(bytes));
    }
  }
  if (!c.report_path.empty()) {
    nlohmann::json j = dtm::report_json(c.input, encoded.report);
    j["left_out"] = left_out;
    files.emplace_back(c.report_path, j.dump(2, ' ', false, nlohmann::json::error_handler_t::replace) + "\n");
  }
  dtm::write_files_atomically(files);
}

int run(Command& c) {
  // Under mpirun every rank reads the input and builds its share of the
  // blocks; rank 0 writes the stream, the same bytes as one process writes.
  // A rank lends its cores to the others on its node while it only waits,
  // unless the user set the threads.
  dtm::MpiSession& mpi = dtm::mpi_session();
  mpi.lend_cores(c.threads == 0);
  const dtm::ThreadBudget threads(c.threads, mpi.cores_share(), mpi.cores_lent_at_most());
  if (const std::string note = dtm::threads_held_note(c.threads);
      !note.empty() && !c.quiet && mpi.rank() == 0)
    std::fprintf(stderr, "meshenc: %s\n", note.c_str());
  if (mpi.size() > 1) {
    if (!c.encode.bricks)
      throw dtm::UsageError("under mpirun, meshenc writes a bricked stream: add --bricks", mpi.rank() == 0);
    c.encode.exchange = &mpi;
    // Rank 0 prints the table; with -v every rank its phases (its memory).
    if (mpi.rank() != 0) c.quiet = true;
  }
  if (c.output == "-") {
    // (Open MPI hands each rank's standard output to mpirun through a
    // terminal of its own, whatever mpirun's is.)
    if (mpi.size() > 1 || std::getenv("OMPI_COMM_WORLD_SIZE"))
      throw dtm::UsageError("-o -: under mpirun a rank's standard output is not the stream's: give -o FILE",
                            mpi.rank() == 0);
    if (isatty(STDOUT_FILENO))
      throw std::invalid_argument(
          "-o -: standard output is a terminal; a stream is binary (pipe or redirect it)");
    c.quiet = true;  // standard output carries the stream
  }
  // An output that cannot be written is said now, not after the encoding
  // (rank 0 writes; every rank stops with it, and it is said once).
  {
    std::string problem;
    // (A TetGen .node's .ele is read too.)
    const std::vector<std::string> inputs = {
        c.input, std::filesystem::path(c.input).replace_extension(".ele").string(),
        std::filesystem::path(c.input).replace_extension(".ELE").string()};
    try {
      if (mpi.rank() == 0 && !c.output.empty() && c.output != "-") dtm::check_writable(c.output, inputs);
      if (mpi.rank() == 0 && !c.report_path.empty() && c.report_path != "-")
        dtm::check_writable(c.report_path, inputs);
    } catch (const std::invalid_argument& e) {
      problem = e.what();
    }
    if (mpi.size() > 1)
      agree_on_errors(mpi, problem);
    else if (!problem.empty())
      throw std::invalid_argument(problem);
  }
  // Whole levels are a few large phases, each faster with the pages the
  // last one freed; bricks keep the lean default, their point being memory.
  if (!c.encode.bricks) dtm::keep_freed_memory_between_phases();
  if (c.preset == "paper") {
    const dtm::EncodeOptions paper = dtm::EncodeOptions::paper();
    c.encode.carve_to_reference = paper.carve_to_reference;
    c.encode.removal_share = paper.removal_share;
    c.encode.quality_ratio = paper.quality_ratio;
    c.encode.quality_guard = paper.quality_guard;
    c.encode.average_quality_floor = paper.average_quality_floor;
    c.encode.quality_floor_cap = paper.quality_floor_cap;
  }
  if (c.quality_floor) c.encode.average_quality_floor = *c.quality_floor;
  if (c.quality_floor_cap) c.encode.quality_floor_cap = *c.quality_floor_cap;
  if (c.removal_share) c.encode.removal_share = *c.removal_share;
  if (c.quality_ratio) c.encode.quality_ratio = *c.quality_ratio;
  if (c.quality_guard) c.encode.quality_guard = *c.quality_guard;
  parse_alpha(c.alpha_text, c.encode);
  parse_field_errors(c.field_errors, c.encode);
  if (c.no_fields && !c.encode.field_errors.empty())
    throw dtm::UsageError("--field-error and --no-fields contradict each other");
  // A stream under a mesh file's name is a mistake the next reader meets:
  // said now.
  // (A name meshenc reads or meshdec writes as a mesh.)
  const auto mesh_name = [](const std::string& path) {
    try {
      dtm::input_format_for_path(path);
      return true;
    } catch (const std::exception&) {
    }
    try {
      dtm::format_for_path(path);
      return true;
    } catch (const std::exception&) {
    }
    return false;
  };
  if (!c.output.empty() && c.output != "-" && mesh_name(c.output))
    throw dtm::UsageError("-o " + c.output +
                          ": meshenc writes a .dtm stream, not a mesh file (meshdec writes the mesh as one)");
  // Said before the input is read, not after its table's header.
  if (c.encode.bricks && c.encode.exact)
    throw dtm::UsageError("--exact: bricked streams (--bricks) do not keep the input's cells exactly yet");
  if (c.encode.bricks && c.encode.keep_order)
    throw dtm::UsageError(
        "--keep-order: bricked streams (--bricks) do not keep the input's vertex order yet");
  if (c.encode.bricks && c.encode.level_step != 1)
    throw dtm::UsageError("--level-step: bricked streams (--bricks) stream every level");
  if (c.encode.bricks && !c.encode.carve_to_reference)
    throw dtm::UsageError(
        "--bricks: bricked layers need the codec preset (not --preset paper): its levels "
        "carve to the input's solid");
  if (c.encode.carve_to_reference &&
      ((c.quality_guard && *c.quality_guard > 0) || (c.quality_ratio && *c.quality_ratio > 0)))
    throw dtm::UsageError(
        std::string(c.quality_guard && *c.quality_guard > 0 ? "--quality-guard" : "--quality-ratio") +
        ": the per-removal quality rules belong to the paper preset's independent sets "
        "(--preset paper); the codec preset keeps every level's average quality (--quality-floor)");
  if (!c.encode.carve_to_reference && (c.encode.exact || c.encode.keep_order))
    throw dtm::UsageError(std::string(c.encode.exact ? "--exact" : "--keep-order") +
                          " needs the codec preset (not --preset paper)");
  // What the work is doing, on standard error: a status line on a terminal.
  dtm::PhaseDisplay display(
      !c.quiet && isatty(STDERR_FILENO), c.verbose,
      mpi.size() > 1 ? "rank " + std::to_string(mpi.rank()) + "/" + std::to_string(mpi.size()) + ": " : "");
  const int threads_used = dtm::thread_count();
  display.start("reading " + c.input + " (" + std::to_string(threads_used) +
                (threads_used == 1 ? " thread)" : " threads)"));
  dtm::InputMesh in = read(c);
  // An output over a file the input named or has beside it (a .face, an
  // *INCLUDE, a NRRD's data file, a piece) would destroy it.
  {
    std::string problem;
    try {
      // (Rank 0 writes, and checks, as before the reading; every rank
      // stops with it.)
      for (const std::string& path : {c.output, c.report_path})
        if (mpi.rank() == 0 && !path.empty() && path != "-") dtm::check_writable(path, dtm::files_read());
    } catch (const std::invalid_argument& e) {
      problem = e.what();
    }
    agree_on_errors(mpi, problem);
  }
  dtm::choose_regions(in, c.region_array, c.input);
  // An array whose name a stream cannot hold (over 64 bytes: meshio's .vtu
  // of a gmsh mesh joins its physical groups' names into one array's):
  // left out, named, and the rest encoded.
  for (auto* list : {&in.fields, &in.cell_fields})
    std::erase_if(*list, [&](const dtm::VertexField& f) {
      if (f.name.size() <= dtm::kMaxFieldNameBytes) return false;
      in.left_out.push_back(std::string(list == &in.fields ? "the point array '" : "the cell array '") +
                            f.name + "' (a stream names an array in at most 64 bytes)");
      return true;
    });
  // A --field-error for no array of the file: said before the table (every
  // rank reads the same file, and says it alike).
  for (const auto& named : c.encode.field_errors) {
    const auto has = [&](const std::vector<dtm::VertexField>& fields) {
      return std::any_of(fields.begin(), fields.end(), [&](const auto& f) { return f.name == named.first; });
    };
    if (!has(in.fields) && !has(in.cell_fields)) {
      std::string arrays;
      for (const auto* list : {&in.fields, &in.cell_fields})
        for (const auto& f : *list) arrays += (arrays.empty() ? "'" : ", '") + f.name + "'";
      throw std::invalid_argument(c.input + ": --field-error names '" + named.first +
                                  "', which is not a field of the input (" +
                                  (arrays.empty() ? std::string("it has none") : "it has " + arrays) + ")");
    }
  }
  // The regions, where the stream can carry them; else named as left out.
  // (Under mpirun a TetGen .ele's are read with its tetrahedra, later.)
  bool regions_kept = true;
  if (!in.tet_regions.empty() || (!in.tetgen_ele.empty() && !in.region_source.empty())) {
    const char* why = c.no_regions                   ? "--no-regions"
                      : !c.encode.carve_to_reference ? "the paper preset carves by alpha alone"
                      : c.no_reference               ? "--no-reference"
                                                     : nullptr;
    if (why) {
      in.left_out.push_back("the tetrahedra's regions, " + in.region_source + " (" + why + ")");
      dtm::release(in.tet_regions);
      regions_kept = false;
    }
  }
  if (!regions_kept) in.region_names.clear();
  // A name of a label no cell or face has (a gmsh physical group of other
  // elements, or of none) has nothing to ride on: said, not lost in silence.
  // (A TetGen .ele, read later under mpirun, names none.)
  const auto names_without_cells = [&in](std::map<int32_t, std::string>& names,
                                         std::span<const int32_t> labels, const char* kind,
                                         const char* holder) {
    std::map<int32_t, bool> seen;
    for (const auto& entry : names) seen[entry.first] = false;
    std::optional<int32_t> last;
    for (int32_t label : labels)
      if (label != last) {
        last = label;
        if (const auto s = seen.find(label); s != seen.end()) s->second = true;
      }
    for (const auto& [label, has] : seen)
      if (!has) {
        in.left_out.push_back("the name \"" + names[label] + "\" of " + kind + " " + std::to_string(label) +
                              ", which no " + holder + " has");
        names.erase(label);
      }
  };
  if (in.tetgen_ele.empty() || !in.tet_regions.empty())
    names_without_cells(in.region_names, in.tet_regions, "region", "tetrahedron");
  // (A tagged face no level can carry is said, not lost in silence: with
  // the tetrahedra at hand, on one process.)
  if (!in.tagged_faces.empty() && !in.tets.empty() && !c.no_face_tags && c.encode.carve_to_reference &&
      !c.no_reference)
    if (const uint64_t inside = dtm::tagged_faces_inside(in.tets, in.tet_regions, in.tagged_faces))
      in.left_out.push_back(dtm::tagged_faces_inside_note(inside, in.tagged_faces.size()));
  if (!in.tagged_faces.empty()) {
    const char* why = c.no_face_tags                      ? "--no-face-tags"
                      : !c.encode.carve_to_reference      ? "the paper preset carves by alpha alone"
                      : c.no_reference || in.tets.empty() ? "no tetrahedra to bound"
                                                          : nullptr;
    if (why) {
      in.left_out.push_back(std::to_string(in.tagged_faces.size()) + " tagged triangles, " +
                            in.face_tag_source + " (" + why + ")");
      dtm::release(in.tagged_faces);
      dtm::release(in.face_tags);
      in.face_tag_names.clear();
    }
  }
  if (!in.face_tag_names.empty())
    names_without_cells(in.face_tag_names, in.face_tags, "face tag", "triangle");
  // A name longer than a stream holds keeps its beginning (encode() cuts it).
  for (const auto& [names, kind] :
       {std::pair{&in.region_names, "region"}, std::pair{&in.face_tag_names, "face tag"}})
    for (const auto& [label, name] : *names)
      if (name.size() > dtm::kMaxRegionNameBytes)
        in.left_out.push_back("the end of the name \"" + name + "\" of " + kind + " " +
                              std::to_string(label) + " (a stream holds " +
                              std::to_string(dtm::kMaxRegionNameBytes) + " bytes of a name: \"" +
                              dtm::held_label_name(name) + "\")");
  if (!in.cell_fields.empty()) {
    const char* why = c.no_cell_data                      ? "--no-cell-data"
                      : !c.encode.carve_to_reference      ? "the paper preset carves by alpha alone"
                      : c.no_reference || in.tets.empty() ? "no tetrahedra to hold them"
                                                          : nullptr;
    if (why) {
      std::string names;
      for (const auto& f : in.cell_fields) names += (names.empty() ? "'" : ", '") + f.name + "'";
      in.left_out.push_back("the cell arrays " + names + " (" + why + ")");
      // (A --field-error for one of them has nothing left to bound.)
      for (const auto& f : in.cell_fields)
        if (std::none_of(in.fields.begin(), in.fields.end(), [&](const auto& p) { return p.name == f.name; }))
          c.encode.field_errors.erase(f.name);
      in.cell_fields.clear();
    }
  }
  // A lossy cell array's NaN or infinity, named by the file's tetrahedron
  // (the encoder, given them on the grid, would count level 0's cells).
  for (const auto& f : in.cell_fields)
    if (c.encode.field_errors.contains(f.name) &&
        (f.type == dtm::ScalarType::kFloat32 || f.type == dtm::ScalarType::kFloat64))
      for (size_t i = 0; i < f.values.size(); ++i)
        if (!std::isfinite(f.values[i]))
          throw std::invalid_argument(c.input + ": cell data '" + f.name + "': tetrahedron " +
                                      std::to_string(i / static_cast<size_t>(f.components)) +
                                      " (from 0, in the file's order) holds " +
                                      (std::isnan(f.values[i]) ? "NaN" : "an infinity") +
                                      ", which a lossy field cannot keep (code it losslessly)");
  // meshdec's own point arrays (each vertex's coarsest level, whether it is
  // on the boundary, its number in the whole level): the decoder makes them
  // again, so a decoded mesh encoded again holds them once, not twice.
  {
    const auto meshdecs = [](const dtm::VertexField& f) {
      if (f.components != 1 || (f.name != "level" && f.name != "boundary" && f.name != "vertex_id"))
        return false;
      return std::all_of(f.values.begin(), f.values.end(), [&](double v) {
        return v >= 0 && v == std::floor(v) && (f.name != "boundary" || v <= 1);
      });
    };
    // (Only with level and boundary, or level and vertex_id, as meshdec
    // writes a whole level and a box or a piece of one: a user's own
    // vertex_id alone, global node numbers say, is kept.)
    const auto has = [&](const char* name) {
      return std::any_of(in.fields.begin(), in.fields.end(),
                         [&](const dtm::VertexField& f) { return f.name == name && meshdecs(f); });
    };
    std::string names;
    if (has("level") && (has("boundary") || has("vertex_id")))
      for (const auto& f : in.fields)
        if (meshdecs(f)) names += (names.empty() ? "'" : ", '") + f.name + "'";
    if (!names.empty()) {
      in.left_out.push_back("the point arrays " + names + " (meshdec's own: the decoder makes them again)");
      std::erase_if(in.fields, meshdecs);
    }
    // The input's own arrays under those names (a water level, say) and a
    // cell array named as meshdec names the regions: kept under another
    // name, said, or meshdec's files would hold two arrays of one name.
    const auto rename = [&](std::vector<dtm::VertexField>& arrays, std::initializer_list<const char*> taken) {
      for (dtm::VertexField& f : arrays)
        for (const char* name : taken)
          if (f.name == name) {
            f.name += " (input)";
            if (mpi.rank() == 0)
              std::fprintf(stderr, "%s: the array '%s' is kept as '%s' (meshdec writes its own '%s')\n",
                           c.input.c_str(), name, f.name.c_str(), name);
          }
    };
    rename(in.fields, {"level", "boundary", "vertex_id"});
    rename(in.cell_fields, {"region"});
  }
  if (c.no_fields && !in.fields.empty()) {
    std::string names;
    for (const auto& f : in.fields) names += (names.empty() ? "'" : ", '") + f.name + "'";
    in.left_out.push_back("the per-vertex fields " + names + " (--no-fields)");
  }
  // --exact keeps a second-order mesh's tetrahedra's edge nodes (format
  // 18.0): what is left out of them says so.
  // (Not --exact-v13 and older: their streams have none.)
  const bool keep_edge_nodes = c.encode.exact && c.encode.exact_ranks >= dtm::ApexRanks::kAfterFlips &&
                               !in.tet_edge_nodes.empty() && !in.tets.empty();
  if (keep_edge_nodes) {
    const std::string was =
        std::to_string(in.edge_points.size()) + " nodes on the edges of second-order elements";
    for (auto it = in.left_out.begin(); it != in.left_out.end(); ++it)
      if (it->rfind(was, 0) == 0) {
        if (const std::string now = dtm::edge_nodes_note(in, true, !c.no_fields && !in.fields.empty());
            now.empty())
          in.left_out.erase(it);
        else
          *it = now;
        break;
      }
  }
  // --keep-order keeps the file's node ids (format 22.0) where the stream
  // keeps the nodes they name: the points, and the edge nodes with their
  // numbering (not in the 18.0 and 19.0 streams asked for by name).
  const bool older_nodes = c.encode.edge_nodes_v18 || c.encode.edge_nodes_v19 || c.encode.edge_nodes_v20;
  // (Not in the streams asked for older decoders: 22.0 brought them.)
  const bool labels_allowed = c.encode.keep_order && !older_nodes &&
                              (!c.encode.exact || c.encode.exact_ranks >= dtm::ApexRanks::kAfterFlips);
  // Where the stream holds fewer nodes than the file (a second-order mesh's
  // edge nodes without --exact, or nodes of other second-order cells), the
  // ones it holds keep their numbers as ids: their places in the file.
  if (labels_allowed && in.node_labels.empty() && !in.edge_points.empty() &&
      in.node_is_edge_point.size() == in.points.size() + in.edge_points.size()) {
    in.node_labels.resize(in.node_is_edge_point.size());
    std::iota(in.node_labels.begin(), in.node_labels.end(), int64_t{1});
  }
  const bool keep_labels = labels_allowed && !in.node_labels.empty();
  if (keep_labels) std::erase(in.left_out, std::string(dtm::kNodeIdsNote));
  if (c.encode.keep_order && !labels_allowed && std::erase(in.left_out, std::string(dtm::kNodeIdsNote)) > 0)
    in.left_out.emplace_back(
        "the node ids (the file numbers its nodes otherwise than 1 to n; the format asked for predates "
        "22.0, which keeps them)");
  if (c.encode.keep_order && keep_edge_nodes && older_nodes)
    in.left_out.emplace_back(
        "where the file numbers its edge nodes among its vertices (format 21.0's node order: an older "
        "format's stream has them after the vertices)");
  // Whatever the stream will not hold, named on standard error (and in the
  // report); --strict refuses the input instead.
  // (Under mpirun every rank reads the input: rank 0 says it once.)
  if (mpi.rank() == 0)
    for (const std::string& what : in.left_out)
      std::fprintf(stderr, "%s: left out (the stream does not hold it): %s\n", c.input.c_str(), what.c_str());
  if (c.strict && !in.left_out.empty())
    throw std::runtime_error(c.input + ": --strict: the stream would leave out " +
                             std::to_string(in.left_out.size()) + " thing" +
                             (in.left_out.size() == 1 ? "" : "s") + " of the input (named above)");
  display.start("quantizing");
  dtm::EncodeInput input;
  input.points = in.points;
  input.tetrahedra = in.tets;
  std::vector<dtm::EncodeInput::Field> fields;
  if (!c.no_fields)
    for (const auto& f : in.fields)
      fields.push_back({f.name, dtm::value_type(f.type), f.components, f.values});
  input.fields = fields;
  if (in.on_grid) input.lattice = &*in.on_grid;
  if (in.voxels && !c.no_reference) input.voxels = &*in.voxels;
  auto plan = dtm::plan_encoding(input, c.encode);
  if (!plan.ok()) throw std::runtime_error(c.input + ": " + plan.status().message());
  // --exact: the input's points and cells must stay apart on the grid (said
  // now, with the --qbits that would do, before the long work).
  if (c.encode.exact && !in.tets.empty())
    if (const dtm::Status s = dtm::check_exact_grid(in.points, in.tets, *plan); !s.ok())
      throw std::runtime_error(c.input + ": " + s.message());
  // --exact of a second-order mesh: its tetrahedra's edge nodes ride on
  // level 0's cells (format 18.0), named by their corners' grid ids, before
  // the tetrahedra are put on the grid.
  TetrahedraEdgeNodes edge_nodes;
  std::vector<uint32_t> numbering;  // --keep-order: the file's, of the points and nodes together
  if (keep_edge_nodes) {
    edge_nodes = tetrahedra_edge_nodes(in, plan->quantized.input_to_point, !fields.empty());
    input.edge_nodes = edge_nodes.nodes;
    if (c.encode.keep_order && !c.encode.edge_nodes_v18 && !c.encode.edge_nodes_v19 &&
        !c.encode.edge_nodes_v20) {
      check_no_node_shared(in, edge_nodes, c.input);
      numbering = node_numbering(in, edge_nodes);
    }
    input.node_numbering = numbering;
    for (size_t f = 0; f < fields.size(); ++f) fields[f].edge_values = edge_nodes.values[f];
  }
  std::vector<int64_t> labels;
  if (keep_labels) {
    if (input.edge_nodes.empty() || !numbering.empty())
      labels = node_labels_in_order(in, numbering, edge_nodes);
    // (Ids 1 to n in order are what a stream without them gives.)
    bool identity = !labels.empty();
    for (size_t k = 0; k < labels.size() && identity; ++k)
      identity = labels[k] == static_cast<int64_t>(k + 1);
    if (labels.empty()) {  // (the reader's record does not fit the nodes kept)
      in.left_out.emplace_back(dtm::kNodeIdsNote);
      if (mpi.rank() == 0)
        std::fprintf(stderr, "%s: left out (the stream does not hold it): %s\n", c.input.c_str(),
                     std::string(dtm::kNodeIdsNote).c_str());
      if (c.strict) throw std::runtime_error(c.input + ": --strict: the stream would leave out the node ids");
    }
    if (identity) labels.clear();
    input.node_labels = labels;
  }
  // Whether the input has tetrahedra (a rank's share may have none).
  const bool with_reference = !in.tets.empty() || !in.tetgen_ele.empty();
  std::optional<dtm::ReferenceShare> share;  // under mpirun, this rank's, handed to the encoder
  if (mpi.size() > 1) {
    // The plan holds the points on the grid: the input's (24 bytes each)
    // are freed before the tetrahedra are read.
    input.points = {};
    dtm::release(in.points);
    if (!in.tetgen_ele.empty()) display.start("reading " + in.tetgen_ele + ", a part on each rank");
    share.emplace(plan->quantized.points, plan->quantized.grid.qbits, mpi.rank(), mpi.size());
    c.encode.reference_share = &*share;
    // With cell data or tagged faces (never from a TetGen .ele) every rank
    // keeps every tetrahedron, as it read them: a cell's source may be any
    // one at its corners, and a face's tag any surface triangle's near it
    // (codec/encode.h).
    if ((in.cell_fields.empty() && in.tagged_faces.empty()) || !in.tetgen_ele.empty())
      hold_share(in, plan->quantized, *share, regions_kept);
  }
  input.tetrahedra = in.tets;
  const std::map<int32_t, uint64_t> regions = region_cells(in, plan->quantized, share ? &*share : nullptr);
  if (!c.quiet) {
    display.clear();
    print_plan(c, in, *plan, regions);
    dtm::print_table_header(stdout, with_reference);
  }
  const dtm::Grid grid = plan->quantized.grid;
  const size_t vertices = plan->quantized.points.size();
  // The reference on the grid, made of the input's where they lie (a copy
  // was the peak of a 10M-vertex encoding), freed once the encoder holds
  // what it needs of them.
  if (!in.tets.empty()) display.start("the reference's tetrahedra on the grid");
  if (in.cell_fields.empty()) {
    dtm::grid_tetrahedra_in_place(in.tets, plan->quantized,
                                  in.tet_regions.empty() ? nullptr : &in.tet_regions);
  } else {
    // The cell arrays (and the regions) follow each tetrahedron's index.
    std::vector<int32_t> source(in.tets.size());
    for (size_t i = 0; i < source.size(); ++i) source[i] = static_cast<int32_t>(i);
    dtm::grid_tetrahedra_in_place(in.tets, plan->quantized, &source);
    const auto gather = [&](auto& values, size_t n) {
      std::remove_reference_t<decltype(values)> kept;
      kept.reserve(source.size() * n);
      for (int32_t t : source)
        for (size_t k = 0; k < n; ++k) kept.push_back(values[static_cast<size_t>(t) * n + k]);
      values = std::move(kept);
    };
    if (!in.tet_regions.empty()) gather(in.tet_regions, 1);
    for (auto& f : in.cell_fields) gather(f.values, static_cast<size_t>(f.components));
  }
  std::vector<dtm::EncodeInput::Field> cell_fields;
  for (const auto& f : in.cell_fields)
    cell_fields.push_back({f.name, dtm::value_type(f.type), f.components, f.values});
  input.cell_fields = cell_fields;
  input.tetrahedra = in.tets;
  input.tetrahedron_regions = in.tet_regions;
  input.region_names = in.region_names;
  input.tagged_faces = in.tagged_faces;
  input.face_tags = in.face_tags;
  input.face_tag_names = in.face_tag_names;
  input.tetrahedra_on_grid = true;
  input.tetrahedra_done = [&in] {
    dtm::release(in.tets);
    dtm::release(in.tet_regions);
  };
  input.points_done = [&in, &input] {
    input.points = {};
    input.fields = {};
    dtm::release(in.points);
    for (auto& f : in.fields) dtm::release(f.values), dtm::release(f.edge_values);
  };
  c.encode.on_phase = [&](std::string_view phase) { display.start(phase); };
  // Without an output the stream is still made: the report gives its size.
  const auto encoded =
      dtm::encode(input, c.encode, std::move(plan).value(), [&](const dtm::LevelReport& level) {
        if (c.quiet) return;
        display.clear();
        dtm::print_table_row(stdout, level, grid);
      });
  if (!encoded.ok()) throw std::runtime_error(c.input + ": " + encoded.status().message());
  // A bricked level keeps no cell above its kept radius (region decoding
  // needs the bound). The encoder raises level 0's where its spacing would
  // drop cells of the input's solid (a graded mesh's coarse inside); where
  // some are still dropped, level 0 lacks them and its surface is farther
  // from the input's than D_max. Said, not left for the table to show.
  if (c.encode.bricks && mpi.rank() == 0 && !encoded->report.levels.empty()) {
    const dtm::EncodeReport& r = encoded->report;
    const dtm::LevelReport& l0 = r.levels.front();
    const double step = r.grid.step, dmax = r.dmax;
    const double far = std::max(l0.reference_to_level ? l0.reference_to_level->max : 0.0,
                                l0.level_to_reference ? l0.level_to_reference->max : 0.0) *
                       step;
    if (r.level0_cells_dropped > 0 && far > dmax * (1 + 1e-9))
      std::fprintf(
          stderr,
          "%s: level 0's surface is up to %.4g from the input's (D_max %.4g): a bricked stream keeps "
          "no cell of circumradius above its kept radius (%.4g), and the input's solid holds %llu "
          "such cells; without --bricks level 0 keeps them\n",
          c.input.c_str(), far, dmax, r.level0_kept_radius * step,
          static_cast<unsigned long long>(r.level0_cells_dropped));
  }
  if (!c.output.empty() || !c.report_path.empty())
    display.start("writing " + (c.output.empty() ? c.report_path : c.output));
  const dtm::EncodeReport& r = encoded->report;
  if (!c.quiet) {
    display.clear();
    print_reference_line(r);
    uint64_t value_bytes = r.field_table_bytes;
    for (const auto& f : r.fields) value_bytes += f.bytes;
    // (What is not the levels: the values, level 0's cell data and vertex
    // order, the edge nodes' values.)
    value_bytes += r.cell_field_table_bytes + r.cell_value_bytes + r.order_bytes + r.edge_value_bytes;
    // (Without -o, to try options: the size all the same, and the lines below
    // under it.)
    std::printf("%s: %llu bytes, %.2f bits per vertex for the levels (%zu vertices, %zu levels)%s\n",
                c.output.empty() ? "the stream (not written: no -o)" : c.output.c_str(),
                static_cast<unsigned long long>(r.stream_bytes),
                8.0 * (r.stream_bytes - value_bytes) / vertices, vertices, r.streamed_levels.size(),
                r.fields.empty() && r.cell_fields.empty() && r.order_bytes == 0 ? "" : ", and:");
    print_fields(r, vertices);
    if (!r.regions.empty()) {
      uint64_t region_bytes = r.region_table_bytes;
      for (uint64_t b : r.region_bytes) region_bytes += b;
      const uint64_t cells = r.levels.empty() ? 0 : r.levels.front().stats.tetrahedra;
      std::printf("  regions: %llu bytes (the table %llu), level 0: %llu bytes, %.3f bits per cell\n",
                  static_cast<unsigned long long>(region_bytes),
                  static_cast<unsigned long long>(r.region_table_bytes),
                  static_cast<unsigned long long>(r.region_bytes.empty() ? 0 : r.region_bytes.front()),
                  cells ? 8.0 * (r.region_bytes.empty() ? 0 : r.region_bytes.front()) / cells : 0.0);
    }
    for (const dtm::FieldReport& f : r.cell_fields) print_array_bytes("cell data", f, r.level0_cells);
    if (!r.cell_fields.empty() && r.cells_from_input == r.level0_cells)
      std::printf("  cell data on level 0's %llu cells: every one an input tetrahedron with its own values\n",
                  static_cast<unsigned long long>(r.level0_cells));
    else if (!r.cell_fields.empty())
      std::printf(
          "  cell data on level 0's %llu cells: %llu are input tetrahedra with their own values, the others "
          "take those of the input tetrahedron holding their centroid%s\n",
          static_cast<unsigned long long>(r.level0_cells),
          static_cast<unsigned long long>(r.cells_from_input),
          r.cells_from_nearest ? (" (" + std::to_string(r.cells_from_nearest) +
                                  " of the nearest beside them: none of their vertices' holds it)")
                                     .c_str()
                               : "");
    if (r.exact_bytes > 0 || r.exact_delaunay_cells > 0) {
      const uint64_t cells = r.exact_delaunay_cells + r.exact.fill_cells;
      std::printf(
          "  exact cells: level 0 is the input's %llu cells: %llu of them Delaunay cells, %llu sent in %llu "
          "bytes (%.2f bits each, %.2f bits per vertex; %llu of them made by %llu 3-2 flips of the %llu "
          "given a flag, %llu apexes the first candidate%s, %llu not candidates, %llu of those ranked in "
          "the second ring, %llu seeds)\n",
          static_cast<unsigned long long>(cells), static_cast<unsigned long long>(r.exact_delaunay_cells),
          static_cast<unsigned long long>(r.exact.fill_cells), static_cast<unsigned long long>(r.exact_bytes),
          r.exact.fill_cells ? 8.0 * r.exact_bytes / r.exact.fill_cells : 0.0, 8.0 * r.exact_bytes / vertices,
          2 * static_cast<unsigned long long>(r.exact.flips), static_cast<unsigned long long>(r.exact.flips),
          static_cast<unsigned long long>(r.exact.flip_candidates),
          static_cast<unsigned long long>(r.exact.rank_zero), r.exact.fit_work ? " that fits" : "",
          static_cast<unsigned long long>(r.exact.escapes),
          static_cast<unsigned long long>(r.exact.second_ring),
          static_cast<unsigned long long>(r.exact.seeds));
    }
    if (r.edge_nodes > 0)
      std::printf(
          "  edge nodes: level 0's %llu second-order edges' nodes in %llu bytes (%.2f bits per vertex; %llu "
          "off their edge's midpoint, %.2f bits each)\n",
          static_cast<unsigned long long>(r.edge_nodes), static_cast<unsigned long long>(r.edge_node_bytes),
          8.0 * r.edge_node_bytes / vertices, static_cast<unsigned long long>(r.moved_edge_nodes),
          r.moved_edge_nodes ? 8.0 * r.edge_node_bytes / r.moved_edge_nodes : 0.0);
    if (r.edge_value_bytes > 0)
      for (const dtm::FieldReport& f : r.fields)
        print_array_bytes("at the edge nodes, field", {f.description, f.edge_value_bytes}, r.edge_nodes);
    if (r.order_bytes > 0)
      std::printf("  vertex order (the input's numbering of level 0): %llu bytes, %.2f bits per vertex\n",
                  static_cast<unsigned long long>(r.order_bytes), 8.0 * r.order_bytes / vertices);
    if (r.node_label_bytes > 0)
      std::printf("  node labels (the input's node ids): %llu bytes\n",
                  static_cast<unsigned long long>(r.node_label_bytes));
    if (r.node_order_bytes > 0)
      std::printf(
          "  node order (the edge nodes among the vertices, as the input numbered them): %llu bytes, "
          "%.2f bits per edge node\n",
          static_cast<unsigned long long>(r.node_order_bytes),
          8.0 * r.node_order_bytes / static_cast<double>(std::max<uint64_t>(r.edge_nodes, 1)));
    if (!r.face_tags.empty()) {
      uint64_t face_bytes = r.face_table_bytes;
      for (uint64_t b : r.face_bytes) face_bytes += b;
      std::printf(
          "  tagged faces: %llu bytes (the table %llu), level 0: %llu bytes; level 0 keeps %llu of the "
          "input's %llu tagged triangles as its faces with their tags",
          static_cast<unsigned long long>(face_bytes), static_cast<unsigned long long>(r.face_table_bytes),
          static_cast<unsigned long long>(r.face_bytes.empty() ? 0 : r.face_bytes.front()),
          static_cast<unsigned long long>(r.tagged_faces_kept),
          static_cast<unsigned long long>(r.tagged_faces));
      // The others are not faces of level 0 (a triangle inside a region, or
      // where level 0 is not the input): their patches' tags are the nearest.
      if (r.tagged_faces_kept < r.tagged_faces)
        std::printf(
            "; the other %llu are not on its surface or an interface (inside a region, or where level "
            "0 is not the input), their patches tagged from the nearest",
            static_cast<unsigned long long>(r.tagged_faces - r.tagged_faces_kept));
      std::printf("\n");
    }
  }
  // What the encoder itself could not keep (the exact cells' fallback to
  // 11.0's coding), named as the reader's left-outs are: quiet or not, in
  // the report too; --strict refuses it, writing nothing.
  std::vector<std::string> dropped;
  if (r.edge_nodes_dropped > 0)
    dropped.push_back("the " + std::to_string(r.edge_nodes_dropped) +
                      " nodes on level 0's edges: the exact cells fell back to format 11.0's coding (its fit "
                      "tests over their budget), which holds none" +
                      (r.fields.empty() ? "" : ", and the fields' values there"));
  if (r.node_labels_dropped)
    dropped.emplace_back("the node ids: the exact cells fell back to format 11.0's coding, which holds none");
  for (const std::string& what : dropped) {
    if (mpi.rank() == 0)
      std::fprintf(stderr, "%s: left out (the stream does not hold it): %s\n", c.input.c_str(), what.c_str());
    in.left_out.push_back(what);
  }
  if (c.strict && !dropped.empty())
    throw std::runtime_error(c.input + ": --strict: the stream would leave out " +
                             std::to_string(dropped.size()) + " thing" + (dropped.size() == 1 ? "" : "s") +
                             " of the input (named above)");
  // Rank 0 writes; every rank fails with it (and says nothing of its own).
  std::string unwritten;
  if (mpi.rank() == 0) try {
      write_outputs(c, *encoded, in.left_out);
    } catch (const std::exception& e) {
      unwritten = e.what();
    }
  if (!mpi.all(unwritten.empty())) throw dtm::AgreedError(unwritten, mpi.rank() == 0);
  display.finish();
  // (The table on a full disk or a closed pipe: an error, not exit 0.)
  if (mpi.rank() == 0 && (std::fflush(stdout) != 0 || std::ferror(stdout)))
    throw std::runtime_error("cannot write to standard output");
  return 0;
}

}  // namespace

namespace dtm {
MpiSession* the_session = nullptr;
MpiSession& mpi_session() { return *the_session; }
}  // namespace dtm

int main(int argc, char** argv) {
  dtm::ask_for_huge_pages(argv);  // before MPI and any thread: it may start the tool again
  dtm::MpiSession mpi(&argc, &argv);
  dtm::the_session = &mpi;
  dtm::tool_rank() = mpi.rank();
  if (!dtm::ranks_run_the_same_command(mpi, "meshenc", argc, argv)) return 2;
  return dtm::tool_main<Command>("meshenc",
                                 "build the Delaunay level-of-detail hierarchy of a volume point set",
                                 kExamples, argc, argv, add_options, run);
}
