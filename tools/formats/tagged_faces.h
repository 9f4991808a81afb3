// The readers that gather tagged faces from several places (Abaqus's
// surfaces and 2D elements, Exodus's side sets and face blocks) keep one
// tag a face.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "input_mesh.h"

namespace dtm {

// Appends `faces` with their `tags` to mesh.tagged_faces and
// mesh.face_tags, a face met again (the same corners, in any order)
// keeping its first tag. Returns the note for InputMesh::left_out ("3
// faces tagged a second time (each keeps its first tag)"), empty for none.
std::string add_tagged_faces_once(InputMesh& mesh, const std::vector<std::array<uint32_t, 3>>& faces,
                                  const std::vector<int32_t>& tags);

// How many of `faces` no level can carry: not a face of `tets` on their
// boundary or between two regions (`regions`, one a tetrahedron, or empty):
// a face inside one region, or no face of the tetrahedra at all. The
// stream's tagged faces are faces of its levels' surfaces.
uint64_t tagged_faces_inside(const std::vector<std::array<uint32_t, 4>>& tets,
                             const std::vector<int32_t>& regions,
                             const std::vector<std::array<uint32_t, 3>>& faces);

// The note for InputMesh::left_out of `inside` such faces of `total`.
std::string tagged_faces_inside_note(uint64_t inside, uint64_t total);

}  // namespace dtm
