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

}  // namespace dtm
