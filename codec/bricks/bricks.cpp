#include "codec/bricks/bricks.h"

#include <algorithm>
#include <string>

#include "common/checksum.h"
#include "common/parallel_for.h"
#include "common/parallel_sort.h"
#include "mesh/carving.h"

namespace dtm {
namespace {

Status index_corrupt(const std::string& what) { return corrupt("brick index: " + what); }

// LEB128, at most 10 bytes and 64 bits.
bool get_varint(std::span<const uint8_t> in, size_t& pos, uint64_t& v) {
  v = 0;
  for (int shift = 0; shift < 64; shift += 7) {
    if (pos >= in.size()) return false;
    const uint8_t b = in[pos++];
    if (shift == 63 && b > 1) return false;
    v |= static_cast<uint64_t>(b & 0x7F) << shift;
    if (!(b & 0x80)) return true;
  }
  return false;
}

bool get_u32_varint(std::span<const uint8_t> in, size_t& pos, uint32_t& v) {
  uint64_t x = 0;
  if (!get_varint(in, pos, x) || x > UINT32_MAX) return false;
  v = static_cast<uint32_t>(x);
  return true;
}

// The smallest bytes an index entry takes: five one-byte varints and the checksum.
constexpr size_t kMinEntryBytes = 9;

}  // namespace

ChunkBytes split_chunk(const BrickChunk& chunk, std::span<const uint8_t> bytes) {
  ChunkBytes c;
  c.payload = bytes.first(chunk.payload_bytes);
  c.carving = bytes.subspan(chunk.payload_bytes, chunk.carving_bytes);
  c.values = bytes.subspan(uint64_t{chunk.payload_bytes} + chunk.carving_bytes, chunk.value_bytes);
  const uint64_t regions_at = uint64_t{chunk.payload_bytes} + chunk.carving_bytes + chunk.value_bytes;
  c.regions = bytes.subspan(regions_at, chunk.region_bytes);
  c.faces = bytes.subspan(regions_at + chunk.region_bytes, chunk.face_bytes);
  if (bytes.size() >= chunk.size())
    c.cell_values = bytes.subspan(chunk.points_size(), chunk.cell_value_bytes);
  return c;
}

IndexFields index_fields(uint16_t stream_flags, int level) {
  return {(stream_flags & kFlagRegions) != 0, (stream_flags & kFlagFaces) != 0,
          (stream_flags & kFlagCellData) != 0 && level == 0};
}

uint32_t chunk_checksum(std::span<const uint8_t> bytes) { return static_cast<uint32_t>(xxh3_64(bytes)); }

Status parse_brick_index(std::span<const uint8_t> index, int depth, int qbits, uint64_t new_vertices,
                         uint64_t chunk_bytes, uint16_t stream_flags, int level,
                         std::vector<BrickChunk>& out) {
  out.clear();
  const IndexFields fields = index_fields(stream_flags, level);
  if (depth < 0 || depth > kMaxBrickDepth || depth > qbits) return index_corrupt("brick depth out of range");
  size_t pos = 0;
  uint64_t count = 0;
  if (!get_varint(index, pos, count)) return index_corrupt("the chunk count is cut short");
  if (count > (index.size() - pos) / kMinEntryBytes)
    return index_corrupt("more chunks than the index has bytes for");
  out.reserve(count);
  const uint64_t bricks = uint64_t{1} << (3 * depth);
  uint64_t offset = 0, points = 0;
  for (uint64_t i = 0; i < count; ++i) {
    BrickChunk c;
    uint64_t delta = 0;
    if (!get_varint(index, pos, delta) || !get_u32_varint(index, pos, c.new_points) ||
        !get_u32_varint(index, pos, c.payload_bytes) || !get_u32_varint(index, pos, c.carving_bytes) ||
        !get_u32_varint(index, pos, c.value_bytes) ||
        (fields.regions && !get_u32_varint(index, pos, c.region_bytes)) ||
        (fields.faces && !get_u32_varint(index, pos, c.face_bytes)) ||
        (fields.cell_values && !get_u32_varint(index, pos, c.cell_value_bytes)) ||
        index.size() - pos < (fields.cell_values ? 8u : 4u))
      return index_corrupt("entry " + std::to_string(i) + " is cut short");
    for (int b = 0; b < 4; ++b) c.checksum |= static_cast<uint32_t>(index[pos++]) << (8 * b);
    if (fields.cell_values)
      for (int b = 0; b < 4; ++b) c.cell_value_checksum |= static_cast<uint32_t>(index[pos++]) << (8 * b);
    if (c.cell_value_bytes == 0 && c.cell_value_checksum != 0)
      return index_corrupt("a cell value checksum without cell values");
    const uint64_t previous = out.empty() ? 0 : out.back().brick + 1;
    if (previous >= bricks || delta >= bricks - previous) return index_corrupt("a brick outside the grid");
    c.brick = previous + delta;
    if (c.new_points == 0 && c.payload_bytes != 0)
      return index_corrupt("a payload in a chunk without points");
    if (c.new_points > 0 && c.payload_bytes < min_payload_bytes(c.new_points))
      return index_corrupt("a chunk's payload is too short for its points");
    if (c.size() == 0) return index_corrupt("an empty chunk");
    if (c.carving_bytes != 0 && !(stream_flags & kFlagCarvingCorrections))
      return index_corrupt("carving corrections present without their flag");
    if (c.value_bytes != 0 && !(stream_flags & kFlagValues))
      return index_corrupt("values present without their flag");
    if (c.value_bytes != 0 && c.new_points == 0) return index_corrupt("values in a chunk without points");
    if (c.value_bytes == 0 && c.new_points > 0 && (stream_flags & kFlagValues))
      return index_corrupt("a chunk's points without their values");
    c.offset = offset;
    c.points_before = points;
    offset += c.size();
    points += c.new_points;
    if (offset > chunk_bytes) return index_corrupt("chunks larger than the layer's chunk bytes");
    out.push_back(c);
  }
  if (pos != index.size()) return index_corrupt("bytes after the last entry");
  if (offset != chunk_bytes) return index_corrupt("chunks smaller than the layer's chunk bytes");
  if (points != new_vertices) return index_corrupt("the chunks' points do not add up to the layer's");
  return Status::Ok();
}

const BrickChunk* find_chunk(std::span<const BrickChunk> chunks, uint64_t brick) {
  const auto it = std::lower_bound(chunks.begin(), chunks.end(), brick,
                                   [](const BrickChunk& c, uint64_t b) { return c.brick < b; });
  return it != chunks.end() && it->brick == brick ? &*it : nullptr;
}

std::vector<uint32_t> morton_ranks(std::span<const MortonCode> codes) {
  // (On every core; the points are distinct, so are their codes, and the
  // index breaks a tie all the same.)
  std::vector<uint32_t> by_code(codes.size());
  for (uint32_t i = 0; i < by_code.size(); ++i) by_code[i] = i;
  parallel_sort(by_code.begin(), by_code.end(),
                [&](uint32_t a, uint32_t b) { return codes[a] != codes[b] ? codes[a] < codes[b] : a < b; });
  std::vector<uint32_t> rank(codes.size());
  parallel_ranges(by_code.size(), 16384, [&](size_t first, size_t last) {
    for (size_t r = first; r < last; ++r) rank[by_code[r]] = static_cast<uint32_t>(r);
  });
  return rank;
}

GridBox brick_box(uint64_t brick, int qbits, int depth) {
  const GridPoint corner = morton_decode(MortonCode{brick} << (3 * (qbits - depth)), qbits);
  const int64_t side = int64_t{1} << (qbits - depth);
  return {{corner.x, corner.y, corner.z}, {corner.x + side - 1, corner.y + side - 1, corner.z + side - 1}};
}

std::vector<uint64_t> bricks_meeting(const GridBox& box, int qbits, int depth, GridBox* covered) {
  std::vector<uint64_t> out;
  const GridBox clipped = box.grown(0, qbits);
  if (clipped.empty()) {
    if (covered) *covered = clipped;
    return out;
  }
  const int shift = qbits - depth;
  std::array<int64_t, 3> first{}, last{};
  for (int a = 0; a < 3; ++a) first[a] = clipped.lo[a] >> shift, last[a] = clipped.hi[a] >> shift;
  for (int64_t x = first[0]; x <= last[0]; ++x)
    for (int64_t y = first[1]; y <= last[1]; ++y)
      for (int64_t z = first[2]; z <= last[2]; ++z)
        out.push_back(static_cast<uint64_t>(morton_encode(
            {static_cast<int32_t>(x), static_cast<int32_t>(y), static_cast<int32_t>(z)}, depth)));
  std::sort(out.begin(), out.end());
  if (covered)
    for (int a = 0; a < 3; ++a)
      covered->lo[a] = first[a] << shift, covered->hi[a] = ((last[a] + 1) << shift) - 1;
  return out;
}

std::vector<uint64_t> carving_bricks_of_cells(const TetMesh& dt, std::span<const GridPoint> points,
                                              std::span<const MortonCode> codes, int qbits, int depth,
                                              double kept_radius) {
  const size_t m = dt.cells.size();
  std::vector<uint64_t> out(m);
  constexpr size_t kBlock = 4096;
  parallel_for((m + kBlock - 1) / kBlock,
               [&](size_t block) {
                 for (size_t c = block * kBlock; c < std::min(m, block * kBlock + kBlock); ++c) {
                   const auto& cell = dt.cells[c];
                   if (!(carving_radius(points, cell) <= kept_radius)) {
                     out[c] = kNoBrick;
                     continue;
                   }
                   MortonCode least = codes[cell[0]];
                   for (int i = 1; i < 4; ++i) least = std::min(least, codes[cell[i]]);
                   out[c] = brick_of(least, qbits, depth);
                 }
               },
               2);
  return out;
}

std::span<const MortonCode> known_in_brick(std::span<const MortonCode> known, uint64_t brick, int qbits,
                                           int depth) {
  const PointSetNode node = brick_node(brick, qbits, depth);
  const MortonCode end = node.base + (MortonCode{1} << (3 * qbits - node.depth));
  const auto first = std::lower_bound(known.begin(), known.end(), node.base);
  const auto last = std::lower_bound(first, known.end(), end);
  return {first, last};
}

SetCoderModels chunk_models(const SetCoderModels& after_base, std::span<const MortonCode> known_in_brick,
                            int qbits) {
  SetCoderModels m = after_base.clone();
  std::vector<GridPoint> points;
  points.reserve(known_in_brick.size());
  for (const MortonCode c : known_in_brick) points.push_back(morton_decode(c, qbits));
  m.note_points(points);
  return m;
}

}  // namespace dtm
