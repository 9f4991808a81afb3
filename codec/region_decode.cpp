#include "codec/region_decode.h"

#include <sys/stat.h>

#include <algorithm>
#include <cerrno>
#include <cfloat>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <functional>
#include <numeric>

#include "codec/sections/carving_coder.h"
#include "codec/sections/face_coder.h"
#include "codec/stream/layer_coder.h"
#include "mesh/carving.h"
#include "mesh/delaunay.h"
#include "mesh/geometry.h"
#include "mesh/topology.h"

namespace dtm {

Status MemorySource::read(uint64_t offset, std::span<uint8_t> out) {
  if (offset > bytes_.size() || out.size() > bytes_.size() - offset)
    return {StatusCode::kTruncated, "the stream ends at byte " + std::to_string(bytes_.size())};
  std::copy_n(bytes_.begin() + static_cast<std::ptrdiff_t>(offset), out.size(), out.begin());
  return Status::Ok();
}

StatusOr<FileSource> FileSource::open(const std::string& path) {
  FileSource f;
  f.path_ = path;
  f.file_ = std::fopen(path.c_str(), "rb");
  if (!f.file_) return Status{StatusCode::kInvalidInput, path + ": cannot open: " + std::strerror(errno)};
  // (A folder opens for reading too; its reads fail later, saying less.)
  struct stat st {};
  if (::fstat(::fileno(f.file_), &st) == 0 && S_ISDIR(st.st_mode))
    return Status{StatusCode::kInvalidInput, path + ": cannot open: " + std::strerror(EISDIR)};
  if (std::fseek(f.file_, 0, SEEK_END) != 0)
    return Status{StatusCode::kInvalidInput, path + ": cannot seek: " + std::strerror(errno)};
  const long end = std::ftell(f.file_);
  if (end < 0) return Status{StatusCode::kInvalidInput, path + ": cannot seek: " + std::strerror(errno)};
  f.size_ = static_cast<uint64_t>(end);
  return f;
}

FileSource::FileSource(FileSource&& o) noexcept : file_(o.file_), size_(o.size_), path_(std::move(o.path_)) {
  o.file_ = nullptr;
}
FileSource& FileSource::operator=(FileSource&& o) noexcept {
  std::swap(file_, o.file_);
  std::swap(size_, o.size_);
  std::swap(path_, o.path_);
  return *this;
}
FileSource::~FileSource() {
  if (file_) std::fclose(file_);
}

Status FileSource::read(uint64_t offset, std::span<uint8_t> out) {
  if (offset > size_ || out.size() > size_ - offset)
    return {StatusCode::kTruncated, path_ + ": the stream ends at byte " + std::to_string(size_)};
  if (std::fseek(file_, static_cast<long>(offset), SEEK_SET) != 0 ||
      std::fread(out.data(), 1, out.size(), file_) != out.size())
    return {StatusCode::kInvalidInput, path_ + ": read error"};
  return Status::Ok();
}

GridBox grid_box_of(const Grid& grid, const std::array<double, 3>& lo, const std::array<double, 3>& hi) {
  GridBox b;
  const double top = std::ldexp(1.0, grid.qbits);
  // A corner a rounding away from a grid point (a decoded vertex's own
  // coordinate, origin + k step in doubles, divided back) is that point.
  // (The rounding grows with the coordinates' size: far from the origin
  // a double's last bit may be many millionths of a step.)
  const auto on_grid = [&](double x, int a, double (*round_away)(double)) {
    const double t = (x - grid.origin[a]) / grid.step;
    const double nearest = std::nearbyint(t);
    const double rounding = 1e-6 + 8 * DBL_EPSILON * (std::abs(x) + std::abs(grid.origin[a])) / grid.step;
    return std::abs(t - nearest) <= rounding ? nearest : round_away(t);
  };
  for (int a = 0; a < 3; ++a) {
    const double l = on_grid(lo[a], a, std::ceil);
    const double h = on_grid(hi[a], a, std::floor);
    b.lo[a] = static_cast<int64_t>(std::clamp(std::isnan(l) ? top : l, -1.0, top));
    b.hi[a] = static_cast<int64_t>(std::clamp(std::isnan(h) ? -1.0 : h, -1.0, top));
  }
  return b;
}

bool cell_meets(std::span<const GridPoint> points, const std::array<uint32_t, 4>& cell, const GridBox& box) {
  std::array<int64_t, 3> lo = {INT64_MAX, INT64_MAX, INT64_MAX}, hi = {INT64_MIN, INT64_MIN, INT64_MIN};
  for (uint32_t v : cell) {
    const GridPoint& p = points[v];
    const int64_t c[3] = {p.x, p.y, p.z};
    for (int a = 0; a < 3; ++a) lo[a] = std::min(lo[a], c[a]), hi[a] = std::max(hi[a], c[a]);
  }
  for (int a = 0; a < 3; ++a)
    if (hi[a] < box.lo[a] || lo[a] > box.hi[a]) return false;
  return true;
}

namespace {

// The region's result from cells over vertices numbered globally: only the
// cells' vertices, ascending number; cells in canonical order.
// `cell_regions` and `cell_values`: per cell, or none. `faces` (corners
// among the cells') and `face_labels`: the tagged faces, ascending.
struct TaggedFaces {
  std::vector<std::array<uint32_t, 3>> faces;
  std::vector<uint8_t> labels;
};
void compact(std::span<const GridPoint> points, std::span<const uint32_t> ids,
             std::span<const int32_t> levels, std::span<const FieldValues> values,
             std::vector<std::array<uint32_t, 4>> cells, std::vector<uint8_t> cell_regions,
             std::span<const FieldValues> cell_values, TaggedFaces faces, RegionMesh& out) {
  std::vector<uint8_t> in_a_cell(points.size(), 0);
  for (const auto& c : cells)
    for (uint32_t v : c) in_a_cell[v] = 1;
  std::vector<uint32_t> used;
  for (uint32_t v = 0; v < points.size(); ++v)
    if (in_a_cell[v]) used.push_back(v);
  std::sort(used.begin(), used.end(), [&](uint32_t a, uint32_t b) { return ids[a] < ids[b]; });
  std::vector<uint32_t> local(points.size(), UINT32_MAX);
  for (const FieldValues& f : values) out.fields.push_back({f.description, {}});
  for (size_t i = 0; i < used.size(); ++i) {
    local[used[i]] = static_cast<uint32_t>(i);
    out.points.push_back(points[used[i]]);
    out.vertex_ids.push_back(ids[used[i]]);
    out.vertex_levels.push_back(levels[used[i]]);
    for (size_t f = 0; f < values.size(); ++f) {
      const size_t n = static_cast<size_t>(values[f].description.components);
      const auto first = values[f].bits.begin() + static_cast<std::ptrdiff_t>(used[i] * n);
      out.fields[f].bits.insert(out.fields[f].bits.end(), first, first + static_cast<std::ptrdiff_t>(n));
    }
  }
  // Each cell positively oriented, its corners ascending but for the last
  // two where that would turn it inside out (sorted_positive()): as the
  // whole level's cells are written.
  for (auto& c : cells) {
    for (uint32_t& v : c) v = local[v];
    c = sorted_positive(c, out.points);
  }
  // The faces in the new numbering, turned as they were, ascending.
  for (auto& f : faces.faces) {
    for (uint32_t& v : f) v = local[v];
    std::rotate(f.begin(), std::min_element(f.begin(), f.end()), f.end());
  }
  std::vector<uint32_t> by_face(faces.faces.size());
  std::iota(by_face.begin(), by_face.end(), 0u);
  std::sort(by_face.begin(), by_face.end(),
            [&](uint32_t a, uint32_t b) { return faces.faces[a] < faces.faces[b]; });
  for (uint32_t k : by_face) {
    out.faces.push_back(faces.faces[k]);
    out.face_labels.push_back(faces.labels[k]);
  }
  // The cells ascending, each with its region (if any).
  std::vector<uint32_t> by_cell(cells.size());
  std::iota(by_cell.begin(), by_cell.end(), 0u);
  std::sort(by_cell.begin(), by_cell.end(), [&](uint32_t a, uint32_t b) { return cells[a] < cells[b]; });
  out.cells.reserve(cells.size());
  for (const FieldValues& f : cell_values) out.cell_fields.push_back({f.description, {}});
  for (uint32_t k : by_cell) {
    out.cells.push_back(cells[k]);
    if (!cell_regions.empty()) out.cell_regions.push_back(cell_regions[k]);
    for (size_t f = 0; f < cell_values.size(); ++f) {
      const auto n = static_cast<size_t>(cell_values[f].description.components);
      const auto first = cell_values[f].bits.begin() + static_cast<std::ptrdiff_t>(k * n);
      out.cell_fields[f].bits.insert(out.cell_fields[f].bits.end(), first,
                                     first + static_cast<std::ptrdiff_t>(n));
    }
  }
}

// The arrays of `from`, without values.
std::vector<FieldValues> empty_like(std::span<const FieldValues> from) {
  std::vector<FieldValues> out;
  out.reserve(from.size());
  for (const FieldValues& f : from) out.push_back({f.description, {}});
  return out;
}

// Appends to `out`'s, per field, the values of cell `c` of `from` (cell-major).
void append_cell(std::span<const FieldValues> from, size_t c, std::vector<FieldValues>& out) {
  for (size_t f = 0; f < from.size(); ++f) {
    const auto n = static_cast<size_t>(from[f].description.components);
    const auto first = from[f].bits.begin() + static_cast<std::ptrdiff_t>(c * n);
    out[f].bits.insert(out[f].bits.end(), first, first + static_cast<std::ptrdiff_t>(n));
  }
}

// What the walk over the layers' headers and indexes keeps of each.
struct LayerPlan {
  LayerHeader header;
  std::vector<BrickChunk> chunks;
  uint64_t chunk_area = 0;    // stream offset of the first chunk
  uint32_t first_vertex = 0;  // the level's vertices before this layer's
  // Where a damage in it is said to be: the layer's level and offset, as
  // the whole decoder says.
  std::string where() const {
    return "level " + std::to_string(header.level) + " at byte " +
           std::to_string(chunk_area - kBrickedLayerHeaderSize - header.index_bytes);
  }
};

// A margin of `factor` x r grid steps and a little more, or the whole grid.
int64_t margin(double r, double factor, int qbits) {
  const double m = std::ceil(factor * r) + 2;
  const double whole = std::ldexp(1.0, qbits + 1);
  return static_cast<int64_t>(std::isfinite(m) && m < whole ? m : whole);
}

}  // namespace

RegionMesh region_of(const ProgressiveDecoder& decoder, const GridBox& box) {
  RegionMesh out;
  out.level = decoder.finest_level();
  const auto& points = decoder.points();
  std::vector<std::array<uint32_t, 4>> cells;
  std::vector<uint8_t> cell_regions;
  out.regions = decoder.regions();
  const ProgressiveDecoder::LevelCells level = decoder.level_cells();
  // Level 0's cell data, in the canonical order of the kept cells.
  const std::vector<FieldValues> all_values = decoder.mesh_status().ok()
                                                  ? decoder.cell_data(level.mesh, level.kept, level.order)
                                                  : std::vector<FieldValues>{};
  std::vector<FieldValues> cell_values = empty_like(all_values);
  if (decoder.mesh_status().ok()) {
    size_t k = 0;  // the cell's place among the kept ones
    for (uint32_t c : level.order) {
      if (!level.kept[c]) continue;
      if (cell_meets(points, level.mesh.cells[c], box)) {
        cells.push_back(level.mesh.cells[c]);
        if (!out.regions.empty()) cell_regions.push_back(level.kept[c]);
        append_cell(all_values, k, cell_values);
      }
      ++k;
    }
  }
  std::vector<uint32_t> ids(points.size());
  std::iota(ids.begin(), ids.end(), 0u);
  // With the input's numbering (flag vertex_order, level 0), a vertex's id is
  // its number there, as the whole level is written.
  if (decoder.mesh_status().ok() && (decoder.header().flags & kFlagVertexOrder) && out.level == 0) {
    const std::vector<uint32_t> numbering = decoder.vertex_order(level.mesh);
    if (numbering.size() == ids.size())
      for (uint32_t k = 0; k < numbering.size(); ++k) ids[numbering[k]] = k;
  }
  // The tagged faces of those cells.
  TaggedFaces faces;
  if (decoder.mesh_status().ok() && (decoder.header().flags & kFlagFaces)) {
    out.face_tags = decoder.face_tag_table();
    SurfaceFaces surface;
    const std::vector<uint8_t> tag = decoder.face_tags(level.mesh, level.kept, surface);
    for (size_t f = 0; f < tag.size(); ++f)
      if (tag[f] > 1 && cell_meets(points, level.mesh.cells[surface.faces[f].cell], box)) {
        faces.faces.push_back(
            outward_triangle(level.mesh, points, {surface.faces[f].cell, surface.faces[f].opposite}));
        faces.labels.push_back(tag[f]);
      }
  }
  compact(points, ids, decoder.vertex_levels(), decoder.fields(), std::move(cells), std::move(cell_regions),
          cell_values, std::move(faces), out);
  out.points_decoded = points.size();
  return out;
}

namespace {

// The stream's header and every layer's header and index down to a level,
// read by offset.
struct StreamPlan {
  StreamHeader header;
  std::vector<FieldDescription> fields;       // with flag values: the field table
  std::vector<RegionLabel> regions;           // with flag regions: the region table
  std::vector<RegionLabel> face_tags;         // with flag faces (17.0): the face tag table
  std::vector<FieldDescription> cell_fields;  // with flag cell_data: the cell field table
  uint64_t table_bytes = 0;                   // the tables' (where the first layer starts)
  std::vector<LayerPlan> layers;              // coarsest first; the last is the level's
};

class Reader {
 public:
  explicit Reader(ByteSource& source) : source_(source) {}
  uint64_t bytes_read = 0;
  Status read(uint64_t offset, uint64_t size, std::vector<uint8_t>& bytes, const std::string& what) {
    if (offset > source_.size() || size > source_.size() - offset)
      return {StatusCode::kTruncated,
              "the stream ends at byte " + std::to_string(source_.size()) + ", before " + what};
    bytes.resize(size);
    bytes_read += size;
    return source_.read(offset, bytes);
  }
  ByteSource& source() { return source_; }

 private:
  ByteSource& source_;
};

// The stream's header, and the level checked against it.
Status read_header(Reader& reader, int level, StreamHeader& header) {
  std::vector<uint8_t> bytes;
  DTM_RETURN_IF_ERROR(
      reader.read(0, std::min<uint64_t>(kHeaderSize, reader.source().size()), bytes, "the header's end"));
  if (const Status s = parse_header(bytes, header); !s.ok())
    return s.code() == StatusCode::kNeedMoreInput
               ? Status{StatusCode::kTruncated, "the stream ends in its header"}
               : s;
  if (level < 0 || level >= header.level_count)
    return {StatusCode::kInvalidInput, "level " + std::to_string(level) +
                                           " asked, the stream has levels 0 to " +
                                           std::to_string(header.level_count - 1)};
  return Status::Ok();
}

// A table after the header and the tables before it (plan.table_bytes):
// its length, then all of it, which `max_bytes` bounds; `parse` reads it
// (its whole size returned through `consumed`), and the plan's table bytes
// grow by it.
template <class Parse>
Status read_framed_table(Reader& reader, StreamPlan& plan, const std::string& name, uint64_t max_bytes,
                         Parse&& parse) {
  const uint64_t at = kHeaderSize + plan.table_bytes;
  std::vector<uint8_t> bytes;
  DTM_RETURN_IF_ERROR(reader.read(at, 4, bytes, "the " + name + "'s length"));
  const uint64_t length = bytes[0] | (bytes[1] << 8) | (bytes[2] << 16) | (uint64_t{bytes[3]} << 24);
  if (length > max_bytes) return {StatusCode::kCorrupt, name + ": longer than any table can be"};
  std::vector<uint8_t> rest;
  DTM_RETURN_IF_ERROR(reader.read(at + 4, length + 8, rest, "the " + name + "'s end"));
  bytes.insert(bytes.end(), rest.begin(), rest.end());
  size_t consumed = 0;
  DTM_RETURN_IF_ERROR(parse(bytes, consumed));
  plan.table_bytes += consumed;
  return Status::Ok();
}

Status read_plan(Reader& reader, int level, const DecoderOptions& options, StreamPlan& plan) {
  const int q = plan.header.grid.qbits;
  std::vector<uint8_t> bytes;
  // The field table (flag values), the region table (flag regions), the
  // face tag table (flag faces, 17.0), then the cell field table (flag
  // cell_data, 16.0).
  if (plan.header.flags & kFlagValues)
    DTM_RETURN_IF_ERROR(read_framed_table(reader, plan, "field table", uint64_t{1} << 20,
                                          [&](std::span<const uint8_t> b, size_t& consumed) {
                                            return parse_field_table(b, plan.fields, consumed);
                                          }));
  if (plan.header.flags & kFlagRegions)
    DTM_RETURN_IF_ERROR(read_framed_table(reader, plan, "region table", uint64_t{1} << 16,
                                          [&](std::span<const uint8_t> b, size_t& consumed) {
                                            return parse_region_table(b, plan.regions, consumed);
                                          }));
  if (plan.header.flags & kFlagFaces)
    DTM_RETURN_IF_ERROR(read_framed_table(
        reader, plan, "face tag table", uint64_t{1} << 16, [&](std::span<const uint8_t> b, size_t& consumed) {
          const Status s = parse_region_table(b, plan.face_tags, consumed);
          if (s.ok() && plan.face_tags.size() > kMaxFaceTags)
            return Status{StatusCode::kCorrupt,
                          "face tag table: more than " + std::to_string(kMaxFaceTags) + " tags"};
          return s.with_context("face tags");
        }));
  if (plan.header.flags & kFlagCellData)
    DTM_RETURN_IF_ERROR(read_framed_table(reader, plan, "cell field table", uint64_t{1} << 20,
                                          [&](std::span<const uint8_t> b, size_t& consumed) {
                                            return parse_field_table(b, plan.cell_fields, consumed);
                                          }));
  LayerWalk walk(plan.header, options.max_vertices, plan.table_bytes);
  while (walk.next_level() >= level) {
    const int at = walk.next_level();
    const uint64_t offset = walk.offset();
    const LayerWalk at_layer = walk;  // (next_index() moves past the layer)
    const std::string what = "level " + std::to_string(at) + "'s layer";
    Layer layer;
    bool header_seen = false;
    uint64_t want = kBrickedLayerHeaderSize;
    Status s;
    // The source is the whole input: a length that runs past its end may be
    // damage, not a cut stream. The layer's checksum covers its header and
    // index: what is read to tell is the header and the index that each
    // length's damage would leave (the index as given, or what is left
    // before the chunks at the stream's end), never the chunks.
    const auto cut_or_damaged = [&](Status cut, const LayerHeader& h) -> Status {
      const uint64_t size = reader.source().size();
      if (cut.code() != StatusCode::kTruncated || offset + kBrickedLayerHeaderSize > size) return cut;
      const uint64_t after = size - offset - kBrickedLayerHeaderSize;
      const uint64_t index = std::max<uint64_t>(h.index_bytes <= after ? h.index_bytes : 0,
                                                h.chunk_bytes <= after ? after - h.chunk_bytes : 0);
      std::vector<uint8_t> head(kBrickedLayerHeaderSize + index);
      DTM_RETURN_IF_ERROR(reader.source().read(offset, head));
      DTM_RETURN_IF_ERROR(at_layer.overshoot_is_damage(head, size - offset));
      return cut;
    };
    while (true) {
      if (Status read = reader.read(offset, want, bytes, what); !read.ok())
        return header_seen ? cut_or_damaged(read, layer.header) : read;
      s = walk.next_index(bytes, layer, &header_seen);
      if (s.code() != StatusCode::kNeedMoreInput || !header_seen) break;
      const uint64_t whole = kBrickedLayerHeaderSize + uint64_t{layer.header.index_bytes};
      if (whole <= want) break;
      reader.bytes_read -= want;  // read again with the index (counted once)
      want = whole;
    }
    DTM_RETURN_IF_ERROR(s);
    LayerPlan p;
    p.header = layer.header;
    p.chunk_area = offset + kBrickedLayerHeaderSize + layer.header.index_bytes;
    p.first_vertex = layer.header.level_vertices - layer.header.new_vertices;
    DTM_RETURN_IF_ERROR(parse_brick_index(layer.index, layer.header.brick_depth, q, layer.header.new_vertices,
                                          layer.header.chunk_bytes, plan.header.flags, layer.header.level,
                                          p.chunks)
                            .with_context(what + " at byte " + std::to_string(offset)));
    // A layer the stream cuts is not there for any region or piece, whichever
    // chunks it reads: the levels a prefix holds are its whole layers', as for
    // the whole decoder (and every piece of a cut stream finds the same).
    const uint64_t size = reader.source().size();
    // (A damaged chunk_bytes fails the checksum next_index() checked: a cut.)
    if (p.chunk_area > size || layer.header.chunk_bytes > size - p.chunk_area)
      return {StatusCode::kTruncated,
              "the stream ends at byte " + std::to_string(size) + ", before the end of " + what};
    plan.layers.push_back(std::move(p));
  }
  // Past level 0, the last layer, bytes are refused as the whole decoder
  // refuses them (spec/FORMAT.md §4), whichever chunks a region reads.
  if (walk.done() && reader.source().size() > walk.offset())
    return {StatusCode::kCorrupt,
            "trailing data after the last layer, which ends at byte " + std::to_string(walk.offset())};
  return Status::Ok();
}

// A region or piece without cells still has the level's arrays, empty:
// the points' fields, the region table, level 0's cell fields.
void declare_arrays(const StreamPlan& plan, int level, RegionMesh& out) {
  for (const FieldDescription& f : plan.fields) out.fields.push_back({f, {}});
  if (plan.header.flags & kFlagRegions) out.regions = plan.regions;
  if (plan.header.flags & kFlagFaces) out.face_tags = plan.face_tags;
  if (level == 0)
    for (const FieldDescription& f : plan.cell_fields) out.cell_fields.push_back({f, {}});
}

bool meets_any(const GridBox& a, std::span<const GridBox> boxes) {
  return std::any_of(boxes.begin(), boxes.end(), [&](const GridBox& b) { return a.meets(b); });
}

// The level's bricks whose cells are wanted: those inside `cubes` (a union
// of whole bricks), as `owns` says brick by brick.
struct Owners {
  std::vector<GridBox> cubes;
  std::function<bool(uint64_t)> owns;
};

// The cells of the level that `owners` own (and, with `box`, that meet it),
// from the chunks within twice the level's kept radius of the owners.
Status decode_owned(Reader& reader, const StreamPlan& plan, const Owners& owners, const GridBox* box,
                    const DecoderOptions& options, RegionMesh& out) {
  const int q = plan.header.grid.qbits;
  const LayerPlan& finest = plan.layers.back();
  const int level = finest.header.level;
  const double r = finest.header.kept_radius;
  // Where the level's points are needed (the owners grown by 2r), then, layer
  // by layer towards the coarsest, also the bricks of the chunks decoded
  // there (their known points): a chunk is read if its brick meets the region
  // or a brick chosen in a finer layer.
  std::vector<GridBox> region;
  for (const GridBox& c : owners.cubes) region.push_back(c.grown(margin(r, 2, q), q));
  std::vector<std::vector<const BrickChunk*>> needed(plan.layers.size());
  // The bricks of the chunks chosen in the finer layers, by depth.
  std::vector<std::pair<int, std::vector<uint64_t>>> chosen;
  const auto meets_chosen = [&](uint64_t brick, int depth) {
    for (const auto& [d, bricks] : chosen) {
      if (d >= depth) {  // a finer brick inside this one
        const auto it = std::lower_bound(bricks.begin(), bricks.end(), brick << (3 * (d - depth)));
        if (it != bricks.end() && (*it >> (3 * (d - depth))) == brick) return true;
      } else if (std::binary_search(bricks.begin(), bricks.end(), brick >> (3 * (depth - d)))) {
        return true;  // inside a coarser brick
      }
    }
    return false;
  };
  for (size_t i = plan.layers.size(); i-- > 0;) {
    const LayerPlan& p = plan.layers[i];
    const int depth = p.header.brick_depth;
    std::vector<uint64_t> bricks;
    for (const BrickChunk& c : p.chunks)
      if (meets_any(brick_box(c.brick, q, depth), region) || meets_chosen(c.brick, depth))
        needed[i].push_back(&c), bricks.push_back(c.brick);
    chosen.emplace_back(depth, std::move(bricks));
  }

  // The points, coarsest layer first.
  std::vector<GridPoint> points;
  std::vector<uint32_t> ids;
  std::vector<int32_t> levels;
  std::vector<MortonCode> known;
  std::vector<FieldValues> values, layer_values;  // of `points`, per field
  for (const FieldDescription& f : plan.fields) values.push_back({f, {}});
  SetCoderModels models;
  models.enable_coordinate_reuse(q);
  std::vector<uint8_t> finest_chunks;
  std::vector<std::pair<const BrickChunk*, uint64_t>> finest_read;  // chunk, its place in finest_chunks
  for (size_t i = 0; i < plan.layers.size(); ++i) {
    const LayerPlan& p = plan.layers[i];
    const int at = p.header.level;
    // The layer's chunks read one after another, then checked and decoded
    // as the whole decoder does (each decodes exactly its index's points).
    std::vector<std::vector<uint8_t>> chunk_bytes(needed[i].size());
    std::vector<ChunkInput> inputs;
    for (size_t k = 0; k < needed[i].size(); ++k) {
      const BrickChunk& chunk = *needed[i][k];
      // (Level 0's cell values only of the owners' chunks: the others are
      // read for their points, and checked without them, §3.5.)
      const bool whole = i + 1 == plan.layers.size() && owners.owns(chunk.brick);
      DTM_RETURN_IF_ERROR(
          reader.read(p.chunk_area + chunk.offset, whole ? chunk.size() : chunk.points_size(), chunk_bytes[k],
                      "level " + std::to_string(at) + ", brick " + std::to_string(chunk.brick)));
      inputs.push_back({&chunk, chunk_bytes[k], p.chunk_area + chunk.offset});
      for (uint32_t n = 0; n < chunk.new_points; ++n) {
        ids.push_back(static_cast<uint32_t>(p.first_vertex + chunk.points_before + n));
        levels.push_back(at);
      }
    }
    out.chunks_read += inputs.size();
    std::vector<GridPoint> added;
    DTM_RETURN_IF_ERROR(
        decode_bricked_points(inputs, known, q, p.header.brick_depth, models, added).with_context(p.where()));
    if (i + 1 == plan.layers.size())
      for (size_t k = 0; k < inputs.size(); ++k) {
        finest_read.emplace_back(inputs[k].chunk, finest_chunks.size());
        finest_chunks.insert(finest_chunks.end(), chunk_bytes[k].begin(), chunk_bytes[k].end());
      }
    if (!plan.fields.empty()) {
      // (The decoder's value limit, as the whole decode's.)
      uint64_t components = 0;
      for (const FieldDescription& f : plan.fields) components += static_cast<uint64_t>(f.components);
      const uint64_t count = points.size() + added.size();
      if (count * components > options.max_values)
        return {StatusCode::kLimitExceeded,
                p.where() + ": " + std::to_string(count) + " vertices of " + std::to_string(components) +
                    " values each exceed the limit of " + std::to_string(options.max_values) + " values"};
      DTM_RETURN_IF_ERROR(decode_bricked_values(inputs, q, p.header.brick_depth, plan.fields, points, values,
                                                added, layer_values)
                              .with_context(p.where()));
      for (size_t f = 0; f < values.size(); ++f)
        values[f].bits.insert(values[f].bits.end(), layer_values[f].bits.begin(), layer_values[f].bits.end());
    }
    merge_known(known, added, q);
    points.insert(points.end(), added.begin(), added.end());
    if (uint64_t{points.size()} > options.max_vertices)
      return {StatusCode::kLimitExceeded, std::to_string(points.size()) + " vertices exceed the limit of " +
                                              std::to_string(options.max_vertices)};
  }
  out.points_decoded = points.size();

  // The level's points in the region, numbered as the whole level numbers
  // them (the canonical order of cells is then the whole level's),
  // tetrahedralized.
  std::vector<uint32_t> inside;
  for (uint32_t v = 0; v < points.size(); ++v)
    if (std::any_of(region.begin(), region.end(), [&](const GridBox& b) { return b.contains(points[v]); }))
      inside.push_back(v);
  std::sort(inside.begin(), inside.end(), [&](uint32_t a, uint32_t b) { return ids[a] < ids[b]; });
  std::vector<GridPoint> local_points;
  std::vector<uint32_t> local_ids;
  std::vector<int32_t> local_levels;
  std::vector<FieldValues> local_values;
  local_values.reserve(values.size());
  for (const FieldValues& f : values) local_values.push_back({f.description, {}});
  for (uint32_t v : inside) {
    local_points.push_back(points[v]);
    local_ids.push_back(ids[v]);
    local_levels.push_back(levels[v]);
    for (size_t f = 0; f < values.size(); ++f) {
      const size_t n = static_cast<size_t>(values[f].description.components);
      const auto first = values[f].bits.begin() + static_cast<std::ptrdiff_t>(v * n);
      local_values[f].bits.insert(local_values[f].bits.end(), first, first + static_cast<std::ptrdiff_t>(n));
    }
  }
  if (!spans_three_dimensions(local_points)) {  // no cell at all: the arrays, empty
    declare_arrays(plan, level, out);
    return Status::Ok();
  }
  if (plan.header.flags & kFlagRegions) out.regions = plan.regions;
  if (plan.header.flags & kFlagFaces) out.face_tags = plan.face_tags;
  DTM_ASSIGN_OR_RETURN(TetMesh dt, delaunay_tetrahedralize(local_points));

  // Each cell's owner brick; the carving of the owners' chunks.
  const int depth = finest.header.brick_depth;
  std::vector<MortonCode> codes(local_points.size());
  for (size_t v = 0; v < codes.size(); ++v) codes[v] = morton_encode(local_points[v], q);
  const std::vector<uint64_t> owner = carving_bricks_of_cells(dt, local_points, codes, q, depth, r);
  std::vector<uint8_t> kept, cell_regions;
  std::vector<FieldValues> cell_values;  // per owned kept cell of dt (ascending), with cell data
  std::vector<uint32_t> cell_slot;       // each owned kept cell's place in cell_values
  std::vector<uint8_t> face_label;       // per cell of dt x 4 + corner: its face's tag, with tagged faces
  if (plan.header.flags & kFlagCarvingCorrections) {
    // The owners' chunks' sections that `part` picks.
    const auto owned_sections = [&](std::span<const uint8_t> ChunkBytes::*part) {
      std::vector<std::span<const uint8_t>> sections;
      for (const auto& [chunk, at] : finest_read)
        if (owners.owns(chunk->brick))
          sections.push_back(
              split_chunk(*chunk, std::span<const uint8_t>(finest_chunks).subspan(at, chunk->size())).*part);
      return sections;
    };
    std::vector<uint64_t> section_bricks;
    for (const auto& [chunk, at] : finest_read)
      if (owners.owns(chunk->brick)) section_bricks.push_back(chunk->brick);
    std::vector<uint32_t> chunk_of_cell(owner.size(), kNoCarvingChunk);
    for (size_t c = 0; c < owner.size(); ++c) {
      const auto it = std::lower_bound(section_bricks.begin(), section_bricks.end(), owner[c]);
      if (owner[c] != kNoBrick && it != section_bricks.end() && *it == owner[c])
        chunk_of_cell[c] = static_cast<uint32_t>(it - section_bricks.begin());
    }
    ChunkCells chunks;
    DTM_RETURN_IF_ERROR(decode_carving_chunks(owned_sections(&ChunkBytes::carving), dt, local_points,
                                              finest.header.alpha, chunk_of_cell, morton_ranks(codes), kept,
                                              nullptr, &chunks)
                            .with_context(finest.where()));
    // Only the owners' cells' regions and values are decoded (the others
    // are some other region's or piece's: their bricks' chunks were not all
    // read).
    std::vector<uint8_t> owned = kept;
    for (size_t c = 0; c < owned.size(); ++c)
      if (chunk_of_cell[c] == kNoCarvingChunk && !(owner[c] != kNoBrick && owners.owns(owner[c])))
        owned[c] = 0;
    // (16.0) Level 0's cell values, from the same chunks (as many as the
    // decoder's value limit allows).
    if (level == 0 && (plan.header.flags & kFlagCellData)) {
      uint64_t components = 0, cells = 0;
      for (const FieldDescription& f : plan.cell_fields) components += static_cast<uint64_t>(f.components);
      cell_slot = kept_cell_slots(owned, cells);
      if (cells * components > options.max_values)
        return {StatusCode::kLimitExceeded,
                std::to_string(cells) + " cells of " + std::to_string(components) +
                    " values each exceed the limit of " + std::to_string(options.max_values) + " values"};
      DTM_RETURN_IF_ERROR(decode_cell_value_chunks(plan.cell_fields, owned_sections(&ChunkBytes::cell_values),
                                                   dt, local_points, chunks, chunk_of_cell, owned,
                                                   cell_values)
                              .with_context(finest.where()));
    }
    // (15.0) The owners' cells' regions, from the same chunks.
    if (plan.header.flags & kFlagRegions) {
      DTM_RETURN_IF_ERROR(decode_region_chunks(owned_sections(&ChunkBytes::regions), dt, chunks,
                                               chunk_of_cell, plan.regions.size(), owned)
                              .with_context(finest.where()));
    }
    // (17.0) The owners' cells' faces' tags, from the same chunks.
    if (plan.header.flags & kFlagFaces) {
      const ChunkFaces faces = chunk_faces(dt, chunks, chunk_of_cell, owned, morton_ranks(codes));
      std::vector<uint8_t> label;
      DTM_RETURN_IF_ERROR(
          decode_face_chunks(owned_sections(&ChunkBytes::faces), faces, plan.face_tags.size(), label)
              .with_context(finest.where()));
      face_label.assign(dt.cells.size() * 4, 1);
      for (size_t f = 0; f < faces.faces.size(); ++f) {
        const SurfaceFace& face = faces.faces[f];
        // A tag where the cell across is another owner's kept cell of a
        // region not above this one's: the surface does not take the face
        // from this cell (§3.5; the whole decoder refuses it too).
        const int32_t n = dt.neighbors[face.cell][face.opposite];
        if (label[f] > 1 && n >= 0 && chunk_of_cell[static_cast<size_t>(n)] != kNoCarvingChunk &&
            !surface_takes_face(owned[face.cell], owned[static_cast<size_t>(n)]))
          return Status{StatusCode::kCorrupt,
                        "a tag on a face that the level's surface does not take from its chunk"}
              .with_context(finest.where());
        face_label[size_t{face.cell} * 4 + face.opposite] = label[f];
      }
    }
    if (plan.header.flags & kFlagRegions) cell_regions = std::move(owned);
  } else {
    kept = carve(dt, local_points, finest.header.alpha);
  }
  std::vector<std::array<uint32_t, 4>> cells;
  std::vector<uint8_t> regions_of_cells;
  std::vector<FieldValues> values_of_cells = empty_like(cell_values);
  TaggedFaces faces;
  for (size_t c = 0; c < dt.cells.size(); ++c)
    if (kept[c] && owner[c] != kNoBrick && owners.owns(owner[c]) &&
        (!box || cell_meets(local_points, dt.cells[c], *box))) {
      cells.push_back(dt.cells[c]);
      if (!cell_regions.empty()) regions_of_cells.push_back(cell_regions[c]);
      if (!cell_values.empty()) append_cell(cell_values, cell_slot[c], values_of_cells);
      for (uint8_t k = 0; k < 4 && !face_label.empty(); ++k)
        if (face_label[c * 4 + k] > 1) {
          faces.faces.push_back(outward_triangle(dt, local_points, {static_cast<uint32_t>(c), k}));
          faces.labels.push_back(face_label[c * 4 + k]);
        }
    }
  compact(local_points, local_ids, local_levels, local_values, std::move(cells), std::move(regions_of_cells),
          values_of_cells, std::move(faces), out);
  return Status::Ok();
}

// A stream that is not bricked: decoded whole to the level.
Status decode_whole(Reader& reader, int level, ProgressiveDecoder& decoder) {
  std::vector<uint8_t> bytes;
  reader.bytes_read = 0;
  DTM_RETURN_IF_ERROR(reader.read(0, reader.source().size(), bytes, "its end"));
  DTM_RETURN_IF_ERROR(decode_stream(bytes, decoder));
  if (decoder.finest_level() != level)
    return {StatusCode::kTruncated, "the stream ends before level " + std::to_string(level)};
  return decoder.mesh_status();
}

// The cubes (octree nodes) that bricks [first, last) of depth `depth` make.
std::vector<GridBox> morton_range_cubes(uint64_t first, uint64_t last, int qbits, int depth) {
  std::vector<GridBox> out;
  while (first < last) {
    int k = 0;  // the largest aligned node of 8^k bricks starting at first
    while (k < depth && first % (uint64_t{8} << (3 * k)) == 0 && first + (uint64_t{8} << (3 * k)) <= last)
      ++k;
    out.push_back(brick_box(first >> (3 * k), qbits, depth - k));
    first += uint64_t{1} << (3 * k);
  }
  return out;
}

}  // namespace

StatusOr<RegionMesh> decode_region(ByteSource& source, const GridBox& box, int level,
                                   const DecoderOptions& options) {
  Reader reader(source);
  StreamPlan plan;
  DTM_RETURN_IF_ERROR(read_header(reader, level, plan.header));
  RegionMesh out;
  out.level = level;
  if (!(plan.header.flags & kFlagBricks)) {
    DecoderOptions o = options;
    o.stop_after_level = level;
    ProgressiveDecoder decoder(o);
    DTM_RETURN_IF_ERROR(decode_whole(reader, level, decoder));
    out = region_of(decoder, box);
    // (Its carving, regions and numbering are decoded there: a damaged one
    // is an error, not an empty box.)
    DTM_RETURN_IF_ERROR(decoder.mesh_status());
    out.bytes_read = reader.bytes_read;
    return out;
  }
  out.bricked = true;
  DTM_RETURN_IF_ERROR(read_plan(reader, level, options, plan));
  const int q = plan.header.grid.qbits;
  const LayerHeader& lh = plan.layers.back().header;
  // The bricks that may own a kept cell meeting the box.
  GridBox cover;
  const std::vector<uint64_t> bricks =
      bricks_meeting(box.grown(margin(lh.kept_radius, 2, q), q), q, lh.brick_depth, &cover);
  if (!bricks.empty()) {
    Owners owners;
    owners.cubes = {cover};
    owners.owns = [&](uint64_t b) { return std::binary_search(bricks.begin(), bricks.end(), b); };
    DTM_RETURN_IF_ERROR(decode_owned(reader, plan, owners, &box, options, out));
  } else {  // no brick: no cell, but the level's arrays (empty)
    declare_arrays(plan, level, out);
  }
  out.bytes_read = reader.bytes_read;
  return out;
}

StatusOr<RegionMesh> decode_piece(ByteSource& source, int level, int piece, int pieces,
                                  const DecoderOptions& options) {
  if (pieces < 1 || piece < 0 || piece >= pieces)
    return Status{StatusCode::kInvalidInput,
                  "piece " + std::to_string(piece) + " of " + std::to_string(pieces) + ": no such piece"};
  Reader reader(source);
  StreamPlan plan;
  DTM_RETURN_IF_ERROR(read_header(reader, level, plan.header));
  if (!(plan.header.flags & kFlagBricks))
    return Status{StatusCode::kUnsupported, "pieces need a bricked stream (meshenc --bricks)"};
  RegionMesh out;
  out.level = level;
  out.bricked = true;
  DTM_RETURN_IF_ERROR(read_plan(reader, level, options, plan));
  const int q = plan.header.grid.qbits;
  const LayerPlan& finest = plan.layers.back();
  const int depth = finest.header.brick_depth;
  // Contiguous ranges of the level's bricks, cut between chunks so that each
  // piece has about as many of the level's new points.
  const std::vector<BrickChunk>& chunks = finest.chunks;
  const uint64_t total = finest.header.new_vertices;
  const auto cut = [&](int k) -> uint64_t {
    if (k == 0) return 0;
    if (k == pieces) return uint64_t{1} << (3 * depth);
    const uint64_t target = total * static_cast<uint64_t>(k) / static_cast<uint64_t>(pieces);
    for (const BrickChunk& c : chunks)
      if (c.points_before >= target) return c.brick;
    return uint64_t{1} << (3 * depth);
  };
  const uint64_t first = cut(piece), last = std::max(first, cut(piece + 1));
  if (first < last) {
    Owners owners;
    owners.cubes = morton_range_cubes(first, last, q, depth);
    owners.owns = [&](uint64_t b) { return b >= first && b < last; };
    DTM_RETURN_IF_ERROR(decode_owned(reader, plan, owners, nullptr, options, out));
  } else {  // no brick: no cell, but the level's arrays (empty)
    declare_arrays(plan, level, out);
  }
  out.bytes_read = reader.bytes_read;
  return out;
}

}  // namespace dtm
