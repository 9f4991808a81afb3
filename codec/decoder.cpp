#include "decoder.h"

#include <string>

#include <random>

#include "bitstream/checksum.h"
#include "bitstream/point_set_coder.h"
#include "core/geometry.h"

namespace dtm {

// Every point decoded so far, to reject a layer that repeats one: open
// addressing with linear probing (coordinates are >= 0, so x = -1 marks an
// empty slot), grown as points arrive, never to what the stream claims. The
// hash is seeded per decoder, so that a stream cannot be crafted to make
// every point collide (which would make the checks quadratic).
struct ProgressiveDecoder::PointSet {
  std::vector<GridPoint> slots = std::vector<GridPoint>(1024, GridPoint{-1, 0, 0});
  size_t size = 0;
  uint64_t seed = (static_cast<uint64_t>(std::random_device{}()) << 32) ^ std::random_device{}();

  size_t hash(const GridPoint& p) const {
    const int32_t key[3] = {p.x, p.y, p.z};
    return static_cast<size_t>(
        xxh3_64({reinterpret_cast<const uint8_t*>(key), sizeof key}, seed));
  }
  size_t slot_of(const GridPoint& p) const {
    const size_t mask = slots.size() - 1;
    size_t i = hash(p) & mask;
    while (slots[i].x >= 0 && slots[i] != p) i = (i + 1) & mask;
    return i;
  }
  bool contains(const GridPoint& p) const { return slots[slot_of(p)].x >= 0; }
  void insert(const GridPoint& p) {
    if (2 * (size + 1) > slots.size()) {
      std::vector<GridPoint> old(slots.size() * 2, GridPoint{-1, 0, 0});
      old.swap(slots);
      for (const GridPoint& q : old)
        if (q.x >= 0) slots[slot_of(q)] = q;
    }
    GridPoint& s = slots[slot_of(p)];
    if (s.x < 0) s = p, ++size;
  }
};

ProgressiveDecoder::ProgressiveDecoder(DecoderOptions options)
    : options_(options), seen_(std::make_unique<PointSet>()) {}
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

// Decodes one more piece (the header or one layer) if its bytes are all here.
Status ProgressiveDecoder::step(const LevelCallback& on_level) {
  const std::span<const uint8_t> avail(pending_.data() + pending_start_,
                                       pending_.size() - pending_start_);
  if (!has_header_) {
    DTM_RETURN_IF_ERROR(parse_header(avail, header_));
    has_header_ = true;
    pending_start_ += kHeaderSize;
    consumed_ += kHeaderSize;
    return Status::Ok();
  }
  const int level = header_.level_count - 1 - static_cast<int>(levels_.size());
  if (level < 0) {  // complete: any further byte is trailing data, whenever it comes
    if (!avail.empty())
      return {StatusCode::kCorrupt, std::to_string(avail.size()) +
                                        " bytes of trailing data after the last layer"};
    return {StatusCode::kNeedMoreInput, "complete"};
  }
  const std::string where = "level " + std::to_string(level) + " at byte " + std::to_string(consumed_);
  LayerHeader lh;
  const uint32_t previous = levels_.empty() ? 0 : levels_.back().vertices;
  Status s = parse_layer_header(avail, header_, level, previous, lh);
  if (s.code() == StatusCode::kNeedMoreInput) return s;
  if (!s.ok()) return {s.code(), where + ": " + s.message()};
  if (lh.level_vertices > options_.max_vertices)
    return {StatusCode::kLimitExceeded, where + ": " + std::to_string(lh.level_vertices) +
                                            " vertices exceed the limit of " +
                                            std::to_string(options_.max_vertices)};
  if (avail.size() < kLayerHeaderSize + lh.payload_bytes)
    return {StatusCode::kNeedMoreInput, "layer incomplete"};
  const auto payload = avail.subspan(kLayerHeaderSize, lh.payload_bytes);
  if (!layer_checksum_ok(avail, payload, lh.checksum))
    return {StatusCode::kCorrupt, where + ": layer checksum mismatch"};

  std::vector<GridPoint> added;
  s = decode_point_set(payload, header_.grid.qbits, lh.new_vertices, added);
  if (!s.ok()) return {s.code(), where + ": " + s.message()};
  for (const GridPoint& p : added)
    if (seen_->contains(p))
      return {StatusCode::kCorrupt, where + ": a point of this layer is already in a coarser level"};
  if (levels_.empty() && !spans_three_dimensions(added))
    return {StatusCode::kCorrupt, where + ": the base level does not span three dimensions"};
  for (const GridPoint& p : added) seen_->insert(p);
  points_.insert(points_.end(), added.begin(), added.end());
  ++layers_pending_;

  DecodedLevel d;
  d.level = level;
  d.vertices = lh.level_vertices;
  d.alpha = lh.alpha;
  if (header_.flags & kFlagCellHashes) d.cell_hash = lh.cell_hash;
  levels_.push_back(d);
  pending_start_ += kLayerHeaderSize + lh.payload_bytes;
  consumed_ += kLayerHeaderSize + lh.payload_bytes;
  if (on_level) on_level(*this, d);
  if (level == options_.stop_after_level) stopped_ = true;
  return Status::Ok();
}

Status ProgressiveDecoder::finish() const {
  if (!error_.ok()) return error_;
  if (stopped_ || complete()) return Status::Ok();
  if (!has_header_) return {StatusCode::kTruncated, "the input ends inside the header"};
  return {StatusCode::kTruncated,
          levels_.empty() ? std::string("the input ends before the base level is complete")
                          : "the input ends after level " + std::to_string(finest_level()) +
                                " (of " + std::to_string(header_.level_count) + " levels)"};
}

int ProgressiveDecoder::finest_level() const {
  return levels_.empty() ? -1 : levels_.back().level;
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
  if (inserted_ == points_.size()) return;
  const std::span<const GridPoint> batch(points_.data() + inserted_, points_.size() - inserted_);
  std::vector<uint32_t> ids(batch.size());
  for (size_t i = 0; i < ids.size(); ++i) ids[i] = static_cast<uint32_t>(inserted_ + i);
  // One layer of a finer level arrives in Morton order, a space-filling
  // curve: inserted in that order, each point located from the previous one,
  // it goes ~12% faster than re-sorted. Anything else (the base layer,
  // several layers at once) gets CGAL's spatially sorted batch insertion.
  if (inserted_ > 0 && layers_pending_ == 1) dt_.insert_one_by_one(batch, ids);
  else dt_.insert(batch, ids);
  inserted_ = points_.size();
  layers_pending_ = 0;
}

TetMesh ProgressiveDecoder::delaunay() const {
  insert_pending();
  return dt_.mesh();
}

std::vector<std::array<uint32_t, 4>> ProgressiveDecoder::carved_cells() const {
  if (levels_.empty()) return {};
  const TetMesh dt = delaunay();
  return flagged_cells(dt, carve(dt, points_, levels_.back().alpha));
}

std::vector<uint8_t> carve(const TetMesh& dt, std::span<const GridPoint> points, double alpha) {
  std::vector<uint8_t> in_mesh(dt.cells.size());
  for (size_t k = 0; k < dt.cells.size(); ++k) {
    const auto& c = dt.cells[k];
    in_mesh[k] =
        canonical_circumradius({points[c[0]], points[c[1]], points[c[2]], points[c[3]]}) <= alpha;
  }
  return in_mesh;
}

std::vector<std::array<uint32_t, 4>> flagged_cells(const TetMesh& dt,
                                                   std::span<const uint8_t> in_mesh) {
  std::vector<std::array<uint32_t, 4>> out;
  for (size_t k = 0; k < dt.cells.size(); ++k)
    if (in_mesh[k]) out.push_back(dt.cells[k]);
  return out;
}

Status decode_stream(std::span<const uint8_t> bytes, ProgressiveDecoder& decoder) {
  const Status s = decoder.feed(bytes);
  if (!s.ok()) return s;
  return decoder.finish();
}

}  // namespace dtm
