// The carving corrections of one level (spec/FORMAT.md §3.2), encoder and
// decoder side by side. Alpha predicts which cells of DT(V_l) the level
// keeps (mesh/carving.h); the encoder knows the true verdicts (the reference
// solid's, spec/HIERARCHY.md §3) and sends, for every cell, whether the
// prediction is wrong, as an adaptive binary symbol. The cells are visited
// in a canonical order and the contexts use only what the decoder has: the
// cell's circumradius over alpha and its face neighbours: from 6.0 the
// verdicts of those already decoded (a wrong prediction comes in patches
// along the surface: research/carving_models measured 10-45% fewer bits on the
// corpus than 4.0's contexts, which count the neighbours alpha keeps). Each
// level's section is coded alone (fresh models), so a decoder reads the
// sections of the levels it shows and no other.
#pragma once

#include <array>
#include <cstdint>
#include <span>
#include <utility>
#include <vector>

#include "common/grid.h"
#include "common/status.h"
#include "mesh/delaunay.h"

namespace dtm {

// The contexts a section is coded with (spec/FORMAT.md §3.2).
enum class CarvingContexts {
  // 4.0 and 5.0: the circumradius bucket and how many face neighbours alpha
  // keeps (80 models).
  kAlphaNeighbours,
  // 6.0: the half-octave bucket, how many face neighbours are kept (their
  // decoded verdict where decoded already, alpha's otherwise) and how many
  // of the decoded ones alpha got wrong, 0, 1 or 2+ (120 models).
  kDecodedNeighbours,
  // 11.0, level 0 of an exact stream (exact_cell_coder.h): 6.0's, each
  // split by the cell's Delaunay margin (480 models). There the carving
  // keeps the Delaunay cells that are input cells; those that are not lie
  // where the mesher moved off Delaunay, where a neighbour's far corner
  // is nearly on the cell's circumsphere (on the Netgen part of
  // bench/results/EXACT.md, a median margin of 0.087 against 0.305).
  kExactMargin,
  // 12.0, level 0 of an exact stream: 11.0's, each split by the cell's
  // shape (1440 models). A mesher's optimiser flips its flattest Delaunay
  // cells away: on hand_10k the cells alpha got wrong have a median
  // quality of 0.45, the kept ones it got right 0.76.
  kExactMarginShape,
  // 13.0, level 0 of an exact stream: 12.0's, each split by whether the
  // cell is one of three around an edge whose 3-2 flip raises their least
  // quality (2880 models; flip_bucket()). Netgen's and gmsh's optimisers
  // remove such edges: on the Netgen part of bench/results/EXACT.md, 82% of
  // the Delaunay cells alpha keeps that are not input cells are such cells,
  // 3% of those that are. (14.0 goes back to 12.0's: its exact cell
  // section flags the flips themselves.)
  kExactMarginShapeFlip,
};
CarvingContexts carving_contexts(uint8_t format_major);
// Level 0 of an exact stream's (flag exact, 11.0 and later).
CarvingContexts exact_carving_contexts(uint8_t format_major);

// Per cell of `dt` (vertex ids index `points`): alpha's verdict and what
// the context of its correction starts from; and the canonical order of the
// cells (each cell's ids ascending, cells ascending).
struct CarvingPrediction {
  std::vector<uint8_t> kept;  // per cell: alpha keeps it
  // Per cell, the context from alpha's verdicts alone: 4.0's whole context
  // (the circumradius bucket, < kCarvingRatioBuckets, and the kept
  // neighbours: < kAlphaNeighbourContexts); 6.0's half-octave bucket and kept
  // neighbours, which the decoded verdicts then change.
  std::vector<uint8_t> context;
  std::vector<uint32_t> order;  // cell indices in coding order
  // kExactMargin: per cell, its margin bucket; kExactMarginShape: that
  // times kShapeBuckets plus its shape bucket; kExactMarginShapeFlip: that
  // times 2 plus its flip bucket.
  std::vector<uint8_t> margin;
};
inline constexpr int kCarvingRatioBuckets = 16;
inline constexpr int kAlphaNeighbourContexts = kCarvingRatioBuckets * 5;
inline constexpr int kDecodedNeighbourContexts = kCarvingRatioBuckets / 2 * 5 * 3;
// A cell's Delaunay margin: over its face neighbours, the least
// |p - centre|^2 / R^2 - 1 of the neighbour's corner p across the face (0 on
// the circumsphere; +infinity with no neighbour), in buckets split at these
// values (spec/FORMAT.md §3.2).
inline constexpr double kMarginSteps[] = {0.06, 0.17, 0.39};
inline constexpr int kMarginBuckets = 4;
inline constexpr int kExactMarginContexts = kDecodedNeighbourContexts * kMarginBuckets;
uint8_t margin_bucket(const TetMesh& dt, std::span<const GridPoint> points, size_t cell);
// A cell's shape: its quality 6 sqrt(2) V / l^3 (V its volume, l its edges'
// root mean square length; 1 for the regular tetrahedron, 0 flat) above
// none, one or both of these values, decided exactly (spec/FORMAT.md §3.2).
inline constexpr double kShapeSteps[] = {0.05, 0.2};
inline constexpr int kShapeBuckets = 3;
inline constexpr int kExactMarginShapeContexts = kExactMarginContexts * kShapeBuckets;
uint8_t shape_bucket(const std::array<GridPoint, 4>& corners);
// 1 when the cell is one of the three cells around an edge of dt (no other
// cell has it) whose 3-2 flip, the three replaced by the two through the
// triangle of their other corners, is valid and raises their least quality
// (D^2 / S^3 in binary64, D = 6V and S the sum of the squared edge lengths,
// exact integers rounded once); else 0 (spec/FORMAT.md §3.2).
inline constexpr int kFlipBuckets = 2;
// D^2 / S^3 of a tetrahedron in binary64 (spec/FORMAT.md §3.2): its quality
// 6 sqrt(2) V / l^3 squared, over 7776, the same in any order of its
// corners (exact integers, each rounded once).
double squared_quality(const GridPoint& a, const GridPoint& b, const GridPoint& c, const GridPoint& d);
uint8_t flip_bucket(const TetMesh& dt, std::span<const GridPoint> points, size_t cell);
// The pairs (x, y) of a cell's corners, in this order, with its other two
// corners the edge; and per pair j, bit j of valid_flips(): the cell is one
// of the three around that edge (the neighbours across the faces opposite x
// and y have the same corner far[x] = far[y] the cell lacks) and the edge's
// 3-2 flip is valid (it crosses the triangle x, y, far[x]). `far[k]`: that
// corner of the neighbour across the face opposite k (UINT32_MAX: none).
inline constexpr std::array<std::pair<size_t, size_t>, 6> kCornerPairs = {
    {{0, 1}, {0, 2}, {0, 3}, {1, 2}, {1, 3}, {2, 3}}};
uint8_t valid_flips(const TetMesh& dt, std::span<const GridPoint> points, size_t cell,
                    std::array<uint32_t, 4>& far);
// With `chunk_of_cell` (bricked layers), the kept neighbours counted are
// those of the same chunk only.
CarvingPrediction predict_carving(const TetMesh& dt, std::span<const GridPoint> points, double alpha,
                                  CarvingContexts contexts, std::span<const uint32_t> chunk_of_cell = {});

// The section for true verdicts `kept` (per cell of dt); empty when alpha's
// prediction is right everywhere.
std::vector<uint8_t> encode_carving(const TetMesh& dt, std::span<const GridPoint> points, double alpha,
                                    std::span<const uint8_t> kept, CarvingContexts contexts);

// The level's verdicts, per cell of dt, from its section (empty: alpha's).
// kCorrupt if the section ends before its last symbol or has bytes after it.
// `order`, if given, receives the canonical order of dt's cells (computed on
// the way: the order the section codes them in).
Status decode_carving(std::span<const uint8_t> section, const TetMesh& dt, std::span<const GridPoint> points,
                      double alpha, CarvingContexts contexts, std::vector<uint8_t>& kept,
                      std::vector<uint32_t>* order = nullptr);

// Bricked layers (8.0, codec/bricks/bricks.h): the corrections in chunks.
// `chunk_of_cell`: per cell of dt, the chunk whose section codes its bit, or
// kNoCarvingChunk (no bit: alpha's verdict stands). Each chunk visits its
// own cells in canonical order with fresh 6.0 models, and its contexts see
// only the face neighbours of the same chunk (another chunk's count as not
// kept): chunks decode independently, on every core, and a region reader
// needs, for a chunk, only the cells whose circumspheres reach its brick.
// A chunk visits its cells by `vertex_rank` (per vertex of dt: its rank in
// the level's Morton order, codec/bricks/bricks.h's morton_ranks) instead of by
// vertex number: an order of places, which a block of the encoder knows
// before the coarser levels that number the vertices are built.
inline constexpr uint32_t kNoCarvingChunk = UINT32_MAX;
// The cells of each chunk in its coding order: cells[first[i] ..
// first[i + 1]) are chunk i's (a bricked layer's region sections visit
// them in this order too, region_coder.h).
struct ChunkCells {
  std::vector<uint32_t> cells, first;
};
ChunkCells chunk_cells(const TetMesh& dt, std::span<const uint32_t> chunk_of_cell, size_t chunk_count,
                       std::span<const uint32_t> vertex_rank);
// `cells`: chunk_cells() of chunk_of_cell (made once where the region
// sections visit them too).
std::vector<std::vector<uint8_t>> encode_carving_chunks(const TetMesh& dt, std::span<const GridPoint> points,
                                                        double alpha, std::span<const uint8_t> kept,
                                                        std::span<const uint32_t> chunk_of_cell,
                                                        const ChunkCells& cells);
// `sections[i]`: chunk i's section (empty: no correction). kCorrupt names
// the chunk (its index) whose section does not end where its bytes do.
// `order`, if given, receives the canonical order of dt's cells (by vertex
// number, as decode_carving's); `cells`, if given, the chunks' cells
// (chunk_cells()).
Status decode_carving_chunks(std::span<const std::span<const uint8_t>> sections, const TetMesh& dt,
                             std::span<const GridPoint> points, double alpha,
                             std::span<const uint32_t> chunk_of_cell, std::span<const uint32_t> vertex_rank,
                             std::vector<uint8_t>& kept, std::vector<uint32_t>* order = nullptr,
                             ChunkCells* cells = nullptr);

}  // namespace dtm
