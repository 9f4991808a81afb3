// What removing one vertex of a level does, seen before it is done (the
// paper preset's independent sets): the cells that refill its cavity (the
// Delaunay tetrahedralization without it, in that region) and how alpha
// carves them. The quality rules judge a candidate on the refill's solid
// angles.
#pragma once

#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include "common/grid.h"
#include "core/level.h"

namespace dtm {

struct Refill {
  std::vector<std::array<uint32_t, 4>> cells;  // local vertices of the level; empty: a flat hull tip
  std::vector<uint8_t> kept;                   // per cell: alpha (L.alpha) keeps it
};

// The refill of the cavity of v, carved by the level's alpha.
Refill refill_of(const LevelGeometry& L, uint32_t v);

}  // namespace dtm
