// The tags of a level's surface faces (spec/HIERARCHY.md §2.3): the input's
// tagged triangles (gmsh physical surfaces, Medit triangle refs) mark
// patches of its boundary and interfaces, where a simulation sets its
// boundary conditions. A face of a level that is a tagged input triangle
// (the same three grid points) has that triangle's tag; any other face has
// the tag of the reference surface's triangle nearest its centroid (a
// tagged triangle's tag, else none). So level 0 keeps the input's tags
// exactly where its faces are the input's, and a coarser face takes the tag
// of the patch it lies on.
#pragma once

#include <array>
#include <cstdint>
#include <span>
#include <utility>
#include <vector>

#include "common/grid.h"
#include "core/surface_distance.h"

namespace dtm {

class FaceTagger {
 public:
  // `surface`: the reference's surface triangles (its boundary and
  // interfaces, grid ids); `tagged` and `label`: the input's tagged
  // triangles (grid ids) and each one's label (2 + its tag's index; 1 is
  // no tag). `points` must outlive the tagger.
  FaceTagger(std::span<const GridPoint> points, std::span<const std::array<uint32_t, 3>> surface,
             std::span<const std::array<uint32_t, 3>> tagged, std::span<const uint8_t> label);

  // The label of each face (grid ids of its corners): its own as a tagged
  // triangle, else the nearest surface triangle's.
  std::vector<uint8_t> labels(std::span<const std::array<uint32_t, 3>> faces) const;
  // The tagged triangles that are among `faces` (a level's): the tags kept
  // exactly.
  size_t tagged_among(std::span<const std::array<uint32_t, 3>> faces) const;
  size_t tagged() const { return tagged_.size(); }
  // A hash of what the tagger was made of (the tagged triangles and their
  // labels, the surface's triangles' labels): the ranks of a run compare
  // theirs, which must be equal for the stream to be one process's.
  uint64_t fingerprint() const;

 private:
  uint8_t own_label(std::array<uint32_t, 3> key) const;  // 0: not a tagged triangle

  std::span<const GridPoint> points_;
  std::vector<std::pair<std::array<uint32_t, 3>, uint8_t>> tagged_;  // sorted keys (ids ascending)
  std::vector<uint8_t> surface_label_;                               // per surface triangle
  FixedSurface surface_;
};

}  // namespace dtm
