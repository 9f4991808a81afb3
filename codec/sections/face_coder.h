// Tagged faces of a stream's levels (spec/FORMAT.md §2.3, §3.7), encoder
// and decoder side by side. A level's surface is its faces between a kept
// cell and one not kept (or the convex hull) and between kept cells of two
// regions (an interface); a mesh's boundary conditions live there, as the
// tags of the input's triangles (gmsh physical surfaces, Medit triangle
// refs). The face tag table names the tags (as the region table names
// regions); each layer's face section gives every face of its level's
// surface its tag, or none, coded from the faces sharing an edge with it
// (label_coder.h): a tag covers a patch, so a level costs little more than
// the patches' borders. Each level's section is coded alone.
#pragma once

#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include "common/csr.h"
#include "common/status.h"
#include "mesh/delaunay.h"

namespace dtm {

// Face tags in a table of at most this many: a face's label is 1 + the
// tag's index, 1 meaning none (label_coder.h codes 1..255).
inline constexpr size_t kMaxFaceTags = 254;

// A level's surface, in canonical order: each face's vertex ids ascending,
// faces ascending. A boundary face is its kept cell's; an interface face
// the cell of the lower region's (its outward side faces the higher).
struct SurfaceFace {
  uint32_t cell = 0;
  uint8_t opposite = 0;  // the cell's corner the face does not have
  std::array<uint32_t, 3> key{};
};
struct SurfaceFaces {
  std::vector<SurfaceFace> faces;
  Csr neighbours;  // per face, the other faces that share one of its edges
};
// `kept`: per cell of `dt`, 0 if the level does not keep it, else its
// region (1 without regions).
SurfaceFaces surface_faces(const TetMesh& dt, std::span<const uint8_t> kept);

// The section for `tag` (per face of `surface`: 1 + the tag's index, 1 =
// no tag), with `tags` tags in the table; empty when every face has no tag.
std::vector<uint8_t> encode_face_tags(const SurfaceFaces& surface, std::span<const uint8_t> tag, size_t tags);
// Each face's 1 + tag index (1: none). An empty section: no face has a tag.
// kCorrupt if a tag is not in the table or the section does not end where
// its bytes do.
Status decode_face_tags(std::span<const uint8_t> section, const SurfaceFaces& surface, size_t tags,
                        std::vector<uint8_t>& tag);

}  // namespace dtm
