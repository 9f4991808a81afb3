// The codec preset's hierarchy (spec/HIERARCHY.md §6.1-6.2): every level
// carved to the reference solid, chosen a whole level at a time
// (coarsening.h), built in one Delaunay construction, checked and repaired
// (level_build.h). build_hierarchy() calls it when carve_to_reference is set.
#pragma once

#include <span>

#include "common/grid.h"
#include "common/status.h"
#include "core/hierarchy.h"

namespace dtm {

StatusOr<Hierarchy> build_codec_hierarchy(std::span<const GridPoint> points, const HierarchyOptions& options,
                                          const LevelCallback& on_level);

}  // namespace dtm
