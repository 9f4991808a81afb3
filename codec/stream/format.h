// The bytes of a .dtm stream, defined once for the encoder, the decoder and
// meshinfo. spec/FORMAT.md is the normative description; its header tables
// are checked against the field lists below by tests/test_format_fields.cpp.
//
//   stream = header, [field table], layer(L), layer(L-1), ..., layer(0)
//   header = kHeaderSize bytes (below), ending with its own checksum
//   field table (5.0, with kFlagValues): codec/sections/value_fields.h
//   region table (9.0, with kFlagRegions): codec/sections/region_coder.h
//   face tag table (9.0, with kFlagFaces): the same layout
//   cell field table (10.0, with kFlagCellData): the field table's layout
//   layer  = layer header + candidate section (7.0: new points beside the
//            coarser level's circumcentres and edge midpoints)
//            + payload (the level's other new points)
//            + carving section (4.0: the level's carving corrections)
//            + region section (9.0, kFlagRegions: the kept cells' regions)
//            + face section (9.0, kFlagFaces: the surface faces' tags)
//            + value section (5.0: the new points' values)
//            + cell value section (10.0, kFlagCellData, level 0's layer
//              only: the values of level 0's kept cells)
//            + vertex order section (10.0, kFlagVertexOrder, level 0's
//              layer only: the input's numbering of level 0's vertices)
//            + exact cell section (11.0 to 13.0, kFlagExact, level 0's layer only:
//              the input's cells that are not Delaunay cells)
//            + edge node section (18.0, kFlagEdgeNodes, level 0's layer
//              only: the nodes on the edges of a second-order input's cells)
//            + edge value section (19.0, kFlagEdgeNodes and kFlagValues,
//              level 0's layer only: the fields' values at those nodes)
//            + node order section (21.0, kFlagVertexOrder and
//              kFlagEdgeNodes, level 0's layer only: the input's numbering
//              of the vertices and edge nodes together)
//            + node label section (22.0, kFlagNodeLabels, level 0's layer
//              only: the input's label of each node)
//   bricked layer (8.0, kFlagBricks) = layer header + brick index + chunks
//            (codec/bricks/bricks.h: each brick's new points and corrections)
#pragma once

#include <array>
#include <cstdint>
#include <limits>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "codec/sections/region_coder.h"
#include "codec/sections/value_fields.h"
#include "common/grid.h"
#include "common/status.h"
#include "mesh/carving.h"

namespace dtm {

inline constexpr std::array<uint8_t, 8> kMagic = {0x89, 'D', 'T', 'M', 0x0D, 0x0A, 0x1A, 0x0A};
// The encoder writes the oldest version that says all the stream holds: 7.0
// when it carries carving corrections (the codec preset, whose layers may
// send points beside candidates; 6.0's correction contexts), else 5.0 when
// it carries values, else 4.0; 8.0 when its layers are bricked (kFlagBricks);
// 9.0 when its cells carry regions (kFlagRegions); 10.0 when level 0's cells
// carry values (kFlagCellData); 11.0 when level 0 is the input's cells
// (kFlagExact) and its exact cells' apexes are ranked among all their
// candidates, 12.0 when among those that fit, 13.0 when its filled bits
// also have the Delaunay cell across as context, its apexes a second ring
// and its level 0's carving the cells' flips as context, 14.0 when its
// exact cell section starts with a flag per 3-2 flip of the kept cells
// (spec/FORMAT.md §3.10, §3.2: apex_ranks_of(), exact_carving_contexts());
// 15.0 when a bricked stream's cells carry regions (each chunk a region
// section, spec/FORMAT.md §3.5); 16.0 when a bricked stream's level 0
// carries cell data (each of its chunks a cell value section); 17.0 when a
// bricked stream's levels carry tagged faces (each chunk a face section);
// 18.0 when an exact level 0 carries its edges' nodes (kFlagEdgeNodes);
// 19.0 when those nodes carry the per-vertex fields' values too (flags
// edge nodes and values: an edge value section in level 0's layer), and
// are predicted from the surface's normals; 20.0 when that prediction sets
// the surface's creases apart (what meshenc --exact writes of a
// second-order mesh; 19.0 and 18.0 on request); 21.0 when a stream with
// edge nodes keeps the input's numbering (kFlagVertexOrder): a node order
// section puts its edge nodes among its vertices where the input numbered
// them (codec/sections/node_order_coder.h); 22.0 when it keeps the input's
// node labels too (kFlagNodeLabels, codec/sections/node_label_coder.h);
// 23.0 for every exact stream (meshenc --exact; --exact-v22 writes 14.0 to
// 22.0): its layer headers hold the section lengths its flags call for,
// and its exact cell section has 23.0's contexts and order of the apexes
// (codec/sections/exact_cell_coder.h); the decoder reads 2.x to 23.x.
inline constexpr uint8_t kVersionMajor = 23;
inline constexpr uint8_t kVersionMajorExactClosing = 23;
inline constexpr uint8_t kVersionMajorLayerSizesByFlags = 23;
inline constexpr uint8_t kVersionMajorNodeLabels = 22;
inline constexpr uint8_t kVersionMajorNodeOrder = 21;
inline constexpr uint8_t kVersionMajorCreaseEdgeNodes = 20;
inline constexpr uint8_t kVersionMajorPredictedEdgeNodes = 19;
inline constexpr uint8_t kVersionMajorEdgeNodes = 18;
inline constexpr uint8_t kVersionMajorBrickedFaces = 17;
inline constexpr uint8_t kVersionMajorBrickedCellData = 16;
inline constexpr uint8_t kVersionMajorBrickedRegions = 15;
inline constexpr uint8_t kVersionMajorExact = 14;
inline constexpr uint8_t kVersionMajorExactInContext = 13;
inline constexpr uint8_t kVersionMajorExactFitting = 12;
inline constexpr uint8_t kVersionMajorExactAllRanked = 11;
inline constexpr uint8_t kVersionMajorCellData = 10;
inline constexpr uint8_t kVersionMajorRegions = 9;
inline constexpr uint8_t kVersionMajorBricked = 8;
inline constexpr uint8_t kVersionMajorUnbricked = 7;
inline constexpr uint8_t kVersionMajorWithValues = 5;
inline constexpr uint8_t kVersionMajorWithoutValues = 4;
inline constexpr uint8_t kOldestVersionMajor = 2;  // the decoder also reads 2.x
inline constexpr uint8_t kVersionMinor = 0;
inline constexpr uint16_t kFlagCellHashes = 1;  // each layer carries its level's cell-set hash
// 4.0: layers carry carving corrections (codec/sections/carving_coder.h); without
// the flag every carving section is empty and alpha alone carves (the paper).
inline constexpr uint16_t kFlagCarvingCorrections = 2;
// 5.0: a field table follows the header and layers carry value sections.
inline constexpr uint16_t kFlagValues = 4;
// 8.0: every layer is bricked (codec/bricks/bricks.h): an index and one chunk per
// brick instead of the candidate, payload, carving and value sections.
inline constexpr uint16_t kFlagBricks = 8;
// Bricked layers' octree depth: at most 16 per axis, 2^48 bricks, far more
// than any layer has points (codec/bricks/bricks.h).
inline constexpr int kMaxBrickDepth = 16;
// 9.0: a region table follows the field table and layers carry region
// sections (codec/sections/region_coder.h); with kFlagBricks from 15.0,
// each chunk carrying its cells' (codec/bricks/bricks.h).
inline constexpr uint16_t kFlagRegions = 16;
// 9.0: a face tag table follows (the region table) and layers carry face
// sections (codec/sections/face_coder.h); with kFlagBricks from 17.0, each
// chunk carrying its cells' faces' (codec/bricks/bricks.h).
inline constexpr uint16_t kFlagFaces = 32;
// 10.0: a cell field table follows (the face tag table) and level 0's layer
// carries a cell value section: per-cell arrays of the finest level
// (codec/sections/cell_value_coder.h); with kFlagBricks from 16.0, each of
// level 0's chunks carrying its cells' (codec/bricks/bricks.h).
inline constexpr uint16_t kFlagCellData = 64;
// 10.0: level 0's layer carries a vertex order section: level 0's vertices
// in the input's numbering (codec/sections/vertex_order_coder.h); not with
// kFlagBricks.
inline constexpr uint16_t kFlagVertexOrder = 128;
// 11.0: level 0's cells are the input's (codec/sections/exact_cell_coder.h):
// its carving section keeps the Delaunay cells that are input cells and its
// layer carries an exact cell section with the others; not with kFlagBricks.
inline constexpr uint16_t kFlagExact = 256;
// 18.0: level 0's layer carries an edge node section: the node on each
// edge of the input's second-order cells (codec/sections/edge_node_coder.h);
// only with kFlagExact, whose level 0's edges are the input's. From 21.0,
// with kFlagVertexOrder too, a node order section after it puts the nodes
// among the vertices (codec/sections/node_order_coder.h).
inline constexpr uint16_t kFlagEdgeNodes = 512;
// 22.0: level 0's layer carries a node label section: the input's label of
// each node in the input's numbering (codec/sections/node_label_coder.h);
// only with kFlagVertexOrder.
inline constexpr uint16_t kFlagNodeLabels = 1024;
inline constexpr uint16_t kKnownFlags = kFlagCellHashes | kFlagCarvingCorrections | kFlagValues |
                                        kFlagBricks | kFlagRegions | kFlagFaces | kFlagCellData |
                                        kFlagVertexOrder | kFlagExact | kFlagEdgeNodes | kFlagNodeLabels;

struct StreamHeader {
  uint8_t version_major = kVersionMajor;
  uint8_t version_minor = kVersionMinor;
  Grid grid;
  AlphaKind alpha_policy = AlphaKind::kPaper;
  uint16_t flags = 0;
  uint16_t level_count = 0;
  uint32_t vertex_count = 0;  // of the finest level (level 0)
  uint32_t checksum = 0;      // low 32 bits of XXH3-64 of the bytes before it
};

struct LayerHeader {
  // Not fields: the stream's major version, whether its layers are bricked
  // (kFlagBricks), and (23.0) its header's flags, which say which fields
  // follow.
  uint8_t format_major = kVersionMajor;
  bool bricked = false;
  uint16_t stream_flags = 0;
  uint16_t level = 0;
  uint32_t new_vertices = 0;    // points in this layer's payload
  uint32_t level_vertices = 0;  // |V_level| = the coarser level's count + new_vertices
  double alpha = 0;             // grid units
  uint32_t payload_bytes = 0;
  uint32_t carving_bytes = 0;  // 4.0 and later: the carving section, after the payload
  uint32_t value_bytes = 0;    // 5.0 and later: the value section, after the carving section
  // 7.0 and later: which candidates the layer's points are sent beside
  // (codec/sections/candidate_coder.h; 0 = none, always at the base level) and the
  // candidate section's size, before the payload.
  uint8_t candidate_kinds = 0;
  uint32_t candidate_bytes = 0;
  // 9.0 and later: the region section, after the carving section, and the
  // face section after it.
  uint32_t region_bytes = 0;
  uint32_t face_bytes = 0;
  // 10.0 and later: the cell value section, after the value section (0 but
  // in level 0's layer).
  uint32_t cell_value_bytes = 0;
  // 10.0 and later: the vertex order section, after it (0 but in level 0's
  // layer).
  uint32_t order_bytes = 0;
  // 11.0 and later: the exact cell section, after it (0 but in level 0's
  // layer of a stream with kFlagExact).
  uint32_t exact_bytes = 0;
  // 18.0 and later: the edge node section, after it (0 but in level 0's
  // layer of a stream with kFlagEdgeNodes).
  uint32_t edge_node_bytes = 0;
  // 19.0 and later: the edge value section, after it (0 but in level 0's
  // layer of a stream with kFlagEdgeNodes and kFlagValues).
  uint32_t edge_value_bytes = 0;
  // 21.0 and later: the node order section, after it (0 but in level 0's
  // layer of a stream with kFlagVertexOrder and kFlagEdgeNodes).
  uint32_t node_order_bytes = 0;
  // 22.0 and later: the node label section, after it (0 but in level 0's
  // layer of a stream with kFlagNodeLabels).
  uint32_t node_label_bytes = 0;
  // Bricked layers (8.0): the largest circumradius of a kept cell (at least
  // alpha; larger cells carry no correction bit), the bricks' octree depth,
  // and the sizes of the index and of the chunks after it.
  double kept_radius = 0;
  uint8_t brick_depth = 0;
  uint32_t index_bytes = 0;
  uint64_t chunk_bytes = 0;
  uint64_t cell_hash = 0;  // meaningful with kFlagCellHashes, else 0
  // XXH3-64 of the header bytes before it and the body (of a bricked layer:
  // and its index; each chunk has its own checksum in the index).
  uint64_t checksum = 0;

  uint64_t body_bytes() const {
    if (bricked) return uint64_t{index_bytes} + chunk_bytes;
    return uint64_t{candidate_bytes} + payload_bytes + carving_bytes + region_bytes + face_bytes +
           value_bytes + cell_value_bytes + order_bytes + exact_bytes + edge_node_bytes + edge_value_bytes +
           node_order_bytes + node_label_bytes;
  }
};

// The fields of each header in stream order, described once: writing,
// parsing, the sizes and the checksum's place derive from these lists. A
// field visitor V has
//   v.magic(name)                        the 8 magic bytes
//   v.template field<Wire>(name, value)  one little-endian Wire (uint8_t ..
//                                        uint64_t, double); value may be an
//                                        int, an enum or a std::array of them
//   v.template checksum<Wire>(name, value)  the header's checksum, last
// A field added in a later version is visited only for streams of that
// version or later.
template <class V>
constexpr void visit_fields(StreamHeader& h, V& v) {
  v.magic("magic");
  v.template field<uint8_t>("version_major", h.version_major);
  v.template field<uint8_t>("version_minor", h.version_minor);
  v.template field<uint8_t>("qbits", h.grid.qbits);
  v.template field<uint8_t>("alpha_policy", h.alpha_policy);
  v.template field<uint16_t>("flags", h.flags);
  v.template field<uint16_t>("level_count", h.level_count);
  v.template field<uint32_t>("vertex_count", h.vertex_count);
  v.template field<double>("origin", h.grid.origin);
  v.template field<double>("step", h.grid.step);
  v.template checksum<uint32_t>("header_checksum", h.checksum);
}

template <class V>
constexpr void visit_fields(LayerHeader& h, V& v) {
  v.template field<uint16_t>("level", h.level);
  v.template field<uint32_t>("new_vertices", h.new_vertices);
  v.template field<uint32_t>("level_vertices", h.level_vertices);
  v.template field<double>("alpha", h.alpha);
  if (h.bricked) {
    v.template field<double>("kept_radius", h.kept_radius);
    v.template field<uint8_t>("brick_depth", h.brick_depth);
    v.template field<uint32_t>("index_bytes", h.index_bytes);
    v.template field<uint64_t>("chunk_bytes", h.chunk_bytes);
    v.template field<uint64_t>("cell_hash", h.cell_hash);
    v.template checksum<uint64_t>("layer_checksum", h.checksum);
    return;
  }
  v.template field<uint32_t>("payload_bytes", h.payload_bytes);
  // 23.0: a section's size is there only where the stream's flags call for
  // the section, and a section of level 0 alone only in level 0's layer
  // (before, every layer held every size its version knew, most of them
  // 0: 20-36 bytes a layer of an exact stream).
  const bool by_flags = h.format_major >= kVersionMajorLayerSizesByFlags;
  const auto has = [&](uint16_t flags) { return !by_flags || (h.stream_flags & flags) == flags; };
  const auto has_at_0 = [&](uint16_t flags) { return !by_flags || (has(flags) && h.level == 0); };
  if (h.format_major >= 4) v.template field<uint32_t>("carving_bytes", h.carving_bytes);
  if (h.format_major >= 5 && has(kFlagValues)) v.template field<uint32_t>("value_bytes", h.value_bytes);
  if (h.format_major >= 7) {
    v.template field<uint8_t>("candidate_kinds", h.candidate_kinds);
    v.template field<uint32_t>("candidate_bytes", h.candidate_bytes);
  }
  if (h.format_major >= 9) {
    if (has(kFlagRegions)) v.template field<uint32_t>("region_bytes", h.region_bytes);
    if (has(kFlagFaces)) v.template field<uint32_t>("face_bytes", h.face_bytes);
  }
  if (h.format_major >= 10) {
    if (has_at_0(kFlagCellData)) v.template field<uint32_t>("cell_value_bytes", h.cell_value_bytes);
    if (has_at_0(kFlagVertexOrder)) v.template field<uint32_t>("order_bytes", h.order_bytes);
  }
  if (h.format_major >= 11 && has_at_0(kFlagExact)) v.template field<uint32_t>("exact_bytes", h.exact_bytes);
  if (h.format_major >= 18 && has_at_0(kFlagEdgeNodes))
    v.template field<uint32_t>("edge_node_bytes", h.edge_node_bytes);
  if (h.format_major >= 19 && has_at_0(kFlagEdgeNodes | kFlagValues))
    v.template field<uint32_t>("edge_value_bytes", h.edge_value_bytes);
  if (h.format_major >= 21 && has_at_0(kFlagEdgeNodes | kFlagVertexOrder))
    v.template field<uint32_t>("node_order_bytes", h.node_order_bytes);
  if (h.format_major >= 22 && has_at_0(kFlagNodeLabels))
    v.template field<uint32_t>("node_label_bytes", h.node_label_bytes);
  v.template field<uint64_t>("cell_hash", h.cell_hash);
  v.template checksum<uint64_t>("layer_checksum", h.checksum);
}

// Counts the bytes of a field list (compile time).
struct FieldSizer {
  size_t size = 0;
  size_t checksum_offset = 0;
  constexpr void magic(const char*) { size += kMagic.size(); }
  template <class Wire, class T>
  constexpr void field(const char*, const T&) {
    size += sizeof(Wire);
  }
  template <class Wire, class T, size_t N>
  constexpr void field(const char*, const std::array<T, N>&) {
    size += N * sizeof(Wire);
  }
  template <class Wire, class T>
  constexpr void checksum(const char*, const T&) {
    checksum_offset = size;
    size += sizeof(Wire);
  }
};

template <class Header>
constexpr FieldSizer sized(uint8_t format_major = kVersionMajor, bool bricked = false,
                           uint16_t stream_flags = 0, uint16_t level = 0) {
  Header h{};
  if constexpr (requires { h.format_major; })
    h.format_major = format_major, h.bricked = bricked, h.stream_flags = stream_flags, h.level = level;
  FieldSizer s;
  visit_fields(h, s);
  return s;
}

inline constexpr size_t kHeaderSize = sized<StreamHeader>().size;
// A layer header's size in a stream of this major version (23.0: and these
// flags, at this level).
constexpr size_t layer_header_size(uint8_t format_major, bool bricked = false, uint16_t stream_flags = 0,
                                   uint16_t level = 0) {
  return sized<LayerHeader>(format_major, bricked, stream_flags, level).size;
}
inline size_t layer_header_size(const LayerHeader& h) {
  return layer_header_size(h.format_major, h.bricked, h.stream_flags, h.level);
}
// A layer header of the streams meshenc writes most (7.0), of bricked ones
// (8.0) and of those with regions (9.0).
inline constexpr size_t kLayerHeaderSize = layer_header_size(kVersionMajorUnbricked);
inline constexpr size_t kBrickedLayerHeaderSize = layer_header_size(kVersionMajorBricked, true);
inline constexpr size_t kRegionLayerHeaderSize = layer_header_size(kVersionMajorRegions);
static_assert(kHeaderSize == 56 && layer_header_size(3) == 38 && layer_header_size(4) == 42 &&
                  layer_header_size(6) == 46 && kLayerHeaderSize == 51 && kBrickedLayerHeaderSize == 55 &&
                  kRegionLayerHeaderSize == 59 && layer_header_size(9, true) == 55 &&
                  layer_header_size(10) == 67 && layer_header_size(10, true) == 55 &&
                  layer_header_size(11) == 71 && layer_header_size(11, true) == 55 &&
                  layer_header_size(17) == 71 && layer_header_size(18) == 75 &&
                  layer_header_size(18, true) == 55 && layer_header_size(19) == 79 &&
                  layer_header_size(19, true) == 55 && layer_header_size(21) == 83 &&
                  layer_header_size(21, true) == 55 && layer_header_size(22) == 87 &&
                  layer_header_size(22, true) == 55 && layer_header_size(23) == 47 &&
                  layer_header_size(23, false, kFlagValues | kFlagExact, 0) == 55 &&
                  layer_header_size(23, false, kFlagValues | kFlagExact, 1) == 51 &&
                  layer_header_size(23, true) == 55,
              "the format's header sizes changed");

// Parses and validates the header at the start of `bytes`. kNeedMoreInput if
// fewer than kHeaderSize bytes are given.
Status parse_header(std::span<const uint8_t> bytes, StreamHeader& h);

// A whole, checksummed layer, as LayerWalk returns it.
struct Layer {
  LayerHeader header;
  std::span<const uint8_t> candidates;
  std::span<const uint8_t> payload;
  std::span<const uint8_t> carving;
  std::span<const uint8_t> regions;
  std::span<const uint8_t> faces;
  std::span<const uint8_t> values;
  std::span<const uint8_t> cell_values;
  std::span<const uint8_t> order;
  std::span<const uint8_t> exact;        // 11.0: the exact cell section
  std::span<const uint8_t> edge_nodes;   // 18.0: the edge node section
  std::span<const uint8_t> edge_values;  // 19.0: the edge value section
  std::span<const uint8_t> node_order;   // 21.0: the node order section
  std::span<const uint8_t> node_labels;  // 22.0: the node label section
  // A bricked layer's index (checksummed with the header) and chunks (each
  // checked against its checksum in the index when it is decoded).
  std::span<const uint8_t> index;
  std::span<const uint8_t> chunks;
  uint64_t offset = 0;  // of the layer header in the stream
  uint64_t size() const { return layer_header_size(header) + header.body_bytes(); }
};

// Reads the layers of a stream in order, from bytes that may arrive in
// pieces: the one place where a layer header is checked against the stream
// header and the layer before it, and its checksum verified. Errors name the
// level and the byte offset of the layer.
class LayerWalk {
 public:
  // `max_level_vertices`: a level with more vertices is refused
  // (kLimitExceeded) before its payload is read. `table_bytes`: the field
  // table's size, between the header and the first layer.
  explicit LayerWalk(const StreamHeader& header,
                     uint64_t max_level_vertices = std::numeric_limits<uint64_t>::max(),
                     uint64_t table_bytes = 0);

  // `bytes` are the stream's bytes from offset() on. ok: `layer` is the next
  // layer, whole and checksummed, and the walk has moved past it.
  // kNeedMoreInput: its bytes are not all here; `header_seen` (if given)
  // says whether its header was, and then `layer.header` holds it. After the
  // last layer, any byte is trailing data (kCorrupt), none kNeedMoreInput.
  Status next(std::span<const uint8_t> bytes, Layer& layer, bool* header_seen = nullptr);
  // A bricked layer from its header and index alone (a region reader, which
  // reads the chunks it needs elsewhere): `bytes` from offset() on hold at
  // least the header and index; the walk moves past the whole layer.
  // layer.chunks is left empty.
  Status next_index(std::span<const uint8_t> bytes, Layer& layer, bool* header_seen = nullptr);

  bool done() const { return next_level_ < 0; }
  int next_level() const { return next_level_; }
  uint64_t offset() const { return offset_; }

  // Where next() said kNeedMoreInput but the stream is known to end with
  // `bytes` (from offset() on: a file read whole, a decoder told the input
  // ended): kCorrupt, naming the layer, if the layer's checksum holds for it
  // ending inside the stream with one section length of its header smaller,
  // by what it overshoots (the stream's last layer) or by one of its bits
  // (any layer). A bit flipped in a length would otherwise read as a stream
  // cut inside the layer, and give the coarser levels without an error. Ok
  // otherwise (a stream cut short). A length of a layer before the last
  // damaged in more than one bit still reads as a cut: that layer's true end
  // is not known.
  Status overshoot_is_damage(std::span<const uint8_t> bytes) const {
    return overshoot_is_damage(bytes, bytes.size());
  }
  // The same where `bytes` are only the first of the `to_end` bytes to the
  // stream's end: of a bricked layer, whose checksum covers its header and
  // index alone, the header and what its index may be (a region reader
  // reads no chunk for it); of any other layer, all of them (else Ok).
  Status overshoot_is_damage(std::span<const uint8_t> bytes, uint64_t to_end) const;

 private:
  Status check(const LayerHeader& h) const;
  Status check_sections(const LayerHeader& h) const;
  Status walk(std::span<const uint8_t> bytes, Layer& layer, bool* header_seen, bool with_chunks);

  StreamHeader header_;
  uint64_t max_level_vertices_;
  int next_level_;
  uint32_t previous_vertices_ = 0;
  uint64_t offset_;
};

// What a stream holds, read from its headers without decoding any point
// (meshinfo). Checksums are verified.
struct LayerSummary {
  // A bricked layer's (8.0) header holds, besides its own fields, its
  // chunks' payload and carving bytes added up in payload_bytes and
  // carving_bytes (once its index is whole), and `chunks` their count.
  LayerHeader header;
  uint64_t chunks = 0;
  uint64_t offset = 0;  // of the layer header in the stream
  bool complete = false;
  std::vector<uint64_t>
      field_bytes;  // complete layers of a 5.0 stream: each field's share of the value section
  std::vector<uint64_t> cell_field_bytes;  // 10.0, level 0: each cell field's share of its section
  std::vector<uint64_t> edge_field_bytes;  // 19.0, level 0: each field's share of the edge value section
  uint64_t size() const { return layer_header_size(header) + header.body_bytes(); }
};
struct StreamSummary {
  StreamHeader header;
  std::vector<FieldDescription> fields;  // 5.0 with kFlagValues: the field table
  uint64_t field_table_bytes = 0;
  std::vector<RegionLabel> regions;  // 9.0 with kFlagRegions: the region table
  uint64_t region_table_bytes = 0;
  std::vector<RegionLabel> face_tags;  // 9.0 with kFlagFaces: the face tag table
  uint64_t face_table_bytes = 0;
  std::vector<FieldDescription> cell_fields;  // 10.0 with kFlagCellData: the cell field table
  uint64_t cell_field_table_bytes = 0;
  uint64_t tables_bytes() const {
    return field_table_bytes + region_table_bytes + face_table_bytes + cell_field_table_bytes;
  }
  std::vector<LayerSummary> layers;  // coarsest first; the last may be incomplete
  uint64_t bytes = 0;                // bytes given
  Status status;                     // ok, or why the scan stopped early
};
StreamSummary scan_stream(std::span<const uint8_t> bytes);

// A level's canonical cell-set hash: each cell as its four grid points in
// lexicographic order (12 int32, little-endian), cells in lexicographic
// order, XXH3-64 of the concatenation.
uint64_t cell_set_hash(std::span<const GridPoint> points, std::span<const std::array<uint32_t, 4>> cells);
// A bricked stream's (8.0, flag bricks): the wrapping 64-bit sum over the
// cells of XXH3-64 of each cell's row as above, which parts of the level
// made apart add up to (spec/FORMAT.md §3.5).
uint64_t cell_hash_sum(std::span<const GridPoint> points, std::span<const std::array<uint32_t, 4>> cells);
// The hash a stream with these header flags states for a level.
uint64_t level_cell_hash(uint32_t flags, std::span<const GridPoint> points,
                         std::span<const std::array<uint32_t, 4>> cells);

}  // namespace dtm
