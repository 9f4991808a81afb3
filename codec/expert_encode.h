// The expert's encoder: a built hierarchy -> .dtm bytes. codec/encode.h is
// the one-call path (quantize, build the hierarchy, encode); this header is
// for callers who build or adjust the hierarchy themselves.
//
//   auto q = quantize(points, 14);
//   auto h = build_hierarchy(q->points, hierarchy_options);
//   auto stream = encode_stream(*h, q->points, q->grid, hierarchy_options.alpha.kind);
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <span>
#include <vector>

#include "codec/sections/exact_cell_coder.h"
#include "codec/sections/region_coder.h"
#include "codec/sections/value_fields.h"
#include "common/grid.h"
#include "common/status.h"
#include "core/face_tags.h"
#include "core/hierarchy.h"
#include "core/quantize.h"
#include "mesh/carving.h"

namespace dtm {

// A node on an edge of the exact cells (a second-order mesh's): the edge's
// corners (indices into `points`), where the node lies in the grid's units
// (not rounded), and whether it is the midpoint of its edge in the input
// (then it is the midpoint of the corners' grid points, whatever their
// rounding).
struct GridEdgeNode {
  std::array<uint32_t, 2> corners;
  std::array<double, 3> at;
  bool midpoint = false;
};

struct StreamOptions {
  // Store each level's canonical cell-set hash, so that a decoder built
  // against another CGAL can prove it rebuilt the same meshes (meshdec --verify).
  bool cell_hashes = false;
  // Stream every level_step-th level of the hierarchy (levels 0, s, 2s, ...)
  // and its coarsest: fewer, larger layers cost fewer bits (each layer's
  // points are coded given the coarser ones, and deciding which layer a point
  // belongs to is what costs) at the price of fewer levels of detail. The
  // stream numbers its levels 0, 1, 2, ... in that order.
  int level_step = 1;
  // Format 7.0's candidate section (spec/FORMAT.md §3.4) in the finest
  // layer where it pays (codec/expert_encode.cpp): fewer bits on meshes
  // from Delaunay refinement, for a decoder that builds the next coarser
  // level's tetrahedralization first. Off: every point through the set coder.
  bool candidates = true;
  // The regions of the cells (format 9.0, spec/FORMAT.md §2.2, §3.6): the
  // table, whose index + 1 each level's Level::kept holds per kept cell.
  // Empty: one region, no table (Level::kept holds 1).
  std::vector<RegionLabel> regions;
  // The surface faces' tags (format 9.0, spec/FORMAT.md §2.3, §3.7): the
  // tag table and what gives each level's faces theirs (core/face_tags.h,
  // whose labels are 2 + a tag's index). Empty / null: none.
  std::vector<RegionLabel> face_tags;
  const FaceTagger* faces = nullptr;
  // Per-cell arrays of level 0 (format 10.0, spec/FORMAT.md §2.4, §3.8):
  // given level 0's kept cells (grid ids, indices into `points`), their
  // values, one FieldValues per array, cell-major in the order given.
  // Empty: none. Needs a hierarchy carved to a reference.
  std::function<StatusOr<std::vector<FieldValues>>(std::span<const std::array<uint32_t, 4>>)> cell_values;
  // Level 0's vertices in the input's numbering (format 10.0, spec/FORMAT.md
  // §3.9): the grid point of each input vertex, a permutation of `points`.
  // Empty: none. Needs a hierarchy carved to a reference.
  std::span<const uint32_t> input_order;
  // Level 0 equal to the input's cells (format 12.0, spec/FORMAT.md §3.10):
  // the input's tetrahedra (grid ids, indices into `points`, any
  // orientation) and each one's label as Level::kept holds them (1 + its
  // region's index; empty: 1 each). level 0 then keeps its Delaunay cells
  // that are input cells and the exact cell section sends the others.
  // Empty: level 0 as the hierarchy carved it. Needs a hierarchy carved to a
  // reference; with cell_values, the cells given are these, in this order.
  std::span<const std::array<uint32_t, 4>> exact_cells;
  std::span<const uint8_t> exact_labels;
  // How the exact cells are coded (ApexRanks): 23.0, or for older
  // decoders 14.0, 13.0, 12.0 or 11.0 (11.0 is also what the encoder falls
  // back to where the fit tests pass their budget).
  ApexRanks exact_ranks = ApexRanks::kClosingFirst;
  // With exact_cells, of a second-order input (format 18.0, spec/FORMAT.md
  // §3.11): the nodes on the exact cells' edges, each edge once; empty:
  // none. Needs exact_ranks 14.0's or 23.0's. With fields, each field's values hold a
  // row for each node after the points' (the k-th node's at row
  // points.size() + k): the edge value section (19.0, §3.12) carries them.
  std::span<const GridEdgeNode> edge_nodes;
  // The edge nodes as 18.0 codes them: each offset from its edge's midpoint
  // alone (19.0: from the offset the surface's normals predict), without
  // the fields' values there; as 19.0 codes them: the surface's normals
  // summed across its creases (20.0: the creases apart).
  bool edge_nodes_v18 = false;
  bool edge_nodes_v19 = false;
  // With input_order and edge_nodes (format 21.0, spec/FORMAT.md §3.13):
  // the input's numbering of its vertices and edge nodes together, entry k
  // its node k: a vertex (below points.size(), in ascending order: the
  // input vertex input_order names) or an edge node (points.size() + its
  // index in edge_nodes), each once. Empty: the nodes after the vertices
  // (20.0). Not with edge_nodes_v18 or edge_nodes_v19.
  std::span<const uint32_t> node_numbering;
  // With input_order (format 22.0, spec/FORMAT.md §3.14): the input's label
  // of each node in its numbering (node_numbering's order where it is
  // given, else input_order's), each in [1, kMaxNodeLabel], no two alike.
  // Empty: the nodes numbered 1 to n. With edge_nodes, only with
  // node_numbering.
  std::span<const int64_t> node_labels;
  // (Bricked streams, format 8.0, come from codec/blocks/bricked_encoder.h: their
  // levels are built block by block.)
};

struct EncodedStream {
  std::vector<uint8_t> bytes;
  // Bytes of each hierarchy level's layer (header included), indexed by
  // hierarchy level; 0 for a level left out by level_step.
  std::vector<uint64_t> layer_bytes;
  // Of those, the carving corrections' (spec/FORMAT.md §3.2) and the
  // values' (§3.3).
  std::vector<uint64_t> carving_bytes;
  std::vector<uint64_t> region_bytes;  // of those, the region sections' (9.0)
  uint64_t region_table_bytes = 0;
  std::vector<uint64_t> face_bytes;  // of those, the face sections' (9.0)
  uint64_t face_table_bytes = 0;
  // Of the input's tagged triangles, those that are faces of level 0's
  // surface (their tags kept exactly).
  uint64_t tagged_faces_kept = 0;
  std::vector<uint64_t> value_bytes;
  // Of those, the candidate section's (§3.4; 0 where the layer sends every
  // point through the set coder), and how many points it sends.
  std::vector<uint64_t> candidate_bytes;
  std::vector<uint64_t> candidate_points;
  // The field table as written (with its scales), each field's bytes over
  // every layer, and the table's own size.
  std::vector<FieldDescription> fields;
  std::vector<uint64_t> field_bytes;
  std::vector<std::vector<uint64_t>> level_field_bytes;  // per hierarchy level, per field
  uint64_t field_table_bytes = 0;
  // The cell field table as written, each array's bytes in level 0's cell
  // value section, the table's size and the section's (10.0).
  std::vector<FieldDescription> cell_fields;
  std::vector<uint64_t> cell_field_bytes;
  uint64_t cell_field_table_bytes = 0;
  uint64_t cell_value_bytes = 0;
  uint64_t level0_cells = 0;  // level 0's kept cells
  uint64_t order_bytes = 0;   // the vertex order section (10.0)
  // The exact cell section (11.0, 12.0) and what it held: level 0's Delaunay
  // cells that are input cells, and the fill's figures.
  uint64_t exact_bytes = 0;
  uint64_t exact_delaunay_cells = 0;
  ExactStats exact;
  // The edge node section (18.0): its bytes, level 0's edges that have a
  // node, and of those the nodes off their edge's midpoint.
  uint64_t edge_node_bytes = 0;
  uint64_t edge_nodes = 0;
  uint64_t moved_edge_nodes = 0;
  // The edge value section (19.0): its bytes, and each field's share of
  // them (length words included).
  uint64_t edge_value_bytes = 0;
  std::vector<uint64_t> edge_node_field_bytes;
  uint64_t node_order_bytes = 0;  // the node order section (21.0)
  uint64_t node_label_bytes = 0;  // the node label section (22.0)
  // Node labels given and not written: the exact cells fell back to 11.0's
  // coding, whose streams cannot hold them.
  bool node_labels_dropped = false;
  // Edge nodes given and not written: the exact cells fell back to 11.0's
  // coding (its fit tests over their budget), which has none.
  uint64_t edge_nodes_dropped = 0;
  // The hierarchy level of each stream level (finest first).
  std::vector<int> streamed_levels;
  // The order in which a decoder produces the vertices (coarsest layer
  // first, ascending Morton code within a layer): decode_order[i] is the
  // index into `points` of the decoder's vertex i.
  std::vector<uint32_t> decode_order;
};

// `points` are the grid points the hierarchy's vertex indices refer to;
// `fields`, if any, give a value per point (and component) each: the stream
// is then 5.0 and carries them. kInvalidInput if the levels are not nested,
// level_step < 1, there are more than 65535 levels to stream, or a field is
// malformed or cannot be coded as asked (FieldSectionEncoder::make).
StatusOr<EncodedStream> encode_stream(const Hierarchy& hierarchy, std::span<const GridPoint> points,
                                      const Grid& grid, AlphaKind alpha_policy,
                                      const StreamOptions& options = {},
                                      std::vector<FieldValues> fields = {});

}  // namespace dtm
