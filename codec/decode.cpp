#include "codec/decode.h"

#include <algorithm>
#include <string>
#include <utility>

#include "codec/sections/candidate_coder.h"
#include "codec/sections/carving_coder.h"
#include "codec/sections/exact_cell_coder.h"
#include "codec/sections/face_coder.h"
#include "codec/sections/node_label_coder.h"
#include "codec/sections/node_order_coder.h"
#include "codec/sections/region_coder.h"
#include "codec/sections/vertex_order_coder.h"
#include "codec/stream/layer_coder.h"
#include "common/parallel_for.h"
#include "mesh/geometry.h"
#include "mesh/topology.h"

namespace dtm {
namespace {
// A layer this large is inserted on every core (where the build has them).
constexpr size_t kParallelLayer = 20000;

// A bricked layer's chunks with their bytes and where each begins in the
// stream (what a damage names).
std::vector<ChunkInput> chunk_inputs(const Layer& layer, std::span<const BrickChunk> chunks) {
  const uint64_t area =
      layer.offset + kBrickedLayerHeaderSize + layer.index.size();  // the chunks' first byte
  std::vector<ChunkInput> inputs;
  inputs.reserve(chunks.size());
  for (const BrickChunk& c : chunks)
    inputs.push_back({&c, layer.chunks.subspan(c.offset, c.size()), area + c.offset});
  return inputs;
}

}  // namespace

ProgressiveDecoder::ProgressiveDecoder(DecoderOptions options) : options_(std::move(options)) {}
ProgressiveDecoder::~ProgressiveDecoder() = default;

Status ProgressiveDecoder::fail(Status s) {
  error_ = s;
  return s;
}

Status ProgressiveDecoder::feed(std::span<const uint8_t> bytes, const LevelCallback& on_level) {
  if (!error_.ok()) return error_;
  if (stopped_) return Status::Ok();  // the requested level is decoded: the rest is not wanted
  pending_.insert(pending_.end(), bytes.begin(), bytes.end());
  while (true) {
    const Status s = step(on_level);
    if (s.code() == StatusCode::kNeedMoreInput) break;
    if (!s.ok()) return fail(s);
    if (stopped_) break;
  }
  // Drop consumed bytes once they are the larger part of the buffer.
  if (pending_start_ > pending_.size() / 2) {
    pending_.erase(pending_.begin(), pending_.begin() + pending_start_);
    pending_start_ = 0;
  }
  return Status::Ok();
}

// Once every table the header announces is read, the layers can be walked.
Status ProgressiveDecoder::tables_read() {
  if (has_field_table_ && has_region_table_ && has_face_table_ && has_cell_field_table_)
    walk_.emplace(header_, options_.max_vertices, tables_bytes_);
  return Status::Ok();
}

// Decodes one more piece (the header or one layer) if its bytes are all here.
Status ProgressiveDecoder::step(const LevelCallback& on_level) {
  const std::span<const uint8_t> avail(pending_.data() + pending_start_, pending_.size() - pending_start_);
  if (!has_header_) {
    DTM_RETURN_IF_ERROR(parse_header(avail, header_));
    has_header_ = true;
    // A level asked for that the stream does not have: said now, not after
    // decoding every level there is.
    if (options_.stop_after_level < -1 || options_.stop_after_level >= static_cast<int>(header_.level_count))
      return {StatusCode::kInvalidInput, "level " + std::to_string(options_.stop_after_level) +
                                             " asked, the stream has levels 0 to " +
                                             std::to_string(static_cast<int>(header_.level_count) - 1)};
    has_field_table_ = !(header_.flags & kFlagValues);
    has_region_table_ = !(header_.flags & kFlagRegions);
    has_face_table_ = !(header_.flags & kFlagFaces);
    has_cell_field_table_ = !(header_.flags & kFlagCellData);
    if (header_.version_major >= 3) models_.enable_coordinate_reuse(header_.grid.qbits);
    pending_start_ += kHeaderSize;
    return tables_read();
  }
  // The tables after the header, in stream order (spec/FORMAT.md §2).
  size_t table_bytes = 0;
  if (!has_field_table_) {
    std::vector<FieldDescription> table;
    DTM_RETURN_IF_ERROR(parse_field_table(avail, table, table_bytes));
    for (const FieldDescription& f : table) fields_.push_back({f, {}});
    value_decoder_.emplace(std::move(table));
    has_field_table_ = true;
  } else if (!has_region_table_) {
    DTM_RETURN_IF_ERROR(parse_region_table(avail, regions_, table_bytes));
    has_region_table_ = true;
  } else if (!has_face_table_) {
    DTM_RETURN_IF_ERROR(parse_region_table(avail, face_tags_, table_bytes).with_context("face tags"));
    if (face_tags_.size() > kMaxFaceTags)
      return {StatusCode::kCorrupt, "face tag table: more than " + std::to_string(kMaxFaceTags) + " tags"};
    has_face_table_ = true;
  } else if (!has_cell_field_table_) {
    DTM_RETURN_IF_ERROR(parse_field_table(avail, cell_fields_, table_bytes).with_context("cell fields"));
    has_cell_field_table_ = true;
  }
  if (table_bytes > 0) {
    tables_bytes_ += table_bytes;
    pending_start_ += table_bytes;
    return tables_read();
  }
  const int level = walk_->next_level();
  Layer layer;
  DTM_RETURN_IF_ERROR(walk_->next(avail, layer));
  const std::string where = "level " + std::to_string(level) + " at byte " + std::to_string(layer.offset);
  const LayerHeader& lh = layer.header;
  report_phase(options_.on_phase,
               "level " + std::to_string(level) + ": its " + std::to_string(lh.new_vertices) + " new points");

  std::vector<GridPoint> added;
  DTM_RETURN_IF_ERROR(decode_layer_points(layer, added).with_context(where));
  if (levels_.empty() && !spans_three_dimensions(added))
    return {StatusCode::kCorrupt, where + ": the base level does not span three dimensions"};
  if (value_decoder_) {
    report_phase(options_.on_phase, "level " + std::to_string(level) + ": their values");
    uint64_t components = 0;
    for (const FieldValues& f : fields_) components += f.description.components;
    if (uint64_t{lh.level_vertices} * components > options_.max_values)
      return {StatusCode::kLimitExceeded, where + ": " + std::to_string(lh.level_vertices) + " vertices of " +
                                              std::to_string(components) +
                                              " values each exceed the limit of " +
                                              std::to_string(options_.max_values) + " values"};
    DTM_RETURN_IF_ERROR((lh.bricked ? decode_bricked_values(layer, added)
                                    : value_decoder_->decode_layer(layer.values, added, layer_values_))
                            .with_context(where));
    for (size_t f = 0; f < fields_.size(); ++f)
      fields_[f].bits.insert(fields_[f].bits.end(), layer_values_[f].bits.begin(),
                             layer_values_[f].bits.end());
  }
  points_.insert(points_.end(), added.begin(), added.end());
  ++layers_pending_;

  DecodedLevel d;
  d.level = level;
  d.vertices = lh.level_vertices;
  d.alpha = lh.alpha;
  if (lh.bricked) d.kept_radius = lh.kept_radius;
  if (header_.flags & kFlagCellHashes) d.cell_hash = lh.cell_hash;
  d.stream_bytes = layer.offset + layer.size();
  levels_.push_back(d);
  finest_offset_ = layer.offset;
  // Only the finest level's carving is ever asked for (carved_cells()).
  carving_.assign(layer.carving.begin(), layer.carving.end());
  region_section_.assign(layer.regions.begin(), layer.regions.end());
  face_section_.assign(layer.faces.begin(), layer.faces.end());
  cell_value_section_.assign(layer.cell_values.begin(), layer.cell_values.end());
  order_section_.assign(layer.order.begin(), layer.order.end());
  exact_section_.assign(layer.exact.begin(), layer.exact.end());
  edge_node_section_.assign(layer.edge_nodes.begin(), layer.edge_nodes.end());
  edge_value_section_.assign(layer.edge_values.begin(), layer.edge_values.end());
  node_order_section_.assign(layer.node_order.begin(), layer.node_order.end());
  node_label_section_.assign(layer.node_labels.begin(), layer.node_labels.end());
  if (lh.bricked) {
    chunk_bytes_.assign(layer.chunks.begin(), layer.chunks.end());
    brick_depth_ = lh.brick_depth;
    kept_radius_ = lh.kept_radius;
  }
  pending_start_ += layer.size();
  if (on_level) on_level(*this, d);
  // (Level 0 is the last: asked for, the rest is read as without a level,
  // so that bytes after it are refused as trailing data, spec §4.)
  if (level == options_.stop_after_level && level > 0) stopped_ = true;
  return Status::Ok();
}

Status ProgressiveDecoder::decode_layer_points(const Layer& layer, std::vector<GridPoint>& added) {
  const LayerHeader& lh = layer.header;
  const int qbits = header_.grid.qbits;
  if (lh.bricked) return decode_bricked_layer(layer, added);
  // The coder itself rejects a point repeated within the layer or already
  // known from a coarser one.
  if (lh.candidate_kinds == 0) {
    DTM_RETURN_IF_ERROR(decode_point_set(layer.payload, known_, qbits, lh.new_vertices, models_, added));
    merge_known(known_, added, qbits);
    return Status::Ok();
  }
  // 7.0: the candidates come from DT(V_{l+1}), the points decoded so far.
  insert_pending();
  DTM_RETURN_IF_ERROR(mesh_status_);
  report_phase(options_.on_phase, "level " + std::to_string(lh.level) + ": its " +
                                      std::to_string(lh.new_vertices) + " new points, from candidates");
  const CandidateList candidates =
      layer_candidates(dt_.finite_cells(), points_, known_, qbits, lh.candidate_kinds);
  std::vector<GridPoint> sent;
  DTM_RETURN_IF_ERROR(decode_candidate_section(layer.candidates, candidates, lh.new_vertices, sent));
  std::vector<MortonCode> sent_codes;
  sent_codes.reserve(sent.size());
  for (const GridPoint& p : sent) sent_codes.push_back(morton_encode(p, qbits));
  std::sort(sent_codes.begin(), sent_codes.end());
  for (size_t i = 0; i < sent_codes.size(); ++i)
    if ((i > 0 && sent_codes[i] == sent_codes[i - 1]) ||
        std::binary_search(known_.begin(), known_.end(), sent_codes[i]))
      return {StatusCode::kCorrupt, "candidates: a point sent twice, or known from a coarser level"};
  models_.note_points(sent);
  merge_known(known_, sent, qbits);
  std::vector<GridPoint> rest;
  const auto left = static_cast<uint32_t>(lh.new_vertices - sent.size());
  DTM_RETURN_IF_ERROR(decode_point_set(layer.payload, known_, qbits, left, models_, rest));
  merge_known(known_, rest, qbits);
  // The layer in Morton order, as a layer without candidates comes out (its
  // size as decoded, never as the header claims: spec §5).
  added.reserve(sent.size() + rest.size());
  for (const MortonCode c : sent_codes) added.push_back(morton_decode(c, qbits));
  const size_t middle = added.size();
  added.insert(added.end(), rest.begin(), rest.end());
  std::inplace_merge(added.begin(), added.begin() + static_cast<std::ptrdiff_t>(middle), added.end(),
                     [qbits](const GridPoint& a, const GridPoint& b) {
                       return morton_encode(a, qbits) < morton_encode(b, qbits);
                     });
  return Status::Ok();
}

Status ProgressiveDecoder::decode_bricked_layer(const Layer& layer, std::vector<GridPoint>& added) {
  const LayerHeader& lh = layer.header;
  const int qbits = header_.grid.qbits;
  std::vector<BrickChunk> chunks;
  DTM_RETURN_IF_ERROR(parse_brick_index(layer.index, lh.brick_depth, qbits, lh.new_vertices, lh.chunk_bytes,
                                        header_.flags, lh.level, chunks));
  const std::vector<ChunkInput> inputs = chunk_inputs(layer, chunks);
  DTM_RETURN_IF_ERROR(decode_bricked_points(inputs, known_, qbits, lh.brick_depth, models_, added));
  merge_known(known_, added, qbits);
  chunks_ = std::move(chunks);
  return Status::Ok();
}

Status ProgressiveDecoder::decode_bricked_values(const Layer& layer, std::span<const GridPoint> added) {
  const LayerHeader& lh = layer.header;
  std::vector<BrickChunk> chunks;
  DTM_RETURN_IF_ERROR(parse_brick_index(layer.index, lh.brick_depth, header_.grid.qbits, lh.new_vertices,
                                        lh.chunk_bytes, header_.flags, lh.level, chunks));
  const std::vector<ChunkInput> inputs = chunk_inputs(layer, chunks);
  return dtm::decode_bricked_values(inputs, header_.grid.qbits, lh.brick_depth,
                                    value_decoder_->descriptions(), points_, fields_, added, layer_values_);
}

ProgressiveDecoder::BrickedCells ProgressiveDecoder::bricked_cells(const TetMesh& dt) const {
  const int qbits = header_.grid.qbits;
  std::vector<MortonCode> codes(points_.size());
  parallel_ranges(codes.size(), 16384, [&](size_t first, size_t last) {
    for (size_t v = first; v < last; ++v) codes[v] = morton_encode(points_[v], qbits);
  });
  const std::vector<uint64_t> owner =
      carving_bricks_of_cells(dt, points_, codes, qbits, brick_depth_, kept_radius_);
  BrickedCells out;
  out.chunk_of_cell.assign(owner.size(), kNoCarvingChunk);
  parallel_ranges(owner.size(), 16384, [&](size_t first, size_t last) {
    for (size_t c = first; c < last; ++c)
      if (const BrickChunk* chunk = owner[c] == kNoBrick ? nullptr : find_chunk(chunks_, owner[c]))
        out.chunk_of_cell[c] = static_cast<uint32_t>(chunk - chunks_.data());
  });
  out.vertex_rank = morton_ranks(codes);
  return out;
}

std::vector<std::span<const uint8_t>> ProgressiveDecoder::chunk_sections(
    std::span<const uint8_t> ChunkBytes::*part) const {
  std::vector<std::span<const uint8_t>> sections;
  sections.reserve(chunks_.size());
  for (const BrickChunk& c : chunks_)
    sections.push_back(split_chunk(c, std::span(chunk_bytes_).subspan(c.offset, c.size())).*part);
  return sections;
}

std::vector<uint8_t> ProgressiveDecoder::bricked_carving(const TetMesh& dt,
                                                         std::vector<uint32_t>& order) const {
  const BrickedCells b = bricked_cells(dt);
  std::vector<uint8_t> kept;
  ChunkCells cells;
  Status s = decode_carving_chunks(chunk_sections(&ChunkBytes::carving), dt, points_, levels_.back().alpha,
                                   b.chunk_of_cell, b.vertex_rank, kept, &order, &cells);
  // (15.0: the kept cells' regions, each chunk's after its carving.)
  if (s.ok() && (header_.flags & kFlagRegions))
    s = decode_region_chunks(chunk_sections(&ChunkBytes::regions), dt, cells, b.chunk_of_cell,
                             regions_.size(), kept);
  if (!s.ok()) {
    mesh_status_ = s.with_context(finest_where());
    return {};
  }
  return kept;
}

Status ProgressiveDecoder::finish() const {
  if (!error_.ok()) return error_;
  if (stopped_ || complete()) return Status::Ok();
  if (!has_header_) return {StatusCode::kTruncated, "the input ends inside the header"};
  if (!has_field_table_) return {StatusCode::kTruncated, "the input ends inside the field table"};
  // The input has ended: a layer that runs past it may be one whose header
  // has a damaged length rather than a cut stream.
  if (walk_ && pending_start_ <= pending_.size())
    DTM_RETURN_IF_ERROR(
        walk_->overshoot_is_damage(std::span<const uint8_t>(pending_).subspan(pending_start_)));
  return {StatusCode::kTruncated, levels_.empty()
                                      ? std::string("the input ends before the base level is complete")
                                      : "the input ends after level " + std::to_string(finest_level()) +
                                            " (of " + std::to_string(header_.level_count) + " levels)"};
}

int ProgressiveDecoder::finest_level() const { return levels_.empty() ? -1 : levels_.back().level; }

std::string ProgressiveDecoder::finest_where() const {
  return "level " + std::to_string(finest_level()) + " at byte " + std::to_string(finest_offset_);
}

uint32_t ProgressiveDecoder::level_vertices(int level) const {
  for (const auto& l : levels_)
    if (l.level == level) return l.vertices;
  return 0;
}

std::vector<int32_t> ProgressiveDecoder::vertex_levels() const {
  std::vector<int32_t> out(points_.size());
  uint32_t first = 0;
  for (const auto& l : levels_) {
    for (uint32_t i = first; i < l.vertices; ++i) out[i] = l.level;
    first = l.vertices;
  }
  return out;
}

void ProgressiveDecoder::insert_pending() const {
  if (inserted_ == points_.size() || !mesh_status_.ok()) return;
  const std::span<const GridPoint> batch(points_.data() + inserted_, points_.size() - inserted_);
  std::vector<uint32_t> ids(batch.size());
  for (size_t i = 0; i < ids.size(); ++i) ids[i] = static_cast<uint32_t>(inserted_ + i);
  // One layer of a finer level arrives in Morton order, a space-filling
  // curve: inserted in that order on one thread, each point located from the
  // previous one, it goes ~12% faster than re-sorted. A large one, where
  // several cores can share it, and anything else (the base layer, several
  // layers at once) get the batch insertion (spatially sorted, on every core).
  report_phase(options_.on_phase, "level " + std::to_string(finest_level()) + ": inserting " +
                                      std::to_string(batch.size()) + " points");
  const bool one_layer = inserted_ > 0 && layers_pending_ == 1;
  const bool shared = parallel_delaunay_available() && batch.size() >= kParallelLayer;
  const Status s = one_layer && !shared ? dt_.insert_one_by_one(batch, ids) : dt_.insert(batch, ids);
  if (!s.ok()) {
    mesh_status_ = s.with_context(finest_where());
    return;
  }
  inserted_ = points_.size();
  layers_pending_ = 0;
}

TetMesh ProgressiveDecoder::delaunay(IncrementalDelaunay::CellOrder order, double spare) const {
  insert_pending();
  if (!mesh_status_.ok()) return {};
  report_phase(options_.on_phase, "level " + std::to_string(finest_level()) + ": its cells");
  return dt_.mesh(order, spare);
}

std::vector<uint8_t> ProgressiveDecoder::carving(const TetMesh& dt) const {
  std::vector<uint32_t> order;
  return carving(dt, order);
}

std::vector<uint8_t> ProgressiveDecoder::carving(const TetMesh& dt, std::vector<uint32_t>& order) const {
  order.clear();
  if (levels_.empty() || !mesh_status_.ok()) return {};
  report_phase(options_.on_phase, "level " + std::to_string(finest_level()) + ": carving");
  const double alpha = levels_.back().alpha;
  if (!(header_.flags & kFlagCarvingCorrections)) {
    order = canonical_cell_order(dt.cells);
    return carve(dt, points_, alpha);
  }
  if (!chunks_.empty() || (header_.flags & kFlagBricks)) return bricked_carving(dt, order);
  std::vector<uint8_t> kept;
  // (Level 0 of an exact stream: its own contexts, spec/FORMAT.md §3.2.)
  Status s = decode_carving(
      carving_, dt, points_, alpha,
      exact_level() ? exact_carving_contexts(header_.version_major) : carving_contexts(header_.version_major),
      kept, &order);
  if (s.ok() && (header_.flags & kFlagRegions) && !exact_level())
    s = decode_regions(region_section_, dt, order, regions_.size(), kept);
  if (!s.ok()) {
    mesh_status_ = s.with_context(finest_where());
    return {};
  }
  return kept;
}

ProgressiveDecoder::LevelCells ProgressiveDecoder::level_cells() const {
  LevelCells out;
  // An exact level grows by its fill, a few percent of the cells (11.6% on
  // the corpus's worst): room for a quarter more, so that adding them does
  // not copy the arrays.
  out.mesh = delaunay(IncrementalDelaunay::CellOrder::kAsBuilt, exact_level() ? 0.25 : 0);
  if (!mesh_status_.ok()) return {};
  out.kept = carving(out.mesh, out.order);
  if (!mesh_status_.ok()) return {};
  if (!exact_level()) return out;
  // The fill from the kept Delaunay cells, then the regions of the whole
  // level (spec/FORMAT.md §3.10): the cells the exact section adds are kept.
  report_phase(options_.on_phase, "level 0: the input's cells (the exact section)");
  ExactFill fill;
  Status s = decode_exact_cells(exact_section_, out.mesh, points_, levels_.back().alpha, out.kept, out.order,
                                apex_ranks_of(header_.version_major), fill);
  if (s.ok()) {
    const auto first = static_cast<uint32_t>(out.mesh.cells.size());
    extend_with_fill(out.mesh, fill);
    out.kept.resize(out.mesh.cells.size(), 1);
    out.order.reserve(out.mesh.cells.size());
    for (uint32_t c = first; c < out.mesh.cells.size(); ++c) out.order.push_back(c);
    if (header_.flags & kFlagRegions)
      s = decode_regions(region_section_, out.mesh, out.order, regions_.size(), out.kept);
  }
  if (!s.ok()) {
    mesh_status_ = s.with_context(finest_where());
    return {};
  }
  return out;
}

std::vector<uint8_t> ProgressiveDecoder::face_tags(const TetMesh& dt, std::span<const uint8_t> kept,
                                                   SurfaceFaces& surface) const {
  surface = {};
  if (kept.size() != dt.cells.size()) return {};  // no carving (its error is in mesh_status())
  surface = surface_faces(dt, kept);
  std::vector<uint8_t> tag;
  if (!(header_.flags & kFlagFaces)) {
    tag.assign(surface.faces.size(), 1);
    return tag;
  }
  const Status s = header_.flags & kFlagBricks
                       ? bricked_face_tags(dt, kept, surface, tag)
                       : decode_face_tags(face_section_, surface, face_tags_.size(), tag);
  if (!s.ok()) {
    mesh_status_ = s.with_context(finest_where());
    return {};
  }
  return tag;
}

Status ProgressiveDecoder::bricked_face_tags(const TetMesh& dt, std::span<const uint8_t> kept,
                                             const SurfaceFaces& surface, std::vector<uint8_t>& tag) const {
  // (17.0: each chunk's faces' tags, after its regions; a surface face's
  // tag is in the chunk of the cell the surface takes it from.)
  const BrickedCells b = bricked_cells(dt);
  const ChunkCells cells = chunk_cells(dt, b.chunk_of_cell, chunks_.size(), b.vertex_rank);
  const ChunkFaces faces = chunk_faces(dt, cells, b.chunk_of_cell, kept, b.vertex_rank);
  std::vector<uint8_t> label;
  DTM_RETURN_IF_ERROR(
      decode_face_chunks(chunk_sections(&ChunkBytes::faces), faces, face_tags_.size(), label));
  // The tagged ones by their cell's face, and the surface's.
  std::vector<std::pair<uint64_t, uint8_t>> tagged;
  for (size_t f = 0; f < faces.faces.size(); ++f)
    if (label[f] > 1)
      tagged.emplace_back(uint64_t{faces.faces[f].cell} * 4 + faces.faces[f].opposite, label[f]);
  std::sort(tagged.begin(), tagged.end());
  tag.assign(surface.faces.size(), 1);
  size_t found = 0;
  for (size_t f = 0; f < surface.faces.size(); ++f) {
    const uint64_t key = uint64_t{surface.faces[f].cell} * 4 + surface.faces[f].opposite;
    const auto it = std::lower_bound(tagged.begin(), tagged.end(), std::pair<uint64_t, uint8_t>{key, 0});
    if (it != tagged.end() && it->first == key) tag[f] = it->second, ++found;
  }
  if (found != tagged.size())
    return {StatusCode::kCorrupt, "a tag on a face that the level's surface does not take from its chunk"};
  return Status::Ok();
}

std::vector<FieldValues> ProgressiveDecoder::cell_data(const TetMesh& dt, std::span<const uint8_t> kept,
                                                       std::span<const uint32_t> order) const {
  std::vector<FieldValues> out;
  if (cell_fields_.empty() || finest_level() != 0 || kept.size() != dt.cells.size() ||
      order.size() != dt.cells.size())
    return out;
  std::vector<std::array<uint32_t, 4>> cells;
  for (uint32_t c : order)
    if (kept[c]) cells.push_back(dt.cells[c]);
  uint64_t components = 0;
  for (const FieldDescription& f : cell_fields_) components += f.components;
  Status s = Status::Ok();
  if (cells.size() * components > options_.max_values) {
    s = {StatusCode::kLimitExceeded, std::to_string(cells.size()) + " cells of " +
                                         std::to_string(components) + " values each exceed the limit of " +
                                         std::to_string(options_.max_values) + " values"};
  } else if (header_.flags & kFlagBricks) {
    // (16.0: each chunk's kept cells' values, after its regions; given
    // here in the kept cells' index order, then in the canonical order.)
    const BrickedCells b = bricked_cells(dt);
    const ChunkCells chunks = chunk_cells(dt, b.chunk_of_cell, chunks_.size(), b.vertex_rank);
    std::vector<FieldValues> by_index;
    s = decode_cell_value_chunks(cell_fields_, chunk_sections(&ChunkBytes::cell_values), dt, points_, chunks,
                                 b.chunk_of_cell, kept, by_index);
    if (s.ok()) {
      uint64_t kept_count = 0;
      const std::vector<uint32_t> slot = kept_cell_slots(kept, kept_count);  // each one's place in by_index
      for (const FieldValues& f : by_index) {
        const auto n = static_cast<size_t>(f.description.components);
        FieldValues& o = out.emplace_back(FieldValues{f.description, {}});
        o.bits.reserve(cells.size() * n);
        for (uint32_t c : order)
          if (kept[c]) {
            const auto first = f.bits.begin() + static_cast<std::ptrdiff_t>(size_t{slot[c]} * n);
            o.bits.insert(o.bits.end(), first, first + static_cast<std::ptrdiff_t>(n));
          }
      }
    }
  } else {
    s = decode_cell_values(cell_fields_, cell_value_section_, cell_positions(points_, cells), out);
  }
  if (!s.ok()) {
    mesh_status_ = s.with_context(finest_where() + ", its cell values");
    return {};
  }
  return out;
}

std::vector<uint32_t> ProgressiveDecoder::vertex_order(const TetMesh& dt) const {
  std::vector<uint32_t> order;
  if (!(header_.flags & kFlagVertexOrder) || finest_level() != 0 || !mesh_status_.ok()) return order;
  const Status s = decode_vertex_order(order_section_, vertex_neighbours(points_.size(), dt.cells), order);
  if (!s.ok()) {
    mesh_status_ = s.with_context(finest_where());
    return {};
  }
  return order;
}

std::vector<uint32_t> ProgressiveDecoder::node_order(const EdgeNodes& nodes) const {
  std::vector<uint32_t> numbering;
  if (!numbers_edge_nodes() || !mesh_status_.ok() || nodes.present.size() != nodes.edges.corners.size())
    return numbering;
  const Status s = decode_node_order(node_order_section_, nodes.edges,
                                     node_order_frame(nodes.edges, nodes.present), points_.size(), numbering);
  if (!s.ok()) {
    mesh_status_ = s.with_context(finest_where());
    return {};
  }
  return numbering;
}

std::vector<int64_t> ProgressiveDecoder::node_labels(size_t nodes) const {
  std::vector<int64_t> labels;
  if (!(header_.flags & kFlagNodeLabels) || finest_level() != 0 || !mesh_status_.ok()) return labels;
  const Status s = decode_node_labels(node_label_section_, nodes, labels);
  if (!s.ok()) {
    mesh_status_ = s.with_context(finest_where());
    return {};
  }
  return labels;
}

ProgressiveDecoder::EdgeNodes ProgressiveDecoder::edge_nodes(const LevelCells& level) const {
  EdgeNodes out;
  if (!has_edge_nodes() || !mesh_status_.ok() || level.kept.size() != level.mesh.cells.size()) return out;
  out.edges = level_edges(level.mesh, level.kept, level.order);
  EdgeNodeOffsets nodes;
  // (19.0: each offset from where the surface's normals put the node;
  // 20.0: its creases apart.)
  std::optional<EdgeNodePredictor> predictor;
  if (header_.version_major >= kVersionMajorPredictedEdgeNodes)
    predictor.emplace(level.mesh, level.kept, points_, header_.grid.qbits,
                      header_.version_major >= kVersionMajorCreaseEdgeNodes);
  const Status s = decode_edge_nodes(edge_node_section_, out.edges, header_.grid.qbits, nodes,
                                     predictor ? &*predictor : nullptr);
  if (!s.ok()) {
    mesh_status_ = s.with_context(finest_where() + ", its edge nodes");
    return {};
  }
  // (19.0: their values, predicted from the vertices'.)
  if (header_.version_major >= kVersionMajorPredictedEdgeNodes && !fields_.empty()) {
    const auto count = static_cast<uint64_t>(std::count(nodes.present.begin(), nodes.present.end(), 1));
    uint64_t components = 0;
    for (const FieldValues& f : fields_) components += static_cast<uint64_t>(f.description.components);
    // (The vertices' values are held already: the nodes' come beside them.)
    Status v = (count + points_.size()) * components > options_.max_values
                   ? Status{StatusCode::kLimitExceeded, std::to_string(points_.size()) + " vertices and " +
                                                            std::to_string(count) + " edge nodes of " +
                                                            std::to_string(components) +
                                                            " values each exceed the limit of " +
                                                            std::to_string(options_.max_values) + " values"}
                   : Status::Ok();
    std::vector<FieldDescription> descriptions;
    for (const FieldValues& f : fields_) descriptions.push_back(f.description);
    if (v.ok())
      v = decode_edge_node_values(edge_value_section_, descriptions, fields_, out.edges, nodes.present,
                                  out.values);
    if (!v.ok()) {
      mesh_status_ = v.with_context(finest_where() + ", its edge nodes");
      return {};
    }
  }
  out.present = std::move(nodes.present);
  out.points.resize(out.edges.corners.size());
  for (size_t e = 0; e < out.points.size(); ++e) {
    const GridPoint &a = points_[out.edges.corners[e][0]], &b = points_[out.edges.corners[e][1]];
    const auto& d = nodes.offset[e];
    out.points[e] = {(double(a.x) + double(b.x) + double(d[0])) / 2,
                     (double(a.y) + double(b.y) + double(d[1])) / 2,
                     (double(a.z) + double(b.z) + double(d[2])) / 2};
  }
  return out;
}

std::vector<std::array<uint32_t, 4>> ProgressiveDecoder::carved_cells() const {
  const LevelCells level = level_cells();
  if (!mesh_status_.ok()) return {};
  // On every core, each range of the order gathered on its own (the cells
  // lie anywhere in memory).
  return collect_in_order<std::array<uint32_t, 4>>(
      level.order.size(), size_t{1} << 16,
      [&](size_t first, size_t last, std::vector<std::array<uint32_t, 4>>& out) {
        for (size_t i = first; i < last; ++i)
          if (level.kept[level.order[i]]) out.push_back(level.mesh.cells[level.order[i]]);
      });
}

Status decode_stream(std::span<const uint8_t> bytes, ProgressiveDecoder& decoder) {
  DTM_RETURN_IF_ERROR(decoder.feed(bytes));
  return decoder.finish();
}

}  // namespace dtm
