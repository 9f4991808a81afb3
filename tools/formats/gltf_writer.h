// A decoded level's boundary surface for the tools people already use:
// glTF 2.0 (binary .glb, or .gltf with its .bin) compressed with Draco
// (KHR_draco_mesh_compression) or plain, and Draco's own .drc. Debian's
// libdraco writes all three (its glTF encoder and its mesh encoder); this
// file makes the surface they encode: the faces of exactly one carved
// tetrahedron, outward, with positions in input units, area-weighted vertex
// normals and vertex colours.
#pragma once

#include <string>
#include <utility>
#include <vector>

#include "tools/formats/mesh_writers.h"
#include "tools/formats/surface_writers.h"

namespace dtm {

// SurfaceStyle (mesh_writers.h): vertex colours by "level" (the coarsest
// level holding the vertex, on a ramp from dark to bright), "boundary" (the
// boundary flag: every surface vertex has it, so one colour), or the name of
// one of the mesh's fields (a vector by its length), on the same ramp between
// the surface's smallest and largest value, or "region" (a mesh with
// regions: each region's own surface in its colour, as the viewer's, and in
// glTF a primitive each, its material named as the region); and whether
// glTF is compressed.

// Draco's position quantization for this surface: just enough bits that
// Draco's step over the surface's extent is at most the stream's grid step,
// so that every position stays within half a grid step of the decoded one,
// and what float32 positions add. A glTF file holds them from the anchor
// (the surface's least corner), which its node's translation adds back, so
// float32 rounds only the offsets; a .drc holds them whole, and far from
// the origin float32 rounds more than a grid step (float_error).
struct SurfaceQuantization {
  int position_bits = 0;
  double draco_step = 0;   // input units
  double grid_step = 0;    // the stream's, input units
  double float_error = 0;  // the most float32 moves a position as the file holds it, input units
  InputPoint anchor;       // what the file's positions are offsets from (a .drc: the origin)
};
inline constexpr int kNormalBits = 10;
inline constexpr int kColourBits = 8;

// The files of `mesh`'s boundary surface in `format` (kGlb, kGltf: the .gltf
// and its .bin beside it, same stem; kDrc). Throws std::invalid_argument when
// the surface is empty, the colour names no field, or libdraco fails.
std::vector<std::pair<std::string, std::string>> render_surface_gltf(const OutputMesh& mesh,
                                                                     MeshFormat format,
                                                                     const std::string& path,
                                                                     const SurfaceStyle& style);

// Whether render_surface_gltf draws `mesh` by region (--color region).
bool draws_regions(const OutputMesh& mesh, MeshFormat format, const SurfaceStyle& style);

// What it then draws: each region's own surface (the faces of exactly one
// of its cells, outward), one after the other, its vertices its own (a
// vertex on an interface is in both regions' surfaces); `region` per vertex
// of `surface`, the region's index in `labels` (ascending). Throws
// std::invalid_argument when the mesh has no regions.
struct RegionSurfaces {
  BoundarySurface surface;  // (vertices repeat across regions)
  std::vector<uint8_t> region;
  std::vector<int32_t> labels;
};
RegionSurfaces region_surfaces(const OutputMesh& mesh);

// What render_surface_gltf uses for `mesh`, whose boundary_surface
// (surface_writers.h) is `surface` (empty surface: position_bits 0), in
// `format` (kDrc: positions whole, else from the anchor).
SurfaceQuantization surface_quantization(const OutputMesh& mesh, const BoundarySurface& surface,
                                         MeshFormat format);

}  // namespace dtm
