// A region of one level, decoded from the chunks around it (spec/FORMAT.md
// §4.1). A bricked stream (8.0) is read by offset: the header, every
// layer's header and index, and only the chunks of the bricks the region
// needs; the result is exactly the level's cells that meet the box, with
// their vertices' numbers in the whole level. A stream that is not bricked
// is read whole and its level filtered to the box (the same result, every
// byte read).
//
// Why the chunks around the box suffice: a kept cell's circumradius is at
// most its layer's kept_radius r, so a kept cell meeting the box has its
// vertex of least Morton code within 2r of it: the bricks that own such
// cells (their carving chunks) meet the box grown by 2r. Every cell such a
// brick owns, and every neighbour its contexts read (those of the same
// chunk), has its vertices and circumsphere within 2r of the brick. So with
// the points within 2r of the owner bricks decoded, each of those cells is
// a cell of their Delaunay tetrahedralization (its sphere is empty of all
// points, hence of these) and each such cell of theirs with a circumradius
// up to r is a cell of the whole level's (no point it lacks can lie in its
// sphere, and the symbolic perturbation depends on the points on the sphere
// only). Coarser layers are decoded where the finer ones need their points
// (their bricks cover those of the finer layer).
#pragma once

#include <array>
#include <cstdint>
#include <cstdio>
#include <span>
#include <string>
#include <vector>

#include "codec/bricks/bricks.h"
#include "codec/decode.h"
#include "codec/sections/region_coder.h"
#include "common/grid.h"
#include "common/status.h"

namespace dtm {

// Bytes by offset: a file (seeks) or memory.
class ByteSource {
 public:
  virtual ~ByteSource() = default;
  virtual uint64_t size() const = 0;
  // Reads out.size() bytes at `offset`; kTruncated if the source ends first.
  virtual Status read(uint64_t offset, std::span<uint8_t> out) = 0;
};

class MemorySource : public ByteSource {
 public:
  explicit MemorySource(std::span<const uint8_t> bytes) : bytes_(bytes) {}
  uint64_t size() const override { return bytes_.size(); }
  Status read(uint64_t offset, std::span<uint8_t> out) override;

 private:
  std::span<const uint8_t> bytes_;
};

class FileSource : public ByteSource {
 public:
  // kNotFound-style errors (kInvalidInput) name the file.
  static StatusOr<FileSource> open(const std::string& path);
  FileSource(FileSource&&) noexcept;
  FileSource& operator=(FileSource&&) noexcept;
  ~FileSource() override;
  uint64_t size() const override { return size_; }
  Status read(uint64_t offset, std::span<uint8_t> out) override;

 private:
  FileSource() = default;
  std::FILE* file_ = nullptr;
  uint64_t size_ = 0;
  std::string path_;
};

// One level's cells that meet a box: those whose bounding box (of grid
// points) meets it.
struct RegionMesh {
  int level = 0;
  std::vector<GridPoint> points;  // the cells' vertices, ascending vertex_ids
  // Each one's number in the whole level as it is written: its decoding
  // order, or with the input's numbering kept (level 0, flag vertex_order)
  // its number there.
  std::vector<uint32_t> vertex_ids;
  std::vector<int32_t> vertex_levels;  // each one's coarsest level
  // Indexing points; in the level's canonical order, each positively
  // oriented (mesh/geometry.h sorted_positive()).
  std::vector<std::array<uint32_t, 4>> cells;
  std::vector<FieldValues> fields;  // the points' values, per field (the stream's)
  // With regions (flag regions): the region table, and per cell 1 + the
  // index of its region in it.
  std::vector<RegionLabel> regions;
  std::vector<uint8_t> cell_regions;
  // At level 0 of a stream with cell data (flag cell_data): each array's
  // values, cell-major in the order of `cells`.
  std::vector<FieldValues> cell_fields;
  // With tagged faces (flag faces; bricked streams 17.0): the face tag
  // table, and the level's tagged surface faces of `cells` (indexing
  // points, turned out of their cell), each with 1 + its tag's index.
  std::vector<RegionLabel> face_tags;
  std::vector<std::array<uint32_t, 3>> faces;
  std::vector<uint8_t> face_labels;
  // What it took: bytes read from the source, chunks decoded, points decoded.
  uint64_t bytes_read = 0;
  uint64_t chunks_read = 0;
  uint64_t points_decoded = 0;
  bool bricked = false;  // false: the stream was decoded whole
};

// `box`: grid coordinates, bounds included. `level`: 0 the finest. Errors:
// those of the stream (kCorrupt naming the level and brick of a damaged
// chunk: only chunks the region reads are checked), kInvalidInput for a
// level the stream does not have.
StatusOr<RegionMesh> decode_region(ByteSource& source, const GridBox& box, int level,
                                   const DecoderOptions& options = {});

// Piece `piece` (0 to pieces - 1) of a level of a bricked stream: the cells
// whose owner bricks (the brick of their least-Morton vertex) lie in the
// piece's contiguous range of the level's bricks, the ranges cut between
// chunks so that each holds about as many of the level's new points. Every
// cell of the level is in exactly one piece; a piece reads only the chunks
// around its bricks (mpirun meshdec: one piece per rank). kUnsupported for
// a stream that is not bricked.
StatusOr<RegionMesh> decode_piece(ByteSource& source, int level, int piece, int pieces,
                                  const DecoderOptions& options = {});

// The same region from a decoder holding the level whole (its finest
// decoded level): the definition decode_region is tested against.
RegionMesh region_of(const ProgressiveDecoder& decoder, const GridBox& box);

// The grid points a box of the input's units holds: a cell's bounding box
// of grid points meets the world box exactly when it meets this one. A
// corner within 1e-6 steps of a grid point (a decoded vertex's coordinate,
// origin + k step in doubles) is on it.
GridBox grid_box_of(const Grid& grid, const std::array<double, 3>& lo, const std::array<double, 3>& hi);

// Whether the cell's bounding box (of its grid points) meets `box`: the
// cells a region holds.
bool cell_meets(std::span<const GridPoint> points, const std::array<uint32_t, 4>& cell, const GridBox& box);

}  // namespace dtm
