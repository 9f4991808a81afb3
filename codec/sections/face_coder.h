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

#include "codec/sections/carving_coder.h"
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
// Whether the level's surface takes a face from the kept cell of region
// `mine` (1 + its index) on one side, `across` being the cell on the other
// side (0: not kept, or none): the boundary, and each interface once, from
// its lower region.
inline bool surface_takes_face(uint8_t mine, uint8_t across) { return across == 0 || across > mine; }

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

// Bricked layers (17.0, spec/FORMAT.md §3.5): a face section per chunk,
// over the faces of the kept cells its brick owns that may be on the
// level's surface as far as the chunk can tell: every face but those whose
// cell across is kept, of the same chunk, and of a region not above the
// cell's (the chunk's insides, and its interfaces coded from their lower
// side). A face whose cell across is another chunk's is coded by both
// chunks; an encoder gives it its tag only in the chunk whose cell the
// surface takes it from (the kept cell, or the lower region's), 1 in the
// other. So a reader of some chunks knows every tagged surface face of
// the cells they own, and each once.
struct ChunkFaces {
  std::vector<SurfaceFace> faces;  // per chunk, its faces by key (vertex ranks ascending), ascending
  std::vector<uint32_t> first;     // chunk i's faces: faces[first[i] .. first[i + 1])
  Csr neighbours;                  // per face, the faces of its chunk that share one of its edges
};
// `kept`: per cell, 0 or its region (1 without regions); `chunks`,
// `chunk_of_cell` and `vertex_rank` as the carving's (chunk_cells()).
ChunkFaces chunk_faces(const TetMesh& dt, const ChunkCells& chunks, std::span<const uint32_t> chunk_of_cell,
                       std::span<const uint8_t> kept, std::span<const uint32_t> vertex_rank);
// One section per chunk for `label` (per face of `faces`: 1 + the tag's
// index, 1 = no tag); empty for a chunk none of whose faces has a tag.
std::vector<std::vector<uint8_t>> encode_face_chunks(const ChunkFaces& faces, std::span<const uint8_t> label,
                                                     size_t tags);
// Each face's label (1: none), each chunk on its own, on every core.
// kCorrupt, naming the chunk (its index), if a label is not in the table
// or a section does not end where its bytes do.
Status decode_face_chunks(std::span<const std::span<const uint8_t>> sections, const ChunkFaces& faces,
                          size_t tags, std::vector<uint8_t>& label);

}  // namespace dtm
