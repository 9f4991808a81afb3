// What meshdec writes for users who want a surface or a point cloud: the
// boundary surface of the decoded level (faces of exactly one tetrahedron,
// oriented outward) as PLY or OFF, and the points as XYZ.
#pragma once

#include <array>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "mesh_writers.h"

namespace dtm {

struct BoundarySurface {
  std::vector<uint32_t> vertices;                  // indices into the mesh's points, ascending
  std::vector<std::array<uint32_t, 3>> triangles;  // indices into `vertices`, normals pointing out
};

// boundary_triangles of `mesh.cells` over the vertices they use, renumbered.
BoundarySurface boundary_surface(const OutputMesh& mesh);

// binary_little_endian PLY: float64 x y z (+ int level when present), faces
// as "list uint8 int vertex_indices".
std::string render_ply(const OutputMesh& mesh);
// ASCII OFF, coordinates that read back to the same doubles.
std::string render_off(const OutputMesh& mesh);
// Every point, one "x y z" line each.
std::string render_xyz(const OutputMesh& mesh);

}  // namespace dtm
