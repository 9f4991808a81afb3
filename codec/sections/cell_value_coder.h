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
#include <span>
#include <vector>

#include "codec/sections/value_fields.h"
#include "common/grid.h"
#include "common/status.h"

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

}  // namespace dtm
