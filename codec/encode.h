// Encoding in one call: points (and, when the input has them, its
// tetrahedra) -> a .dtm stream, with the report of every level.
//
//   dtm::EncodeInput in;
//   in.points = points;                      // std::vector<dtm::InputPoint>
//   dtm::EncodeOptions options;              // q = 14, D_max = 0.5% of the extent, ...
//   auto encoded = dtm::encode(in, options);
//   if (!encoded.ok()) fail(encoded.status().message());
//   write(encoded->bytes);                   // decode with codec/decode.h
//
// The policies every caller would otherwise copy live here: the voxel
// lattice as the grid, the default D_max, lengths in input units. Callers
// who build the hierarchy themselves use codec/expert_encode.h.
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <map>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "codec/sections/exact_cell_coder.h"
#include "codec/sections/region_coder.h"
#include "codec/sections/value_fields.h"
#include "common/exchange.h"
#include "common/grid.h"
#include "common/progress.h"
#include "common/status.h"
#include "core/hierarchy.h"
#include "core/quantize.h"
#include "core/solid_difference.h"
#include "core/surface_distance.h"
#include "core/voxel_solid.h"
#include "mesh/carving.h"

namespace dtm {

class ReferenceShare;  // codec/blocks/reference_share.h

struct EncodeOptions {
  // The grid: bits per axis, 1 to 24; 0 = 14, or for a lattice input just
  // enough bits for its extent (a larger value is allowed, not a smaller).
  int qbits = 0;
  // Input coordinates are multiplied by `scale` first, or, if box > 0, by
  // whatever makes their largest extent `box`. Every length below and in
  // the report is in these scaled input units; the stream is not (it holds
  // the grid in the input's units: the decoded mesh is the input's size).
  double scale = 1.0;
  double box = 0;

  // The hierarchy (spec/HIERARCHY.md). The defaults are the codec's levels;
  // EncodeOptions::paper() the seed paper's.
  // Boundary tolerance; 0 = 0.5% of the input's largest extent (of a
  // voxel lattice's points, the solid's, not its grid's: plan_encoding()).
  double dmax = 0;
  // Every level keeps the cells inside the reference solid (the input's
  // tetrahedra, or level 0's alpha carving), alpha only predicting them and
  // the stream correcting it; false: alpha alone carves (the paper).
  bool carve_to_reference = true;
  // Each level removes about this share of the finer level's vertices, in
  // several independent-set passes; 0: one pass per level (the paper).
  double removal_share = 0.5;
  AlphaKind alpha = AlphaKind::kPaper;
  double fixed_alpha = 0;               // with AlphaKind::kFixed
  int max_levels = 0;                   // coarser levels at most; 0 = no limit
  size_t min_base_vertices = 16;        // never build a level with fewer vertices
  bool paper_stop = true;               // stop at the first level removing no boundary vertex
  double quality_guard = 0;             // HierarchyOptions::quality_guard; 0 = off
  double quality_ratio = 0;             // HierarchyOptions::quality_ratio; 0 = off
  double average_quality_floor = 0.85;  // HierarchyOptions::average_quality_floor; 0 = off
  double quality_floor_cap = 0.25;      // HierarchyOptions::quality_floor_cap; 0 = none
  bool measure_boundary_error = true;   // LevelStats' max/mean_boundary_error

  // Fields coded lossily: name -> E, every decoded value within E of the
  // original (float fields only). The others are lossless.
  std::map<std::string, double> field_errors;

  // The stream (codec/expert_encode.h, StreamOptions).
  int level_step = 1;
  bool cell_hashes = false;
  bool candidates = true;
  // Level 0's vertices in the input's numbering (format 10.0; meshenc
  // --keep-order): the decoder gives them in the input's order. Needs every
  // input point its own grid point (no merge by quantization) and the codec
  // preset; not with bricks.
  bool keep_order = false;
  // Level 0 equal to the input's tetrahedra (format 12.0; meshenc --exact):
  // the same cells, positively oriented, coded as corrections to the
  // Delaunay tetrahedralization the decoder builds. Needs the input's
  // tetrahedra, a valid mesh on the grid (no point merged by quantization,
  // no cell flat there) and the codec preset; not with bricks.
  bool exact = false;
  // EncodedMesh::vertex_of_input made (false: left empty, for a caller that
  // does not need it; encode() handed the plan by rvalue then frees the
  // plan's map from input points once it is read no more, 4 bytes an input
  // point).
  bool vertex_of_input = true;
  // How the exact cells are coded: kClosingFirst (the default) writes
  // 23.0; kAfterFlips 14.0 (18.0 to 22.0 with edge nodes or node ids),
  // kAmongFittingInContext 13.0, kAmongFitting 12.0, kAmongCandidates 11.0,
  // which older decoders read, at more bits (StreamOptions).
  ApexRanks exact_ranks = ApexRanks::kClosingFirst;
  // A second-order input's edge nodes as format 18.0 coded them (each
  // offset alone, no values there), for decoders of 18.0; or as 19.0 did
  // (the surface's normals summed across its creases), for decoders of
  // 19.0; both false: 20.0 (StreamOptions).
  bool edge_nodes_v18 = false;
  bool edge_nodes_v19 = false;
  // With keep_order, a second-order mesh's edge nodes after the vertices, as
  // 20.0 streams have them (21.0: where the input numbered them, with
  // EncodeInput::node_numbering).
  bool edge_nodes_v20 = false;
  // Bricked layers (format 8.0, codec/blocks/bricked_encoder.h): the levels built
  // block by block (blocks of about block_points points), each layer's
  // points and corrections in chunks of about brick_points new points.
  // The codec preset only; every level (no level_step), no candidates, no
  // exact cells or vertex order yet.
  bool bricks = false;
  uint64_t brick_points = 2048;
  uint64_t block_points = uint64_t{1} << 18;
  // Blocks built at once by this process (each on its share of the
  // threads); 0: one per thread. Memory grows with it, the stream does not
  // change.
  int blocks_at_once = 0;
  // A block a neighbour changed is checked where it changed rather than
  // built again when its last build was clean (codec/blocks/block_levels.h,
  // check_part()); false: built again. The stream is the same either way.
  bool check_parts = true;
  // A level built in one block is analysed from the build's
  // tetrahedralization rather than one made again; false: made again. The
  // stream is the same either way.
  bool reuse_build_mesh = true;
  // The ranks of an MPI run making one bricked stream together (every rank
  // calls encode() with the same input and options, but for the
  // tetrahedra: each needs only its share, EncodeInput::tetrahedra);
  // nullptr: this process.
  RankExchange* exchange = nullptr;
  // The share of the tetrahedra this rank was given, cut by the plan's
  // points (codec/blocks/reference_share.h): a caller that cut them passes its
  // own, so that the cuts are found once; nullptr: made from `exchange`.
  const ReferenceShare* reference_share = nullptr;

  // Told each phase of the work as it starts (common/progress.h): the
  // hierarchy's levels, then the stream's.
  PhaseCallback on_phase;

  // The seed paper's hierarchy: alpha carving without corrections, one
  // independent set per level, its quality trade-off (a removal may not make
  // its neighbourhood's smallest solid angle worse than min(0.3, the star's))
  // and its stopping rule.
  static EncodeOptions paper() {
    EncodeOptions o;
    o.carve_to_reference = false;
    o.removal_share = 0;
    o.quality_ratio = 0;
    // The paper's trade-off: as many removals as keep the mesh's average
    // smallest solid angle at level 0's (§III, Tables 1-2).
    o.quality_guard = 0;
    o.average_quality_floor = 1;
    o.quality_floor_cap = 0;
    o.paper_stop = true;
    return o;
  }
};

struct EncodeInput {
  std::span<const InputPoint> points;
  // The input's own tetrahedra (indices into `points`), when it has them:
  // the reference shape each level's boundary is measured against. Under
  // an exchange of several ranks, each rank may be given only the
  // tetrahedra its share holds (codec/blocks/reference_share.h, on the plan's grid
  // ids): a rank never needs them all (the others, when given, are
  // ignored), but with cell_fields, which need them all.
  std::span<const std::array<uint32_t, 4>> tetrahedra;
  // A second-order mesh's nodes on its tetrahedra's edges
  // (tools/formats/second_order.h), each edge once: its corners (as
  // `tetrahedra` names points) and where the node lies. Kept with
  // EncodeOptions::exact (format 18.0, spec/FORMAT.md §3.11: level 0's
  // cells are the input's, and so are its edges); unused without it.
  struct EdgeNode {
    std::array<uint32_t, 2> corners;
    InputPoint at;
  };
  std::span<const EdgeNode> edge_nodes;
  // With EncodeOptions::keep_order and edge_nodes kept: the input's
  // numbering of the points and edge nodes together (format 21.0,
  // spec/FORMAT.md §3.13), entry k its node k: a point (an index into
  // `points`, the points coming in ascending order) or an edge node
  // (points.size() + its index in edge_nodes), each once. Empty, or with
  // EncodeOptions::edge_nodes_v18 or edge_nodes_v19: the decoded edge
  // nodes follow the vertices (20.0, 19.0, 18.0).
  std::span<const uint32_t> node_numbering;
  // With EncodeOptions::keep_order: the input's label of each node (a file's
  // node id: gmsh's node tag, an Abaqus node number, an Exodus node map's
  // id), in the input's numbering (node_numbering's order where the stream
  // keeps it, else the points'), each in [1, 2^62 - 1], no two alike
  // (format 22.0, spec/FORMAT.md §3.14). Empty: the nodes are numbered 1
  // to n. Not kept where the stream keeps edge nodes without their
  // numbering.
  std::span<const int64_t> node_labels;
  // Per tetrahedron, its region (material): the input's own label (a gmsh
  // physical volume, a Medit ref, ...); empty: none. Every level's cells
  // then carry the region that holds their centroid (format 9.0; bricked,
  // 15.0, on one process or on ranks). At most 255 distinct labels; not with the paper
  // preset. With
  // tetrahedra_on_grid, in the order of `tetrahedra` (grid_tetrahedra_in_place
  // with the labels).
  std::span<const int32_t> tetrahedron_regions;
  // Names of the labels, where the input has them ($PhysicalNames). A name
  // of a label no tetrahedron has is kInvalidInput (it would be lost).
  std::map<int32_t, std::string> region_names;
  // The input's tagged triangles (indices into `points`: gmsh physical
  // surfaces, Medit triangle refs) and each one's tag: every level's surface
  // faces carry a tag (core/face_tags.h; format 9.0, in bricks 17.0). At
  // most 254 distinct tags; needs the tetrahedra; not with the paper
  // preset. On the ranks of a bricked run, every rank must be given every
  // tetrahedron and the same tagged triangles (kInvalidInput on every rank
  // otherwise).
  std::span<const std::array<uint32_t, 3>> tagged_faces;
  std::span<const int32_t> face_tags;
  std::map<int32_t, std::string> face_tag_names;  // likewise, of tags some face has
  // The tetrahedra name the plan's grid points already (grid_tetrahedra()
  // of the input's, core/reference_shape.h): a caller short of memory frees
  // its own before encoding (meshenc does, for meshes of 10M vertices).
  bool tetrahedra_on_grid = false;
  // Called once the encoder reads `tetrahedra` no more, so that the caller
  // may free them: the bricked encoder (EncodeOptions::bricks) calls it
  // before its levels are built (keeping its own copy of the few it tests
  // again), or with cell_fields once level 1 is built (level 0's cells then
  // have their values); the whole-level encoder reads them to the end and
  // does not call it.
  std::function<void()> tetrahedra_done;
  // Called once the encoder reads `points` and the fields' values no more
  // (it holds them on its grid), before its levels are built, so that the
  // caller may free them (24 bytes a point and 8 a value).
  std::function<void()> points_done;
  // A scan's voxels (the input's points are some of their centres): the
  // solid every level is carved to, when there are no tetrahedra.
  const VoxelMask* voxels = nullptr;
  // Points that already lie on an integer lattice (a voxel volume's
  // centres, core/quantize.h's form, in the same order as `points`): its
  // grid is used as it is, so positions are coded losslessly.
  const QuantizedPoints* lattice = nullptr;
  // Per-vertex fields to code with the points (a 5.0 stream; none: 4.0),
  // and at the edge nodes (19.0).
  struct Field {
    std::string name;
    ValueType type = ValueType::kF64;
    int components = 1;
    std::span<const double> values;  // per point, `components` each (point-major)
    // With edge_nodes kept (exact): per edge node, in their order,
    // `components` each; empty: each node's value is its edge's corners'
    // mean (a float field's; an integer field's the lesser).
    std::span<const double> edge_values{};
  };
  std::span<const Field> fields;
  // Per-cell arrays (element results, material properties): `values` per
  // tetrahedron of `tetrahedra` (in its order, also with
  // tetrahedra_on_grid), `components` each. Level 0's cells carry them
  // (format 10.0; core/cell_sources.h says which input tetrahedron gives a
  // cell its values), lossless or within EncodeOptions::field_errors;
  // coarser levels carry none. In bricks too (format 16.0), on ranks as
  // well, where every rank must then be given every tetrahedron and its
  // values, not its share (kInvalidInput otherwise). Not with the paper
  // preset.
  std::span<const Field> cell_fields;
};

struct FieldReport {
  FieldDescription description;
  uint64_t bytes = 0;  // its value sections' bytes over every layer
  // Of a per-vertex field of a stream with edge nodes (19.0): its share of
  // the edge value section, length words included.
  uint64_t edge_value_bytes = 0;
};

struct LevelReport {
  LevelStats stats;  // lengths in grid units: multiply by grid.step
  // With tetrahedra in the input: the distance between the input's boundary
  // surface and this level's, both ways, grid units.
  std::optional<DistanceSummary> reference_error;  // both ways together
  std::optional<DistanceSummary>
      reference_to_level;  // the reference's boundary vertices to the level's surface
  std::optional<DistanceSummary> level_to_reference;  // the level's surface to the reference's
};

struct EncodeReport {
  Grid grid;             // origin and step in scaled input units
  Grid stream_grid;      // the same in the input's units: the stream's (EncodePlan::stream_grid)
  double scale = 1.0;    // what the input coordinates were multiplied by
  double dmax = 0;       // scaled input units
  bool lattice = false;  // the input's lattice is the grid: lossless
  uint64_t input_points = 0;
  uint64_t duplicates_merged = 0;
  uint64_t reference_tetrahedra = 0;  // after quantization, 0 without tetrahedra
  uint64_t reference_voxels = 0;      // the voxels of the solid carved to, 0 without
  uint64_t reference_boundary_vertices = 0;
  // Bricked on MPI ranks, the reference in parts: the points whose place in
  // it the ranks answered in their exchanges, and the blocks' runs that
  // asked them (each run again once answered); the points the ranks
  // answered while they worked (the blocks' passes run again, not the
  // blocks).
  uint64_t reference_questions = 0, reference_question_runs = 0, reference_questions_at_once = 0;
  // Bricked: the blocks a neighbour changed (summed over the levels'
  // passes), built again and checked where they changed instead.
  uint64_t blocks_built_again = 0, blocks_checked_in_parts = 0;
  // Bricked: the levels analysed from their build's tetrahedralization
  // (built in one block, analysed in one, on this rank).
  uint64_t levels_analysed_from_build = 0;
  // Bricked, carved to the input's solid: level 0's kept radius (grid
  // units) as its mean spacing sets it, and as the encoder raised it where
  // the solid holds larger cells (a graded mesh's coarse inside) that level
  // 0 would otherwise lack, beyond D_max (equal when not raised); the cells
  // of the solid thicker than D_max that level 0 leaves out all the same
  // (a few, within D_max, are not worth a raise; more once its rounds end).
  double level0_spacing_kept_radius = 0, level0_kept_radius = 0;
  uint64_t level0_cells_dropped = 0;
  // With tetrahedra in the input: level 0's solid against the input's, grid
  // units cubed (core/solid_difference.h).
  std::optional<SolidDifference> level0_difference;
  std::vector<LevelReport> levels;                       // every hierarchy level, finest first
  std::vector<uint64_t> layer_bytes;                     // per hierarchy level; 0 if not streamed
  std::vector<uint64_t> carving_bytes;                   // of those, the carving corrections
  std::vector<uint64_t> candidate_bytes;                 // of those, the candidate section (7.0)
  std::vector<uint64_t> candidate_points;                // the points it sends
  std::vector<uint64_t> value_bytes;                     // of those, the values
  std::vector<std::vector<uint64_t>> level_field_bytes;  // and of those, each field's (empty if not streamed)
  std::vector<FieldReport> fields;
  uint64_t field_table_bytes = 0;
  std::vector<RegionLabel> regions;    // the region table (empty without regions)
  std::vector<uint64_t> region_bytes;  // per hierarchy level, its region section
  uint64_t region_table_bytes = 0;
  std::vector<RegionLabel> face_tags;  // the face tag table (empty without tagged faces)
  // The region and face tag names longer than a stream holds (64 bytes), as
  // given: the tables hold their first 64 bytes (a UTF-8 character whole).
  std::vector<std::string> names_cut;
  std::vector<uint64_t> face_bytes;  // per hierarchy level, its face section
  uint64_t face_table_bytes = 0;
  // The input's tagged triangles (those quantization did not collapse), and
  // how many of them are faces of level 0 (their tags kept exactly).
  uint64_t tagged_faces = 0, tagged_faces_kept = 0;
  // Level 0's cell data (10.0): each array with its bytes, the table's and
  // the section's size, level 0's kept cells, and of those how many are
  // input tetrahedra (their values exact) and how many took the nearest of
  // their vertices' tetrahedra's (core/cell_sources.h; the rest, the one
  // holding their centroid).
  std::vector<FieldReport> cell_fields;
  uint64_t cell_field_table_bytes = 0, cell_value_bytes = 0;
  uint64_t level0_cells = 0, cells_from_input = 0, cells_from_nearest = 0;
  uint64_t order_bytes = 0;  // the vertex order section (--keep-order), 0 without
  // --exact: the exact cell section's bytes, the input cells that are
  // level 0's Delaunay cells, and the fill's figures (the rest).
  uint64_t exact_bytes = 0;
  // --exact of a second-order mesh (18.0): the edge node section's bytes,
  // the edges of level 0 with a node, and the nodes off their edge's
  // midpoint (a curved boundary's).
  uint64_t edge_node_bytes = 0;
  uint64_t edge_nodes = 0;
  uint64_t moved_edge_nodes = 0;
  uint64_t edge_value_bytes = 0;     // the nodes' values (19.0)
  uint64_t node_order_bytes = 0;     // --keep-order: the nodes among the vertices (21.0)
  uint64_t node_label_bytes = 0;     // --keep-order: the input's node ids (22.0)
  bool node_labels_dropped = false;  // given, not written (the exact cells fell back to 11.0's coding)
  uint64_t edge_nodes_dropped = 0;   // given, not written (the exact cells fell back to 11.0's coding)
  uint64_t exact_delaunay_cells = 0;
  ExactStats exact;
  // Points merged by quantization whose values differed: each vertex keeps
  // its first point's values.
  uint64_t merged_points_with_other_values = 0;
  std::vector<int> streamed_levels;  // hierarchy level of each stream level
  uint64_t stream_bytes = 0;
};

struct EncodedMesh {
  std::vector<uint8_t> bytes;
  EncodeReport report;
  // For each input point, the index of its vertex in the order the decoder
  // produces them (ProgressiveDecoder::points(): coarsest layer first,
  // ascending Morton code within a layer). Points that quantization merged
  // share a vertex.
  std::vector<uint32_t> vertex_of_input;
};

// The grid `input` and `options` make, and D_max in its units: what encode()
// uses, for callers who want to say it before the (long) work starts.
struct EncodePlan {
  QuantizedPoints quantized;  // its grid in scaled input units: the encoder measures in them
  // The same grid in the input's own units (origin and step divided by the
  // scale; a lattice's own): what the stream's header holds, so that the
  // decoded mesh is in the input's units whatever --scale or --box said.
  Grid stream_grid;
  double scale = 1.0;
  double dmax = 0;  // scaled input units
};
StatusOr<EncodePlan> plan_encoding(const EncodeInput& input, const EncodeOptions& options);

// --exact's check of a plan's grid: no two input points on one grid point,
// no input cell losing a corner or turning flat or over there. kInvalidInput
// says what goes wrong and the --qbits that would keep them apart, if a grid
// of up to 24 bits does. `tetrahedra` index `points`.
Status check_exact_grid(std::span<const InputPoint> points,
                        std::span<const std::array<uint32_t, 4>> tetrahedra, const EncodePlan& plan);

// Called once per hierarchy level as soon as it is built.
using LevelReady = std::function<void(const LevelReport&)>;

// kInvalidInput (with the reason) for options out of range, points that
// cannot make a tetrahedral mesh (fewer than 4 distinct, all coplanar), or a
// field that does not fit the points or cannot be coded as asked (a NaN in a
// lossy field: the field's name and the first point's index).
StatusOr<EncodedMesh> encode(const EncodeInput& input, const EncodeOptions& options = {},
                             const LevelReady& on_level = {});
// The same, from a plan_encoding() result of this input, which holds the
// points on the grid: `input.points` is read no more (and may be empty), so
// a caller may free them before reading what remains of the input.
StatusOr<EncodedMesh> encode(const EncodeInput& input, const EncodeOptions& options, const EncodePlan& plan,
                             const LevelReady& on_level = {});
// The same, handed the plan: with options.vertex_of_input false, its map
// from input points (plan.quantized.input_to_point) is freed once read, before
// the levels are built.
StatusOr<EncodedMesh> encode(const EncodeInput& input, const EncodeOptions& options, EncodePlan&& plan,
                             const LevelReady& on_level = {});

}  // namespace dtm
