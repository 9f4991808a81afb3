#include "format.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <string>

#include "bitstream/byte_io.h"
#include "bitstream/checksum.h"
#include "bitstream/point_set_coder.h"

namespace dtm {
namespace {

constexpr size_t kLayerChecksumOffset = 30;

uint32_t low32(uint64_t v) { return static_cast<uint32_t>(v); }

Status corrupt(const std::string& what) { return {StatusCode::kCorrupt, what}; }

}  // namespace

std::vector<uint8_t> write_header(const StreamHeader& h) {
  ByteWriter w;
  w.bytes(kMagic);
  w.u8(h.version_major);
  w.u8(h.version_minor);
  w.u8(static_cast<uint8_t>(h.grid.qbits));
  w.u8(static_cast<uint8_t>(h.alpha_policy));
  w.u16(h.flags);
  w.u16(h.level_count);
  w.u32(h.vertex_count);
  for (double o : h.grid.origin) w.f64(o);
  w.f64(h.grid.step);
  w.u32(low32(xxh3_64(w.data())));
  return w.take();
}

Status parse_header(std::span<const uint8_t> bytes, StreamHeader& h) {
  const size_t magic_seen = std::min(bytes.size(), kMagic.size());
  if (!std::equal(bytes.begin(), bytes.begin() + magic_seen, kMagic.begin()))
    return {StatusCode::kNotDtm, "not a .dtm stream (wrong magic)"};
  if (bytes.size() < kHeaderSize) return {StatusCode::kNeedMoreInput, "header incomplete"};
  ByteReader r(bytes.subspan(kMagic.size(), kHeaderSize - kMagic.size()));
  uint8_t qbits = 0, policy = 0;
  uint32_t header_checksum = 0;
  r.u8(h.version_major);
  r.u8(h.version_minor);
  if (h.version_major < kOldestVersionMajor || h.version_major > kVersionMajor)
    return {StatusCode::kUnsupported, "format version " + std::to_string(h.version_major) + "." +
                                          std::to_string(h.version_minor) + " is not supported (this decoder reads " +
                                          std::to_string(kOldestVersionMajor) + ".x to " +
                                          std::to_string(kVersionMajor) + ".x)"};
  r.u8(qbits);
  r.u8(policy);
  r.u16(h.flags);
  r.u16(h.level_count);
  r.u32(h.vertex_count);
  for (double& o : h.grid.origin) r.f64(o);
  r.f64(h.grid.step);
  r.u32(header_checksum);
  if (header_checksum != low32(xxh3_64(bytes.first(kHeaderSize - 4))))
    return corrupt("header checksum mismatch");
  if (qbits < kMinQBits || qbits > kMaxQBits) return corrupt("qbits out of range");
  h.grid.qbits = qbits;
  if (policy > 2) return corrupt("unknown alpha policy");
  h.alpha_policy = static_cast<AlphaPolicy::Kind>(policy);
  if (h.flags & ~kKnownFlags) return {StatusCode::kUnsupported, "unknown header flags"};
  if (h.level_count == 0) return corrupt("zero levels");
  if (h.vertex_count < 4) return corrupt("fewer than 4 vertices");
  for (double o : h.grid.origin)
    if (!std::isfinite(o)) return corrupt("origin is not finite");
  if (!std::isfinite(h.grid.step) || !(h.grid.step > 0)) return corrupt("step is not positive");
  return Status::Ok();
}

std::vector<uint8_t> write_layer(LayerHeader h, std::span<const uint8_t> payload) {
  ByteWriter w;
  w.u16(h.level);
  w.u32(h.new_vertices);
  w.u32(h.level_vertices);
  w.f64(h.alpha);
  w.u32(h.payload_bytes = static_cast<uint32_t>(payload.size()));
  w.u64(h.cell_hash);
  w.u64(xxh3_64(w.data(), payload));
  w.bytes(payload);
  return w.take();
}

Status parse_layer_header(std::span<const uint8_t> bytes, const StreamHeader& stream,
                          int expected_level, uint32_t previous_level_vertices, LayerHeader& h) {
  if (bytes.size() < kLayerHeaderSize) return {StatusCode::kNeedMoreInput, "layer header incomplete"};
  ByteReader r(bytes.first(kLayerHeaderSize));
  r.u16(h.level);
  r.u32(h.new_vertices);
  r.u32(h.level_vertices);
  r.f64(h.alpha);
  r.u32(h.payload_bytes);
  r.u64(h.cell_hash);
  r.u64(h.checksum);
  if (h.level != expected_level)
    return corrupt("layer for level " + std::to_string(h.level) + " where level " +
                   std::to_string(expected_level) + " was due");
  if (h.new_vertices == 0) return corrupt("a layer without points");
  if (static_cast<uint64_t>(previous_level_vertices) + h.new_vertices != h.level_vertices)
    return corrupt("level vertex count does not add up");
  if (h.level_vertices > stream.vertex_count)
    return corrupt("level has more vertices than the finest level");
  if (h.level == 0 && h.level_vertices != stream.vertex_count)
    return corrupt("finest level's vertex count differs from the header's");
  if (std::isnan(h.alpha) || !(h.alpha > 0)) return corrupt("alpha is not positive");
  if (h.payload_bytes < min_payload_bytes(h.new_vertices))
    return corrupt("payload too short for its point count");
  if (!(stream.flags & kFlagCellHashes) && h.cell_hash != 0)
    return corrupt("cell hash present without its flag");
  return Status::Ok();
}

bool layer_checksum_ok(std::span<const uint8_t> layer_header_bytes,
                       std::span<const uint8_t> payload, uint64_t checksum) {
  return xxh3_64(layer_header_bytes.first(kLayerChecksumOffset), payload) == checksum;
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
  uint64_t offset = kHeaderSize;
  uint32_t previous = 0;
  for (int level = s.header.level_count - 1; level >= 0; --level) {
    LayerSummary layer;
    layer.offset = offset;
    const auto rest = bytes.subspan(offset);
    Status st = parse_layer_header(rest, s.header, level, previous, layer.header);
    if (st.code() == StatusCode::kNeedMoreInput) {
      s.status = {StatusCode::kTruncated, "the stream ends in the header of level " +
                                              std::to_string(level) + "'s layer"};
      return s;
    }
    if (!st.ok()) {
      s.status = {st.code(), "level " + std::to_string(level) + " at byte " +
                                 std::to_string(offset) + ": " + st.message()};
      return s;
    }
    if (rest.size() < kLayerHeaderSize + layer.header.payload_bytes) {
      s.layers.push_back(layer);  // header read, payload incomplete
      s.status = {StatusCode::kTruncated, "the stream ends inside level " +
                                              std::to_string(level) + "'s layer"};
      return s;
    }
    if (!layer_checksum_ok(rest, rest.subspan(kLayerHeaderSize, layer.header.payload_bytes),
                           layer.header.checksum)) {
      s.status = {StatusCode::kCorrupt, "level " + std::to_string(level) + " at byte " +
                                            std::to_string(offset) + ": layer checksum mismatch"};
      return s;
    }
    layer.complete = true;
    s.layers.push_back(layer);
    offset += kLayerHeaderSize + layer.header.payload_bytes;
    previous = layer.header.level_vertices;
  }
  if (offset != bytes.size())
    s.status = {StatusCode::kCorrupt, std::to_string(bytes.size() - offset) +
                                          " bytes of trailing data after the last layer"};
  return s;
}

uint64_t cell_set_hash(std::span<const GridPoint> points,
                       std::span<const std::array<uint32_t, 4>> cells) {
  std::vector<std::array<int32_t, 12>> canon;
  canon.reserve(cells.size());
  for (const auto& c : cells) {
    std::array<GridPoint, 4> q = {points[c[0]], points[c[1]], points[c[2]], points[c[3]]};
    std::sort(q.begin(), q.end());
    std::array<int32_t, 12> row;
    for (int i = 0; i < 4; ++i) row[3 * i] = q[i].x, row[3 * i + 1] = q[i].y, row[3 * i + 2] = q[i].z;
    canon.push_back(row);
  }
  std::sort(canon.begin(), canon.end());
  ByteWriter w;
  for (const auto& row : canon)
    for (int32_t v : row) w.u32(static_cast<uint32_t>(v));
  return xxh3_64(w.data());
}

}  // namespace dtm
