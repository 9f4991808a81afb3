#include "codec/stream/format.h"

#include <algorithm>
#include <cmath>
#include <type_traits>

#include "codec/bricks/bricks.h"
#include "codec/sections/candidate_coder.h"
#include "codec/sections/face_coder.h"
#include "codec/stream/header_fields.h"
#include "codec/stream/layer_coder.h"
#include "common/byte_io.h"
#include "common/checksum.h"
#include "common/parallel_for.h"

namespace dtm {
namespace {

using header_fields::FieldWriter;
using header_fields::read_fields;

constexpr size_t kHeaderChecksumOffset = sized<StreamHeader>().checksum_offset;
// (A layer header's checksum is its last field.)
constexpr size_t layer_checksum_offset(size_t header_size) { return header_size - sizeof(uint64_t); }

}  // namespace

Status parse_header(std::span<const uint8_t> bytes, StreamHeader& h) {
  const size_t magic_seen = std::min(bytes.size(), kMagic.size());
  if (!std::equal(bytes.begin(), bytes.begin() + magic_seen, kMagic.begin()))
    return {StatusCode::kNotDtm, "not a .dtm stream (wrong magic)"};
  if (bytes.size() < kHeaderSize) return {StatusCode::kNeedMoreInput, "header incomplete"};
  h = read_fields<StreamHeader>(bytes.first(kHeaderSize));
  // The version first: a future version may change everything after it.
  if (h.version_major < kOldestVersionMajor || h.version_major > kVersionMajor)
    return {StatusCode::kUnsupported,
            "format version " + std::to_string(h.version_major) + "." + std::to_string(h.version_minor) +
                " is not supported (this decoder reads " + std::to_string(kOldestVersionMajor) + ".x to " +
                std::to_string(kVersionMajor) + ".x)"};
  if (h.checksum != static_cast<uint32_t>(xxh3_64(bytes.first(kHeaderChecksumOffset))))
    return corrupt("header checksum mismatch");
  if (h.grid.qbits < kMinQBits || h.grid.qbits > kMaxQBits) return corrupt("qbits out of range");
  if (static_cast<uint8_t>(h.alpha_policy) > 2) return corrupt("unknown alpha policy");
  if (h.flags & ~kKnownFlags) return {StatusCode::kUnsupported, "unknown header flags"};
  if ((h.flags & kFlagValues) && h.version_major < 5) return corrupt("values flagged in a stream before 5.0");
  if ((h.flags & kFlagBricks) && h.version_major < 8) return corrupt("bricks flagged in a stream before 8.0");
  if ((h.flags & kFlagRegions) && h.version_major < 9)
    return corrupt("regions flagged in a stream before 9.0");
  if ((h.flags & kFlagRegions) && (h.flags & kFlagBricks) && h.version_major < 15)
    return corrupt("regions flagged in a bricked stream before 15.0");
  if ((h.flags & kFlagRegions) && !(h.flags & kFlagCarvingCorrections))
    return corrupt("regions flagged without carving corrections");
  if ((h.flags & kFlagFaces) && h.version_major < 9) return corrupt("faces flagged in a stream before 9.0");
  if ((h.flags & kFlagFaces) && (h.flags & kFlagBricks) && h.version_major < 17)
    return corrupt("faces flagged in a bricked stream before 17.0");
  if ((h.flags & kFlagFaces) && !(h.flags & kFlagCarvingCorrections))
    return corrupt("faces flagged without carving corrections");
  if ((h.flags & kFlagCellData) && h.version_major < 10)
    return corrupt("cell data flagged in a stream before 10.0");
  if ((h.flags & kFlagCellData) && (h.flags & kFlagBricks) && h.version_major < 16)
    return corrupt("cell data flagged in a bricked stream before 16.0");
  if ((h.flags & kFlagCellData) && !(h.flags & kFlagCarvingCorrections))
    return corrupt("cell data flagged without carving corrections");
  if ((h.flags & kFlagVertexOrder) && h.version_major < 10)
    return corrupt("a vertex order flagged in a stream before 10.0");
  if ((h.flags & kFlagVertexOrder) && (h.flags & kFlagBricks))
    return corrupt("a vertex order flagged in a bricked stream");
  if ((h.flags & kFlagVertexOrder) && !(h.flags & kFlagCarvingCorrections))
    return corrupt("a vertex order flagged without carving corrections");
  if ((h.flags & kFlagExact) && h.version_major < 11)
    return corrupt("exact cells flagged in a stream before 11.0");
  if ((h.flags & kFlagExact) && (h.flags & kFlagBricks))
    return corrupt("exact cells flagged in a bricked stream");
  if ((h.flags & kFlagExact) && !(h.flags & kFlagCarvingCorrections))
    return corrupt("exact cells flagged without carving corrections");
  if ((h.flags & kFlagEdgeNodes) && h.version_major < 18)
    return corrupt("edge nodes flagged in a stream before 18.0");
  if ((h.flags & kFlagEdgeNodes) && !(h.flags & kFlagExact))
    return corrupt("edge nodes flagged without exact cells");
  if ((h.flags & kFlagNodeLabels) && h.version_major < 22)
    return corrupt("node labels flagged in a stream before 22.0");
  if ((h.flags & kFlagNodeLabels) && !(h.flags & kFlagVertexOrder))
    return corrupt("node labels flagged without a vertex order");
  if (h.level_count == 0) return corrupt("zero levels");
  if (h.vertex_count < 4) return corrupt("fewer than 4 vertices");
  for (double o : h.grid.origin)
    if (!std::isfinite(o)) return corrupt("origin is not finite");
  if (!std::isfinite(h.grid.step) || !(h.grid.step > 0)) return corrupt("step is not positive");
  return Status::Ok();
}

LayerWalk::LayerWalk(const StreamHeader& header, uint64_t max_level_vertices, uint64_t table_bytes)
    : header_(header),
      max_level_vertices_(max_level_vertices),
      next_level_(header.level_count - 1),
      offset_(kHeaderSize + table_bytes) {}

Status LayerWalk::check(const LayerHeader& h) const {
  if (h.level != next_level_)
    return corrupt("layer for level " + std::to_string(h.level) + " where level " +
                   std::to_string(next_level_) + " was due");
  if (h.new_vertices == 0) return corrupt("a layer without points");
  if (static_cast<uint64_t>(previous_vertices_) + h.new_vertices != h.level_vertices)
    return corrupt("level vertex count does not add up");
  if (h.level_vertices > header_.vertex_count)
    return corrupt("level has more vertices than the finest level");
  if (h.level == 0 && h.level_vertices != header_.vertex_count)
    return corrupt("finest level's vertex count differs from the header's");
  if (std::isnan(h.alpha) || !(h.alpha > 0)) return corrupt("alpha is not positive");
  if (h.bricked) {
    if (!(h.kept_radius >= h.alpha)) return corrupt("kept radius below alpha");
    if (!(header_.flags & kFlagCarvingCorrections) && h.kept_radius != h.alpha)
      return corrupt("kept radius other than alpha without carving corrections");
    if (h.brick_depth > kMaxBrickDepth || h.brick_depth > header_.grid.qbits)
      return corrupt("brick depth out of range");
    if (previous_vertices_ == 0 && h.brick_depth != 0) return corrupt("a base layer of more than one brick");
    if (h.chunk_bytes < min_payload_bytes(h.new_vertices))
      return corrupt("chunks too short for their points");
  } else {
    DTM_RETURN_IF_ERROR(check_sections(h));
  }
  if (!(header_.flags & kFlagCellHashes) && h.cell_hash != 0)
    return corrupt("cell hash present without its flag");
  if (h.level_vertices > max_level_vertices_)
    return {StatusCode::kLimitExceeded, std::to_string(h.level_vertices) + " vertices exceed the limit of " +
                                            std::to_string(max_level_vertices_)};
  return Status::Ok();
}

// The sections of a layer that is not bricked.
Status LayerWalk::check_sections(const LayerHeader& h) const {
  // (With candidates, the payload holds only the points they do not send.)
  if (h.candidate_kinds == 0 && h.payload_bytes < min_payload_bytes(h.new_vertices))
    return corrupt("payload too short for its point count");
  if (!(header_.flags & kFlagCarvingCorrections) && h.carving_bytes != 0)
    return corrupt("carving corrections present without their flag");
  if (!(header_.flags & kFlagValues) && h.value_bytes != 0)
    return corrupt("a value section present without its flag");
  if (!(header_.flags & kFlagRegions) && h.region_bytes != 0)
    return corrupt("a region section present without its flag");
  if (!(header_.flags & kFlagFaces) && h.face_bytes != 0)
    return corrupt("a face section present without its flag");
  if (!(header_.flags & kFlagCellData) && h.cell_value_bytes != 0)
    return corrupt("a cell value section present without its flag");
  if (h.level != 0 && h.cell_value_bytes != 0)
    return corrupt("a cell value section in a layer but level 0's");
  if (!(header_.flags & kFlagVertexOrder) && h.order_bytes != 0)
    return corrupt("a vertex order section present without its flag");
  if (h.level != 0 && h.order_bytes != 0) return corrupt("a vertex order section in a layer but level 0's");
  if (h.level == 0 && (header_.flags & kFlagVertexOrder) && h.order_bytes == 0)
    return corrupt("level 0's layer without its vertex order section");
  if (!(header_.flags & kFlagExact) && h.exact_bytes != 0)
    return corrupt("an exact cell section present without its flag");
  if (h.level != 0 && h.exact_bytes != 0) return corrupt("an exact cell section in a layer but level 0's");
  if (h.level == 0 && (header_.flags & kFlagExact) && h.exact_bytes == 0)
    return corrupt("level 0's layer without its exact cell section");
  if (!(header_.flags & kFlagEdgeNodes) && h.edge_node_bytes != 0)
    return corrupt("an edge node section present without its flag");
  if (h.level != 0 && h.edge_node_bytes != 0) return corrupt("an edge node section in a layer but level 0's");
  if (h.level == 0 && (header_.flags & kFlagEdgeNodes) && h.edge_node_bytes == 0)
    return corrupt("level 0's layer without its edge node section");
  // (19.0: the edge nodes' values come with both flags.)
  const bool edge_values = (header_.flags & kFlagEdgeNodes) && (header_.flags & kFlagValues);
  if (!edge_values && h.edge_value_bytes != 0)
    return corrupt("an edge value section present without edge nodes and values");
  if (h.level != 0 && h.edge_value_bytes != 0)
    return corrupt("an edge value section in a layer but level 0's");
  if (h.level == 0 && edge_values && h.format_major >= kVersionMajorPredictedEdgeNodes &&
      h.edge_value_bytes == 0)
    return corrupt("level 0's layer without its edge value section");
  // (21.0: the edge nodes' place among the vertices comes with both flags.)
  const bool node_order = (header_.flags & kFlagEdgeNodes) && (header_.flags & kFlagVertexOrder);
  if (!node_order && h.node_order_bytes != 0)
    return corrupt("a node order section present without edge nodes and a vertex order");
  if (h.level != 0 && h.node_order_bytes != 0)
    return corrupt("a node order section in a layer but level 0's");
  // (23.0: a stream given no numbering has none, its nodes after the
  // vertices as in 20.0.)
  if (h.level == 0 && node_order && h.format_major >= kVersionMajorNodeOrder &&
      (h.format_major < kVersionMajorLayerSizesByFlags || (header_.flags & kFlagNodeLabels)) &&
      h.node_order_bytes == 0)
    return corrupt("level 0's layer without its node order section");
  if (!(header_.flags & kFlagNodeLabels) && h.node_label_bytes != 0)
    return corrupt("a node label section present without its flag");
  if (h.level != 0 && h.node_label_bytes != 0)
    return corrupt("a node label section in a layer but level 0's");
  if (h.level == 0 && (header_.flags & kFlagNodeLabels) && h.node_label_bytes == 0)
    return corrupt("level 0's layer without its node label section");
  if (h.candidate_kinds & ~kKnownCandidateKinds) return corrupt("unknown candidate kinds");
  if (h.candidate_kinds != 0 && previous_vertices_ == 0)
    return corrupt("candidates at the base level, which has no coarser level");
  if (h.candidate_kinds != 0 && header_.grid.qbits > kMaxCandidateQBits)
    return corrupt("candidates on a grid of more than 19 bits");
  if (h.candidate_kinds == 0 && h.candidate_bytes != 0)
    return corrupt("a candidate section without candidate kinds");
  return Status::Ok();
}

Status LayerWalk::overshoot_is_damage(std::span<const uint8_t> bytes, uint64_t to_end) const {
  if (done() || to_end < bytes.size() || (!(header_.flags & kFlagBricks) && bytes.size() != to_end))
    return Status::Ok();
  const uint8_t major = header_.version_major;
  const bool bricked = header_.flags & kFlagBricks;
  const size_t header_size =
      layer_header_size(major, bricked, header_.flags, static_cast<uint16_t>(std::max(next_level_, 0)));
  if (bytes.size() < header_size) return Status::Ok();
  const LayerHeader h = read_fields<LayerHeader>(bytes.first(header_size), major, bricked, header_.flags);
  const uint64_t present = to_end - header_size;
  if (present >= h.body_bytes()) return Status::Ok();
  const uint64_t over = h.body_bytes() - present;
  const std::span<const uint8_t> rest = bytes.subspan(header_size);
  // The header as the encoder wrote it, were `length` `value`: does its
  // checksum hold for what follows, the layer ending inside the stream?
  const auto holds_with = [&](auto LayerHeader::*length, uint64_t value) {
    LayerHeader fixed = h;
    fixed.*length = static_cast<std::remove_reference_t<decltype(fixed.*length)>>(value);
    if (fixed.*length != value || fixed.body_bytes() > present) return false;
    FieldWriter writer;
    // (A bricked layer's checksum covers its index; the rest its body.)
    const uint64_t covered = bricked ? fixed.index_bytes : fixed.body_bytes();
    if (covered > rest.size()) return false;
    writer.trailer = rest.first(covered);
    visit_fields(fixed, writer);
    return fixed.checksum == h.checksum;
  };
  // Smaller by the overshoot (the last layer, whatever the damage), or by
  // one bit set (any layer: one before the last runs past the stream's end
  // by the layers after it too).
  const auto holds = [&](auto LayerHeader::*length) {
    const uint64_t value = h.*length;
    if (value >= over && holds_with(length, value - over)) return true;
    for (int bit = 0; bit < 64; ++bit) {
      const uint64_t one = uint64_t{1} << bit;
      if ((value & one) && one != over && holds_with(length, value & ~one)) return true;
    }
    return false;
  };
  bool damaged = false;
  if (bricked) {
    damaged = holds(&LayerHeader::chunk_bytes) || holds(&LayerHeader::index_bytes);
  } else {
    for (auto length :
         {&LayerHeader::candidate_bytes, &LayerHeader::payload_bytes, &LayerHeader::carving_bytes,
          &LayerHeader::region_bytes, &LayerHeader::face_bytes, &LayerHeader::value_bytes,
          &LayerHeader::cell_value_bytes, &LayerHeader::order_bytes, &LayerHeader::exact_bytes,
          &LayerHeader::edge_node_bytes, &LayerHeader::edge_value_bytes, &LayerHeader::node_order_bytes,
          &LayerHeader::node_label_bytes})
      damaged = damaged || holds(length);
  }
  if (!damaged) return Status::Ok();
  return corrupt(
      "level " + std::to_string(next_level_) + " at byte " + std::to_string(offset_) +
      ": a section length in its layer header is damaged: it runs " + std::to_string(over) +
      " bytes past the stream's end, where the layer's checksum holds for it ending inside the stream");
}

Status LayerWalk::next(std::span<const uint8_t> bytes, Layer& layer, bool* header_seen) {
  return walk(bytes, layer, header_seen, true);
}

Status LayerWalk::next_index(std::span<const uint8_t> bytes, Layer& layer, bool* header_seen) {
  if (!(header_.flags & kFlagBricks))
    return {StatusCode::kInvalidInput, "next_index: the layers are not bricked"};
  return walk(bytes, layer, header_seen, false);
}

Status LayerWalk::walk(std::span<const uint8_t> bytes, Layer& layer, bool* header_seen, bool with_chunks) {
  if (header_seen) *header_seen = false;
  if (done()) {
    if (!bytes.empty())
      // (The bytes after it may arrive in pieces: where they start is
      // known, not how many follow.)
      return corrupt("trailing data after the last layer, which ends at byte " + std::to_string(offset_));
    return {StatusCode::kNeedMoreInput, "complete"};
  }
  const uint8_t major = header_.version_major;
  const bool bricked = header_.flags & kFlagBricks;
  // (23.0: the header's size depends on the stream's flags and the level;
  // a layer whose level is not this one is refused below.)
  const size_t header_size =
      layer_header_size(major, bricked, header_.flags, static_cast<uint16_t>(std::max(next_level_, 0)));
  if (bytes.size() < header_size) return {StatusCode::kNeedMoreInput, "layer header incomplete"};
  const std::string where = "level " + std::to_string(next_level_) + " at byte " + std::to_string(offset_);
  layer = Layer{};
  layer.header = read_fields<LayerHeader>(bytes.first(header_size), major, bricked, header_.flags);
  layer.offset = offset_;
  DTM_RETURN_IF_ERROR(check(layer.header).with_context(where));
  if (header_seen) *header_seen = true;
  if (bricked) {
    const LayerHeader& lh = layer.header;
    const uint64_t needed = with_chunks ? lh.body_bytes() : lh.index_bytes;
    if (bytes.size() - header_size < needed) return {StatusCode::kNeedMoreInput, "layer incomplete"};
    layer.index = bytes.subspan(header_size, lh.index_bytes);
    if (with_chunks) layer.chunks = bytes.subspan(header_size + lh.index_bytes, lh.chunk_bytes);
    if (xxh3_64(bytes.first(layer_checksum_offset(header_size)), layer.index) != lh.checksum)
      return corrupt(where + ": layer checksum mismatch");
    offset_ += header_size + lh.body_bytes();
    previous_vertices_ = lh.level_vertices;
    --next_level_;
    return Status::Ok();
  }
  if (bytes.size() - header_size < layer.header.body_bytes())
    return {StatusCode::kNeedMoreInput, "layer incomplete"};
  const std::span<const uint8_t> body = bytes.subspan(header_size, layer.header.body_bytes());
  const LayerHeader& lh = layer.header;
  layer.candidates = body.first(lh.candidate_bytes);
  layer.payload = body.subspan(lh.candidate_bytes, lh.payload_bytes);
  layer.carving = body.subspan(uint64_t{lh.candidate_bytes} + lh.payload_bytes, lh.carving_bytes);
  const uint64_t regions_at = uint64_t{lh.candidate_bytes} + lh.payload_bytes + lh.carving_bytes;
  layer.regions = body.subspan(regions_at, lh.region_bytes);
  layer.faces = body.subspan(regions_at + lh.region_bytes, lh.face_bytes);
  const uint64_t values_at = regions_at + lh.region_bytes + lh.face_bytes;
  layer.values = body.subspan(values_at, lh.value_bytes);
  layer.cell_values = body.subspan(values_at + lh.value_bytes, lh.cell_value_bytes);
  const uint64_t order_at = values_at + lh.value_bytes + lh.cell_value_bytes;
  layer.order = body.subspan(order_at, lh.order_bytes);
  layer.exact = body.subspan(order_at + lh.order_bytes, lh.exact_bytes);
  const uint64_t edge_nodes_at = order_at + lh.order_bytes + lh.exact_bytes;
  layer.edge_nodes = body.subspan(edge_nodes_at, lh.edge_node_bytes);
  layer.edge_values = body.subspan(edge_nodes_at + lh.edge_node_bytes, lh.edge_value_bytes);
  const uint64_t node_order_at = edge_nodes_at + lh.edge_node_bytes + lh.edge_value_bytes;
  layer.node_order = body.subspan(node_order_at, lh.node_order_bytes);
  layer.node_labels = body.subspan(node_order_at + lh.node_order_bytes);
  if (xxh3_64(bytes.first(layer_checksum_offset(header_size)), body) != layer.header.checksum)
    return corrupt(where + ": layer checksum mismatch");
  offset_ += header_size + layer.header.body_bytes();
  previous_vertices_ = layer.header.level_vertices;
  --next_level_;
  return Status::Ok();
}

StreamSummary scan_stream(std::span<const uint8_t> bytes) {
  StreamSummary s;
  s.bytes = bytes.size();
  s.status = parse_header(bytes, s.header);
  if (!s.status.ok()) {
    if (s.status.code() == StatusCode::kNeedMoreInput)
      s.status = {StatusCode::kTruncated, "the stream ends inside its header"};
    return s;
  }
  if (s.header.flags & kFlagValues) {
    size_t table_bytes = 0;
    s.status = parse_field_table(bytes.subspan(kHeaderSize), s.fields, table_bytes);
    if (!s.status.ok()) {
      if (s.status.code() == StatusCode::kNeedMoreInput)
        s.status = {StatusCode::kTruncated, "the stream ends inside its field table"};
      return s;
    }
    s.field_table_bytes = table_bytes;
  }
  if (s.header.flags & kFlagRegions) {
    size_t table_bytes = 0;
    s.status = parse_region_table(bytes.subspan(kHeaderSize + s.field_table_bytes), s.regions, table_bytes);
    if (!s.status.ok()) {
      if (s.status.code() == StatusCode::kNeedMoreInput)
        s.status = {StatusCode::kTruncated, "the stream ends inside its region table"};
      return s;
    }
    s.region_table_bytes = table_bytes;
  }
  if (s.header.flags & kFlagFaces) {
    size_t table_bytes = 0;
    s.status = parse_region_table(bytes.subspan(kHeaderSize + s.field_table_bytes + s.region_table_bytes),
                                  s.face_tags, table_bytes);
    if (s.status.ok() && s.face_tags.size() > kMaxFaceTags)
      s.status = {StatusCode::kCorrupt, "face tag table: more than 254 tags"};
    if (!s.status.ok()) {
      if (s.status.code() == StatusCode::kNeedMoreInput)
        s.status = {StatusCode::kTruncated, "the stream ends inside its face tag table"};
      return s;
    }
    s.face_table_bytes = table_bytes;
  }
  if (s.header.flags & kFlagCellData) {
    size_t table_bytes = 0;
    s.status = parse_field_table(
        bytes.subspan(kHeaderSize + s.field_table_bytes + s.region_table_bytes + s.face_table_bytes),
        s.cell_fields, table_bytes);
    if (!s.status.ok()) {
      if (s.status.code() == StatusCode::kNeedMoreInput)
        s.status = {StatusCode::kTruncated, "the stream ends inside its cell field table"};
      return s;
    }
    s.cell_field_table_bytes = table_bytes;
  }
  LayerWalk walk(s.header, std::numeric_limits<uint64_t>::max(), s.tables_bytes());
  while (true) {
    const int level = walk.next_level();
    Layer layer;
    bool header_seen = false;
    const Status st = walk.next(bytes.subspan(walk.offset()), layer, &header_seen);
    if (st.ok()) {
      s.layers.push_back({layer.header, 0, layer.offset, true, {}, {}, {}});
      if (layer.header.bricked) {
        LayerHeader& lh = s.layers.back().header;
        std::vector<BrickChunk> chunks;
        s.status =
            parse_brick_index(layer.index, lh.brick_depth, s.header.grid.qbits, lh.new_vertices,
                              lh.chunk_bytes, s.header.flags, lh.level, chunks)
                .with_context("level " + std::to_string(level) + " at byte " + std::to_string(layer.offset));
        if (!s.status.ok()) return s;
        s.layers.back().chunks = chunks.size();
        for (const BrickChunk& c : chunks)
          if (s.status = check_chunk(c, layer.chunks.subspan(c.offset, c.size()),
                                     layer.offset + kBrickedLayerHeaderSize + layer.index.size() + c.offset)
                             .with_context("level " + std::to_string(level) + " at byte " +
                                           std::to_string(layer.offset));
              !s.status.ok())
            return s;
        for (const BrickChunk& c : chunks) {
          lh.payload_bytes += c.payload_bytes, lh.carving_bytes += c.carving_bytes,
              lh.value_bytes += c.value_bytes, lh.region_bytes += c.region_bytes,
              lh.face_bytes += c.face_bytes, lh.cell_value_bytes += c.cell_value_bytes;
          // Each chunk's value sections, their fields' shares added up.
          const ChunkBytes parts = split_chunk(c, layer.chunks.subspan(c.offset, c.size()));
          const auto add_shares = [&](std::span<const uint8_t> section,
                                      std::span<const FieldDescription> table,
                                      std::vector<uint64_t>& field_bytes) {
            if (table.empty() || section.empty()) return true;
            std::vector<uint64_t> shares;
            s.status =
                value_section_field_bytes(section, table, shares)
                    .with_context("level " + std::to_string(level) + ", brick " + std::to_string(c.brick));
            field_bytes.resize(shares.size(), 0);
            for (size_t f = 0; f < shares.size(); ++f) field_bytes[f] += shares[f];
            return s.status.ok();
          };
          if (!add_shares(parts.values, s.fields, s.layers.back().field_bytes) ||
              !add_shares(parts.cell_values, s.cell_fields, s.layers.back().cell_field_bytes))
            return s;
        }
      } else if (!s.fields.empty()) {
        s.status = value_section_field_bytes(layer.values, s.fields, s.layers.back().field_bytes);
        if (!s.status.ok()) return s;
      }
      if (!s.fields.empty() && !layer.edge_values.empty()) {
        s.status = value_section_field_bytes(layer.edge_values, s.fields, s.layers.back().edge_field_bytes);
        if (!s.status.ok()) return s;
      }
      if (!s.cell_fields.empty() && !layer.cell_values.empty()) {
        s.status =
            value_section_field_bytes(layer.cell_values, s.cell_fields, s.layers.back().cell_field_bytes);
        if (!s.status.ok()) return s;
      }
      continue;
    }
    if (st.code() != StatusCode::kNeedMoreInput) {
      s.status = st;
    } else if (!walk.done()) {
      // (The bytes are the whole input: a length past their end may be damage.)
      if (Status damage = walk.overshoot_is_damage(bytes.subspan(walk.offset())); !damage.ok()) {
        s.status = damage;
        return s;
      }
      if (header_seen) s.layers.push_back({layer.header, 0, layer.offset, false, {}, {}, {}});
      s.status = {StatusCode::kTruncated,
                  header_seen
                      ? "the stream ends inside level " + std::to_string(level) + "'s layer"
                      : "the stream ends in the header of level " + std::to_string(level) + "'s layer"};
    }
    return s;
  }
}

namespace {

std::array<int32_t, 12> canonical_row(std::span<const GridPoint> points, const std::array<uint32_t, 4>& c) {
  std::array<GridPoint, 4> q = {points[c[0]], points[c[1]], points[c[2]], points[c[3]]};
  std::sort(q.begin(), q.end());
  std::array<int32_t, 12> row;
  for (int i = 0; i < 4; ++i) row[3 * i] = q[i].x, row[3 * i + 1] = q[i].y, row[3 * i + 2] = q[i].z;
  return row;
}

}  // namespace

uint64_t cell_hash_sum(std::span<const GridPoint> points, std::span<const std::array<uint32_t, 4>> cells) {
  // A wrapping sum, so any grouping gives the same: on every core, each
  // cell's row in a buffer of its own (not a writer's heap array a cell,
  // whose allocations were most of a block's time here).
  constexpr size_t kCells = 16384;
  std::vector<uint64_t> sums((cells.size() + kCells - 1) / kCells, 0);
  parallel_ranges(cells.size(), kCells, [&](size_t first, size_t last) {
    uint64_t sum = 0;
    std::array<uint8_t, 48> bytes;
    for (size_t c = first; c < last; ++c) {
      const std::array<int32_t, 12> row = canonical_row(points, cells[c]);
      for (size_t i = 0; i < row.size(); ++i)
        for (size_t b = 0; b < 4; ++b)
          bytes[4 * i + b] = static_cast<uint8_t>(static_cast<uint32_t>(row[i]) >> (8 * b));
      sum += xxh3_64(bytes);
    }
    sums[first / kCells] = sum;
  });
  uint64_t sum = 0;
  for (uint64_t s : sums) sum += s;
  return sum;
}

uint64_t level_cell_hash(uint32_t flags, std::span<const GridPoint> points,
                         std::span<const std::array<uint32_t, 4>> cells) {
  return (flags & kFlagBricks) ? cell_hash_sum(points, cells) : cell_set_hash(points, cells);
}

uint64_t cell_set_hash(std::span<const GridPoint> points, std::span<const std::array<uint32_t, 4>> cells) {
  std::vector<std::array<int32_t, 12>> canon;
  canon.reserve(cells.size());
  for (const auto& c : cells) canon.push_back(canonical_row(points, c));
  std::sort(canon.begin(), canon.end());
  ByteWriter w;
  for (const auto& row : canon)
    for (int32_t v : row) w.u32(static_cast<uint32_t>(v));
  return xxh3_64(w.data());
}

}  // namespace dtm
