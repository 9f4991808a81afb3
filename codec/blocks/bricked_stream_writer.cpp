#include "codec/blocks/bricked_stream_writer.h"

#include <algorithm>
#include <string>
#include <utility>

#include "codec/blocks/block_runs.h"
#include "codec/bricks/brick_index_encoder.h"
#include "codec/bricks/bricks.h"
#include "codec/stream/format.h"
#include "codec/stream/format_encoder.h"
#include "common/byte_io.h"
#include "common/release.h"

namespace dtm {
namespace {

// The layer's points in bricks: the bricks with points, ascending, and
// where each one's points begin in the layer (one more at the end).
struct LayerBricks {
  std::vector<uint64_t> bricks;
  std::vector<size_t> first;
};
LayerBricks bricks_of(std::span<const GridPoint> fresh, int qbits, int depth) {
  LayerBricks b;
  for (size_t i = 0; i < fresh.size(); ++i) {
    const uint64_t brick = brick_of(morton_encode(fresh[i], qbits), qbits, depth);
    if (b.bricks.empty() || b.bricks.back() != brick) b.bricks.push_back(brick), b.first.push_back(i);
  }
  b.first.push_back(fresh.size());
  return b;
}

// The oldest version that says all the stream holds: 17.0 with tagged
// faces (each chunk its kept cells' faces' tags), 16.0 with cell data
// (level 0's chunks carry their cells' values), 15.0 with regions (each
// chunk its kept cells'), else 8.0 (§3.5).
uint8_t stream_version(const BrickedStreamInput& in) {
  return !in.face_tags.empty() ? kVersionMajorBrickedFaces
         : in.cell_values      ? kVersionMajorBrickedCellData
         : !in.regions.empty() ? kVersionMajorBrickedRegions
                               : kVersionMajorBricked;
}
uint16_t stream_flags(const BrickedStreamInput& in) {
  return static_cast<uint16_t>(
      (in.cell_hashes ? kFlagCellHashes : 0) | kFlagCarvingCorrections | kFlagBricks |
      (in.values ? kFlagValues : 0) | (in.regions.empty() ? 0 : kFlagRegions) |
      (in.face_tags.empty() ? 0 : kFlagFaces) | (in.cell_values ? kFlagCellData : 0));
}

class LayerWriter {
 public:
  LayerWriter(const BrickedStreamInput& in, BrickedEncoding& out)
      : in_(in), out_(out), q_(in.grid.qbits), x_(*in.exchange) {
    models_.enable_coordinate_reuse(q_);
  }
  Status write(int level, BrickedLevel& lo);

 private:
  // The bricks' payloads, made by the ranks in turn.
  Status payloads(int level, const BlockPlan& plan, std::span<const GridPoint> fresh, const LayerBricks& b,
                  std::vector<std::vector<uint8_t>>& out);
  // Their values, each chunk's from the coarser levels' in its brick.
  // `fresh_ids`: the new points' grid ids.
  Status values(int level, const BlockPlan& plan, std::span<const uint32_t> fresh_ids,
                std::span<const GridPoint> fresh, const LayerBricks& b,
                std::vector<std::vector<uint8_t>>& out);
  // V_{l+1} in brick k's box, ascending (the points a chunk of layer l is
  // coded against), and their ids if asked: found in the index for each
  // brick rather than held for the level (16 bytes a code: level 1's were
  // the largest thing a rank held while level 0's bricks were coded).
  void coarser_in(int level, const LayerBricks& b, size_t k, std::vector<MortonCode>& codes,
                  std::vector<uint32_t>* ids) const {
    const int shift = 3 * (q_ - depth_);
    in_.index->between(MortonCode{b.bricks[k]} << shift, MortonCode{b.bricks[k] + 1} << shift, in_.level_of,
                       level + 1, codes, ids);
  }

  const BrickedStreamInput& in_;
  BrickedEncoding& out_;
  int q_;
  RankExchange& x_;
  SetCoderModels models_;  // as the base layer leaves them
  bool base_ = true;       // the next layer written is the base layer
  int depth_ = 0;          // the layer's brick depth
};

Status LayerWriter::payloads(int level, const BlockPlan& plan, std::span<const GridPoint> fresh,
                             const LayerBricks& b, std::vector<std::vector<uint8_t>>& out) {
  if (base_) {  // the base layer: one chunk, the stream's models
    out.assign(1, encode_point_set({}, fresh, q_, models_, brick_node(0, q_, 0)));
    return Status::Ok();
  }
  Status status = Status::Ok();
  out = run_blocks(
      plan, x_,
      [&](size_t k) -> StatusOr<std::vector<uint8_t>> {
        std::vector<MortonCode> known;
        coarser_in(level, b, k, known, nullptr);
        return encode_chunk_points(fresh.subspan(b.first[k], b.first[k + 1] - b.first[k]), known, b.bricks[k],
                                   q_, depth_, models_);
      },
      status);
  return status;
}

Status LayerWriter::values(int level, const BlockPlan& plan, std::span<const uint32_t> fresh_ids,
                           std::span<const GridPoint> fresh, const LayerBricks& b,
                           std::vector<std::vector<uint8_t>>& out) {
  out.assign(b.bricks.size(), {});
  if (!in_.values) return Status::Ok();
  Status status = Status::Ok();
  const auto coded = run_blocks(
      plan, x_,
      [&](size_t k) -> StatusOr<std::vector<uint8_t>> {
        std::vector<MortonCode> codes;
        std::vector<uint32_t> coarser_ids;  // V_{l+1} in the brick, in Morton order
        if (!base_) coarser_in(level, b, k, codes, &coarser_ids);
        const std::vector<GridPoint> coarser_points = gather(in_.points, coarser_ids);
        std::vector<uint64_t> field_bytes;
        const std::vector<uint8_t> section = in_.values->encode_chunk(
            coarser_ids, coarser_points, fresh_ids.subspan(b.first[k], b.first[k + 1] - b.first[k]),
            fresh.subspan(b.first[k], b.first[k + 1] - b.first[k]), field_bytes);
        ByteWriter w;
        put(w, std::span<const uint8_t>(section));
        w.u64(field_bytes.size());
        for (uint64_t f : field_bytes) w.u64(f);
        return w.take();
      },
      status);
  DTM_RETURN_IF_ERROR(status);
  std::vector<uint64_t>& level_fields = out_.level_field_bytes[static_cast<size_t>(level)];
  level_fields.assign(in_.values->descriptions().size(), 0);
  for (size_t k = 0; k < b.bricks.size(); ++k) {
    BlockReader r(coded[k]);
    out[k] = r.bytes();
    const uint64_t fields = r.u64();
    for (uint64_t f = 0; f < fields; ++f) level_fields[f] += r.u64();
  }
  return Status::Ok();
}

Status LayerWriter::write(int level, BrickedLevel& lo) {
  report_phase(in_.on_phase, "writing level " + std::to_string(level) + "'s layer");
  const auto l = static_cast<size_t>(level);
  const int depth = depth_ = lo.brick_depth;
  // The layer's points in Morton order (their codes are not kept: at
  // level 0 they were the largest thing every rank held), and their ids
  // where the values or the decode order need them.
  std::vector<uint32_t> ids = in_.index->level_ids(in_.level_of, level);
  const size_t level_vertices = ids.size();
  // (Made to size, as the decode order: grown by doubling, level 0's
  // would be held up to three times over while copied.)
  size_t new_points = 0;
  for (uint32_t id : ids) new_points += in_.level_of[id] == level;
  std::vector<GridPoint> fresh;
  std::vector<uint32_t> fresh_ids;
  const bool with_ids = in_.values || in_.decode_order;
  fresh.reserve(new_points);
  if (with_ids) fresh_ids.reserve(new_points);
  for (uint32_t id : ids)
    if (in_.level_of[id] == level) {
      fresh.push_back(in_.points[id]);
      if (with_ids) fresh_ids.push_back(id);
    }
  release(ids);
  if (in_.decode_order) {
    if (out_.decode_order.capacity() < in_.points.size()) out_.decode_order.reserve(in_.points.size());
    out_.decode_order.insert(out_.decode_order.end(), fresh_ids.begin(), fresh_ids.end());
  }
  const LayerBricks b = bricks_of(fresh, q_, depth);
  BlockPlan plan;  // the bricks, shared out among the ranks
  plan.blocks = b.bricks;
  plan.bits.assign(b.bricks.size(), 3 * depth);
  plan.first = b.first;
  assign_ranks(plan, x_.size());
  std::vector<std::vector<uint8_t>> payload, value;
  DTM_RETURN_IF_ERROR(payloads(level, plan, fresh, b, payload));
  DTM_RETURN_IF_ERROR(values(level, plan, fresh_ids, fresh, b, value));
  release(fresh_ids);

  // The chunks: every brick with points, corrections, regions or cell
  // values, ascending.
  std::vector<BrickParts> parts;
  auto carving = lo.carving.begin();
  auto regions = lo.regions.begin();
  auto faces = lo.faces.begin();
  auto cells = lo.cell_values.begin();
  size_t p = 0;
  while (p < b.bricks.size() || carving != lo.carving.end() || regions != lo.regions.end() ||
         faces != lo.faces.end() || cells != lo.cell_values.end()) {
    BrickParts& part = parts.emplace_back();
    part.brick = std::min({p < b.bricks.size() ? b.bricks[p] : UINT64_MAX,
                           carving != lo.carving.end() ? carving->first : UINT64_MAX,
                           regions != lo.regions.end() ? regions->first : UINT64_MAX,
                           faces != lo.faces.end() ? faces->first : UINT64_MAX,
                           cells != lo.cell_values.end() ? cells->first : UINT64_MAX});
    const bool points = p < b.bricks.size() && b.bricks[p] == part.brick;
    if (points) {
      part.new_points = static_cast<uint32_t>(b.first[p + 1] - b.first[p]);
      part.payload = std::move(payload[p]);
    }
    if (carving != lo.carving.end() && carving->first == part.brick) {
      out_.carving_bytes[l] += carving->second.size();
      part.carving = std::move(carving->second);
      ++carving;
    }
    if (regions != lo.regions.end() && regions->first == part.brick) {
      out_.region_bytes[l] += regions->second.size();
      part.regions = std::move(regions->second);
      ++regions;
    }
    if (faces != lo.faces.end() && faces->first == part.brick) {
      out_.face_bytes[l] += faces->second.size();
      part.faces = std::move(faces->second);
      ++faces;
    }
    if (cells != lo.cell_values.end() && cells->first == part.brick) {
      out_.cell_value_bytes += cells->second.size();
      part.cell_values = std::move(cells->second);
      ++cells;
    }
    if (points) {
      out_.value_bytes[l] += value[p].size();
      part.values = std::move(value[p]);
      ++p;
    }
  }
  std::vector<uint8_t> chunk_bytes;
  const std::vector<BrickChunk> chunks = write_chunks(parts, chunk_bytes);
  parts.clear();
  const uint16_t flags = stream_flags(in_);
  const std::vector<uint8_t> index = write_brick_index(chunks, index_fields(flags, level));
  if (level == 0) out_.tagged_faces_kept = lo.tagged_faces_kept;
  if (level == 0 && in_.cell_values) {
    out_.cell_field_bytes = std::move(lo.cell_field_bytes);
    out_.cells_from_input = lo.cells_from_input;
    out_.cells_from_nearest = lo.cells_from_nearest;
  }
  LayerHeader lh;
  lh.format_major = stream_version(in_);
  lh.bricked = true;
  lh.level = static_cast<uint16_t>(level);
  lh.new_vertices = static_cast<uint32_t>(fresh.size());
  lh.level_vertices = static_cast<uint32_t>(level_vertices);
  lh.alpha = lo.alpha;
  lh.kept_radius = lo.kept_radius;
  lh.brick_depth = static_cast<uint8_t>(depth);
  if (in_.cell_hashes) lh.cell_hash = lo.cell_hash;
  const std::vector<uint8_t> layer = write_bricked_layer(lh, index, chunk_bytes);
  out_.layer_bytes[l] = layer.size();
  out_.chunk_count[l] = chunks.size();
  out_.index_bytes[l] = index.size();
  out_.brick_depth[l] = depth;
  out_.bytes.insert(out_.bytes.end(), layer.begin(), layer.end());
  base_ = false;
  return Status::Ok();
}

}  // namespace

void BrickedLevel::take_faces(BlockAnalysis& a) {
  for (auto& [brick, bytes] : a.faces) faces[brick] = std::move(bytes);
  tagged_faces_kept += a.figures.tagged_faces_kept;
}

void BrickedLevel::take_sections(BlockAnalysis& a) {
  for (auto& [brick, bytes] : a.carving) carving[brick] = std::move(bytes);
  for (auto& [brick, bytes] : a.regions) regions[brick] = std::move(bytes);
  for (auto& [brick, bytes] : a.cell_values) cell_values[brick] = std::move(bytes);
  cell_field_bytes.resize(std::max(cell_field_bytes.size(), a.cell_field_bytes.size()), 0);
  for (size_t k = 0; k < a.cell_field_bytes.size(); ++k) cell_field_bytes[k] += a.cell_field_bytes[k];
  cells_from_input += a.figures.cells_from_input;
  cells_from_nearest += a.figures.cells_from_nearest;
  take_faces(a);
}

void BrickedLevel::clear_sections() {
  carving.clear();
  regions.clear();
  faces.clear();
  cell_values.clear();
  cell_field_bytes.clear();
  cells_from_input = cells_from_nearest = tagged_faces_kept = 0;
}

StatusOr<BrickedEncoding> write_bricked_stream(const BrickedStreamInput& in,
                                               std::vector<BrickedLevel>& levels) {
  StreamHeader header;
  header.grid = in.grid;
  header.alpha_policy = in.alpha_policy;
  header.version_major = stream_version(in);
  header.flags = stream_flags(in);
  header.level_count = static_cast<uint16_t>(levels.size());
  header.vertex_count = static_cast<uint32_t>(in.points.size());
  BrickedEncoding out;
  out.bytes = write_header(header);
  if (in.values) {
    const std::vector<uint8_t> table = write_field_table(in.values->descriptions());
    out.field_table_bytes = table.size();
    out.bytes.insert(out.bytes.end(), table.begin(), table.end());
  }
  if (!in.regions.empty()) {
    DTM_RETURN_IF_ERROR(check_region_table(in.regions));
    const std::vector<uint8_t> table = write_region_table(in.regions);
    out.region_table_bytes = table.size();
    out.bytes.insert(out.bytes.end(), table.begin(), table.end());
  }
  if (!in.face_tags.empty()) {
    DTM_RETURN_IF_ERROR(check_region_table(in.face_tags));
    const std::vector<uint8_t> table = write_region_table(in.face_tags);
    out.face_table_bytes = table.size();
    out.bytes.insert(out.bytes.end(), table.begin(), table.end());
  }
  if (in.cell_values) {
    const std::vector<uint8_t> table = write_field_table(in.cell_values->descriptions());
    out.cell_field_table_bytes = table.size();
    out.bytes.insert(out.bytes.end(), table.begin(), table.end());
  }
  const size_t count = levels.size();
  out.value_bytes.assign(count, 0);
  out.level_field_bytes.assign(count, {});
  out.layer_bytes.assign(count, 0);
  out.carving_bytes.assign(count, 0);
  out.region_bytes.assign(count, 0);
  out.face_bytes.assign(count, 0);
  out.chunk_count.assign(count, 0);
  out.index_bytes.assign(count, 0);
  out.brick_depth.assign(count, 0);
  for (const BrickedLevel& l : levels) out.levels.push_back(l.stats);
  LayerWriter writer(in, out);
  for (int level = static_cast<int>(count) - 1; level >= 0; --level)
    DTM_RETURN_IF_ERROR(writer.write(level, levels[static_cast<size_t>(level)]));
  return out;
}

}  // namespace dtm
