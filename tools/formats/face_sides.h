// Where the writers that name a face by its cell (Abaqus's S1..S4, Exodus's
// side sets) find the tagged faces: each one's cell and side.
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <vector>

#include "mesh_writers.h"

namespace dtm {

struct CellSide {
  static constexpr uint32_t kNoCell = UINT32_MAX;
  uint32_t cell = kNoCell;
  uint8_t side = 0;
};

// Per tagged face of `m` (OutputMesh::faces), the cell whose side it is,
// and which side, as `outward(cell, side)` lists a cell's four sides
// (turned out of the cell): the cell the face turns out of (the outward
// side a cyclic turn of the face), else the first cell that has it;
// kNoCell where none has.
std::vector<CellSide> tagged_face_sides(
    const OutputMesh& m, const std::function<std::array<uint32_t, 3>(uint32_t cell, uint8_t side)>& outward);

}  // namespace dtm
