// .dtm bytes -> levels, coarsest first, as the bytes arrive. A layer is
// validated as soon as its bytes are in; its points join the Delaunay
// tetrahedralization the decoder holds (never rebuilt) when a mesh is asked
// for: one batch per layer if the caller looks at every level, one batch for
// all of them if it only looks at the last (as fast as a single CGAL
// construction). Level l's mesh is DT(V_l) carved with the stored alpha_l,
// corrected by the layer's carving section when the stream has them.
//
// Safety: nothing the stream claims is allocated before the bytes that
// justify it are present: points are stored as they are decoded, never
// reserved by count, and a level's vertex count is checked against
// DecoderOptions' limit before its payload is read. A damaged layer is reported with
// its level and byte offset and leaves the levels before it usable.
#pragma once

#include <array>
#include <cmath>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <span>
#include <vector>

#include "codec/bricks/bricks.h"
#include "codec/sections/cell_value_coder.h"
#include "codec/sections/edge_node_coder.h"
#include "codec/sections/face_coder.h"
#include "codec/sections/value_fields.h"
#include "codec/stream/format.h"
#include "codec/stream/layer_coder.h"
#include "common/progress.h"
#include "common/status.h"
#include "mesh/carving.h"
#include "mesh/delaunay.h"

namespace dtm {

struct DecoderOptions {
  // The most vertices a stream may make this decoder hold: a Delaunay
  // tetrahedralization needs ~600 bytes per vertex, so 30M fits in 24 GiB.
  uint64_t max_vertices = 30'000'000;
  // The most per-vertex values (vertices x components of every field) a
  // stream may make this decoder hold, 8 bytes each: 1G is 8 GiB.
  uint64_t max_values = 1'000'000'000;
  // Stop after this level (0 = finest; -1 = decode every level present).
  // A level the stream's header does not have is an error (kInvalidInput)
  // as soon as the header is read.
  int stop_after_level = -1;
  // Named as each phase of the work starts ("level 0: carving"), for a
  // tool's status line or timings (common/progress.h).
  PhaseCallback on_phase;
};

struct DecodedLevel {
  int level = 0;
  uint32_t vertices = 0;
  double alpha = 0;  // grid units
  // Bricked streams: no kept cell has a larger circumradius (carving_radius,
  // grid units; spec/FORMAT.md §3.5). Otherwise +infinity.
  double kept_radius = INFINITY;
  std::optional<uint64_t> cell_hash;
  // Bytes of the stream up to the end of this level's layer: what a reader
  // must have received to show the level (a viewer's bits per vertex).
  uint64_t stream_bytes = 0;
};

class ProgressiveDecoder {
 public:
  using LevelCallback = std::function<void(const ProgressiveDecoder&, const DecodedLevel&)>;

  explicit ProgressiveDecoder(DecoderOptions options = {});
  ~ProgressiveDecoder();
  ProgressiveDecoder(const ProgressiveDecoder&) = delete;
  ProgressiveDecoder& operator=(const ProgressiveDecoder&) = delete;

  // Takes the next bytes. `on_level` is called for every level completed by
  // them, with the decoder showing that level. Returns ok (waiting for more
  // bytes, or done) or the error that stopped decoding; after an error every
  // call returns it again.
  Status feed(std::span<const uint8_t> bytes, const LevelCallback& on_level = {});
  // At the end of the input: ok if every level (or the requested one) was
  // decoded, kTruncated if the input stopped early (the levels decoded stand),
  // or the error.
  Status finish() const;

  bool has_header() const { return has_header_; }
  // Every level of the stream is decoded (later bytes would be trailing data).
  bool complete() const { return has_header_ && levels_.size() == header_.level_count; }
  // The level asked for in DecoderOptions is decoded; later bytes are ignored.
  bool stopped() const { return stopped_; }
  const StreamHeader& header() const { return header_; }
  // The finest level decoded so far; -1 before the base layer.
  int finest_level() const;
  const std::vector<DecodedLevel>& levels() const { return levels_; }  // coarsest first

  // The vertices of the finest decoded level, coarsest layer first: level l
  // is the first level_vertices(l) of them.
  const std::vector<GridPoint>& points() const { return points_; }
  uint32_t level_vertices(int level) const;
  // Per vertex, the coarsest level that contains it.
  std::vector<int32_t> vertex_levels() const;
  // The stream's per-vertex fields (5.0; none before), each with the values
  // of points(), vertex-major. Valid once has_header() and the field table
  // are in; each whole layer adds its points' values.
  const std::vector<FieldValues>& fields() const { return fields_; }
  // DT of the finest decoded level (ids index points()) and its carving.
  // These bring the triangulation up to date first. If the points make a
  // degenerate triangulation (over kMaxCellsPerVertex cells per vertex, which
  // no mesh has: a hostile stream), they return nothing and mesh_status()
  // says why, for good. delaunay()'s cells are as the triangulation holds
  // them (built on every core, their order varies from run to run) unless
  // asked for in the canonical order (sorted vertex ids; it costs a sort);
  // carved_cells() are in the canonical order.
  TetMesh delaunay(IncrementalDelaunay::CellOrder order = IncrementalDelaunay::CellOrder::kAsBuilt,
                   double spare = 0) const;
  std::vector<std::array<uint32_t, 4>> carved_cells() const;
  // Per cell of `dt` (delaunay()'s result): whether the finest level keeps
  // it, alpha's verdict corrected by the stream's (spec/FORMAT.md §3.2):
  // 0 if not, else its region, 1 + its index in regions() (1 in a stream
  // of one region).
  std::vector<uint8_t> carving(const TetMesh& dt) const;
  // The same, and the canonical order of dt's cells (found on the way).
  // Level 0 of an exact stream (11.0 and 12.0, flag exact) is more than dt's cells:
  // there carving() gives the Delaunay cells it keeps, without their
  // regions; level_cells() gives the level.
  std::vector<uint8_t> carving(const TetMesh& dt, std::vector<uint32_t>& order) const;
  // The finest decoded level, for a writer: `mesh` holds delaunay()'s cells
  // and, at level 0 of an exact stream, the input's other cells after them
  // (codec/sections/exact_cell_coder.h), every kept cell's neighbour across
  // each face the cell now there; `kept` per cell of mesh as carving()
  // gives it (the region); `order` the canonical order of mesh's cells (the
  // exact cells last, as the section gives them). face_tags(), cell_data()
  // and vertex_order() take these. Empty, and mesh_status() set, if a
  // section is damaged.
  struct LevelCells {
    TetMesh mesh;
    std::vector<uint8_t> kept;
    std::vector<uint32_t> order;
  };
  LevelCells level_cells() const;
  // Level 0 of this stream is the input's cells (11.0 and 12.0, flag exact).
  bool exact_level() const { return (header_.flags & kFlagExact) && finest_level() == 0; }
  Status mesh_status() const { return mesh_status_; }
  // The stream's regions (9.0, flag regions; spec/FORMAT.md §2.2): the
  // label and name of each region index. Empty without regions.
  const std::vector<RegionLabel>& regions() const { return regions_; }
  // The finest level's surface (`kept`: carving()'s result for `dt`) and
  // each face's tag (9.0, flag faces; spec/FORMAT.md §3.7; bricked, 17.0:
  // §3.5): 1 + its index
  // in face_tag_table(), 1 = no tag (every face, without the flag). Empty
  // and mesh_status() set if the section is damaged.
  std::vector<uint8_t> face_tags(const TetMesh& dt, std::span<const uint8_t> kept,
                                 SurfaceFaces& surface) const;
  const std::vector<RegionLabel>& face_tag_table() const { return face_tags_; }
  // The stream's per-cell arrays (10.0, flag cell data; spec/FORMAT.md
  // §2.4, §3.8): their descriptions, and the values of level 0's kept
  // cells (`kept`, `order`: carving()'s results for `dt`), one FieldValues
  // per array, cell-major in the canonical order of the kept cells. Empty
  // without them or before level 0 (coarser levels carry none), and
  // mesh_status() set if the section is damaged.
  const std::vector<FieldDescription>& cell_field_table() const { return cell_fields_; }
  std::vector<FieldValues> cell_data(const TetMesh& dt, std::span<const uint8_t> kept,
                                     std::span<const uint32_t> order) const;
  // With flag vertex order (10.0, spec/FORMAT.md §3.9) and level 0 decoded:
  // for each input vertex in the input's numbering, its index in points()
  // (`dt`: delaunay()'s result). Empty otherwise, and mesh_status() set if
  // the section is damaged.
  std::vector<uint32_t> vertex_order(const TetMesh& dt) const;
  // With flag edge nodes (18.0, spec/FORMAT.md §3.11) and level 0 decoded:
  // the nodes on its kept cells' edges (`level`: level_cells()' result):
  // the edges (level_edges()), whether each has a node, and where, in grid
  // units (a midpoint lies halfway between grid points); with fields (19.0),
  // the nodes' values, one FieldValues per field, node-major over the
  // present nodes in the edges' order (empty in an 18.0 stream, which has
  // none). Empty otherwise, and mesh_status() set if a section is damaged.
  struct EdgeNodes {
    LevelEdges edges;
    std::vector<uint8_t> present;
    std::vector<std::array<double, 3>> points;
    std::vector<FieldValues> values;
  };
  bool has_edge_nodes() const { return (header_.flags & kFlagEdgeNodes) && finest_level() == 0; }
  // Whether level 0's edge nodes come in the input's numbering among its
  // vertices (a node order section, 21.0; in 23.0 a stream with the flags
  // may go without, its nodes then after the vertices as in 20.0).
  bool numbers_edge_nodes() const {
    return has_edge_nodes() && (header_.flags & kFlagVertexOrder) &&
           header_.version_major >= kVersionMajorNodeOrder && !node_order_section_.empty();
  }
  EdgeNodes edge_nodes(const LevelCells& level) const;
  // With edge nodes and the vertex order (21.0, spec/FORMAT.md §3.13) and
  // level 0 decoded: the input's nodes in its numbering, each a vertex (an
  // entry below points().size(): the vertices come in ascending order, the
  // vertex order's) or the present node r of `nodes` (points().size() + r,
  // r counting the present nodes in the edges' order). Empty otherwise (an
  // 18.0 to 20.0 stream puts the nodes after the vertices), and
  // mesh_status() set if the section is damaged.
  std::vector<uint32_t> node_order(const EdgeNodes& nodes) const;
  // With flag node labels (22.0, spec/FORMAT.md §3.14) and level 0 decoded:
  // the input's label of each of its `nodes` nodes (points().size(), and
  // with edge nodes the present ones too), in the input's numbering
  // (vertex_order()'s; with edge nodes, node_order()'s). Empty otherwise,
  // and mesh_status() set if the section is damaged.
  std::vector<int64_t> node_labels(size_t nodes) const;

 private:
  Status tables_read();
  Status step(const LevelCallback& on_level);
  Status fail(Status s);
  void insert_pending() const;
  // The layer's new points in Morton order, merged into known_.
  Status decode_layer_points(const Layer& layer, std::vector<GridPoint>& added);
  Status decode_bricked_layer(const Layer& layer, std::vector<GridPoint>& added);
  // A bricked layer's values, chunk by chunk (spec/FORMAT.md §3.5), into layer_values_.
  Status decode_bricked_values(const Layer& layer, std::span<const GridPoint> added);
  std::vector<uint8_t> bricked_carving(const TetMesh& dt, std::vector<uint32_t>& order) const;
  // A bricked level's cells by chunk: each cell's chunk of the finest
  // layer (kNoCarvingChunk: none codes it), and each point's Morton rank
  // (§3.5).
  struct BrickedCells {
    std::vector<uint32_t> chunk_of_cell, vertex_rank;
  };
  BrickedCells bricked_cells(const TetMesh& dt) const;
  // The sections of the finest layer's chunks that `part` picks.
  std::vector<std::span<const uint8_t>> chunk_sections(std::span<const uint8_t> ChunkBytes::*part) const;
  // A bricked level's tags of `surface` (17.0), from its chunks' faces.
  Status bricked_face_tags(const TetMesh& dt, std::span<const uint8_t> kept, const SurfaceFaces& surface,
                           std::vector<uint8_t>& tag) const;

  DecoderOptions options_;
  std::vector<uint8_t> pending_;  // bytes received and not yet consumed
  size_t pending_start_ = 0;
  bool has_header_ = false;
  bool has_field_table_ = false;
  bool has_region_table_ = false;
  uint64_t tables_bytes_ = 0;   // the field and region tables' bytes
  uint64_t finest_offset_ = 0;  // the finest level's layer: where it starts in the stream
  // "level L at byte B": where an error in the finest level's sections is.
  std::string finest_where() const;
  std::vector<RegionLabel> regions_;
  std::vector<uint8_t> region_section_;  // the finest level's
  bool has_face_table_ = false;
  std::vector<RegionLabel> face_tags_;
  std::vector<uint8_t> face_section_;  // the finest level's
  bool has_cell_field_table_ = false;
  std::vector<FieldDescription> cell_fields_;
  std::vector<uint8_t> cell_value_section_;  // level 0's
  std::vector<uint8_t> order_section_;       // level 0's
  std::vector<uint8_t> exact_section_;       // level 0's
  std::vector<uint8_t> edge_node_section_;   // level 0's
  std::vector<uint8_t> edge_value_section_;  // level 0's
  std::vector<uint8_t> node_order_section_;  // level 0's
  std::vector<uint8_t> node_label_section_;  // level 0's
  StreamHeader header_;
  std::optional<FieldSectionDecoder> value_decoder_;
  std::vector<FieldValues> fields_;
  std::vector<FieldValues> layer_values_;  // scratch: one layer's
  std::optional<LayerWalk> walk_;          // made with the header
  std::vector<DecodedLevel> levels_;
  std::vector<GridPoint> points_;
  std::vector<uint8_t> carving_;  // the finest level's carving section
  // Bricked streams (8.0): the finest layer's index, chunks (their carving
  // sections are the level's corrections), brick depth and kept radius.
  std::vector<BrickChunk> chunks_;
  std::vector<uint8_t> chunk_bytes_;
  int brick_depth_ = 0;
  double kept_radius_ = 0;
  std::vector<MortonCode> known_;  // Morton codes of points_, ascending: the coder's context
  SetCoderModels models_;          // the layer coder's models, adapted layer after layer
  // The triangulation lags behind points_ until a mesh is asked for.
  mutable IncrementalDelaunay dt_;
  mutable size_t inserted_ = 0;        // points_ already in dt_
  mutable size_t layers_pending_ = 0;  // whole layers not yet in dt_
  mutable Status mesh_status_;         // why dt_ is unusable, if it is
  Status error_;
  bool stopped_ = false;  // the requested level is decoded
};

// One call: decodes `bytes` with `decoder` (up to its stop_after_level) and
// returns finish()'s status; `decoder` then holds the result.
Status decode_stream(std::span<const uint8_t> bytes, ProgressiveDecoder& decoder);

}  // namespace dtm
