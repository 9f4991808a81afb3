// Per-cell arrays of level 0 (format 10.0, spec/FORMAT.md §2.4, §3.8):
// element results and material properties, encoder and decoder side by
// side. The cell field table (the field table's layout) follows the face
// tag table; level 0's layer alone carries a cell value section, coded as
// the vertex fields are (codec/sections/value_fields.h: lossless, or within
// a bound for floats), with each kept cell standing at its centroid: a
// cell's value is predicted from the nearest cells decoded before it, in
// the canonical order of the kept cells. Coarser levels carry none: their
// cells are not the input's, and a prefix of the stream is for seeing the
// shape (docs/VALUES.md says why).
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <span>
#include <vector>

#include "codec/sections/carving_coder.h"
#include "codec/sections/value_fields.h"
#include "common/grid.h"
#include "common/status.h"
#include "mesh/delaunay.h"

namespace dtm {

// Where each cell stands for the value coder's neighbour search: the sum of
// its four corners (four times its centroid, exact on the grid).
std::vector<GridPoint> cell_positions(std::span<const GridPoint> points,
                                      std::span<const std::array<uint32_t, 4>> cells);

// The encoder's side is a FieldSectionEncoder made from the kept cells'
// values (which sets the table's scales) coding one layer of the cells at
// cell_positions() in the canonical order (codec/expert_encode.cpp).

// The values of the cells at `positions`, one FieldValues per array of
// `fields`. kCorrupt if the section is damaged or does not end where its
// bytes do.
Status decode_cell_values(std::span<const FieldDescription> fields, std::span<const uint8_t> section,
                          std::span<const GridPoint> positions, std::vector<FieldValues>& out);

// Bricked streams (16.0, spec/FORMAT.md §3.5): each of level 0's chunks
// carries a cell value section for the kept cells its brick owns, in its
// carving section's order (`chunks`, chunk_cells()), coded as a chunk's
// point values are with nothing known: fresh models, and as neighbours only
// the chunk's earlier cells. So chunks code alone, and a region reader
// decodes those it reads.
//
// Encoder (cell_value_encoder.cpp): one section for each chunk, with bytes
// for each chunk owning a kept cell (`kept`, per cell of dt). `source_of`
// gives a kept cell's index into `values`' points (the input tetrahedron
// whose values it takes); `field_bytes` gains each field's share.
std::vector<std::vector<uint8_t>> encode_cell_value_chunks(
    const FieldSectionEncoder& values, const TetMesh& dt, std::span<const GridPoint> points,
    const ChunkCells& chunks, std::span<const uint8_t> kept,
    const std::function<uint32_t(uint32_t cell)>& source_of, std::vector<uint64_t>& field_bytes);
// Decoder: the values of the kept cells (`kept`, per cell of dt) from
// their chunks' sections, on every core: `out`, one FieldValues per field,
// cell-major over the kept cells in ascending index of dt (the memory the
// kept cells' count justifies, which the caller bounds). kCorrupt, naming
// the chunk (its index), if a section is damaged, does not end where its
// bytes do, is there without kept cells or missing with them, or a kept
// cell's brick has no chunk (`chunk_of_cell`: kNoCarvingChunk).
Status decode_cell_value_chunks(std::span<const FieldDescription> fields,
                                std::span<const std::span<const uint8_t>> sections, const TetMesh& dt,
                                std::span<const GridPoint> points, const ChunkCells& chunks,
                                std::span<const uint32_t> chunk_of_cell, std::span<const uint8_t> kept,
                                std::vector<FieldValues>& out);
// Each kept cell's place among the kept cells in index order (0 for a cell
// not kept), the order decode_cell_value_chunks() gives their values in;
// `count`: how many are kept.
std::vector<uint32_t> kept_cell_slots(std::span<const uint8_t> kept, uint64_t& count);

}  // namespace dtm
