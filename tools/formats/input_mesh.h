// What every input reader returns: the points, the reference tetrahedra when
// the file has them, and the per-vertex values kept aside for the attribute
// coding to come.
#pragma once

#include <array>
#include <cmath>
#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "common/grid.h"
#include "core/quantize.h"
#include "core/voxel_solid.h"
#include "scalar_type.h"

namespace dtm {

// Whether a cell array's values on the cells the mesh keeps none of (a
// file's triangles, its other elements) say anything, so that dropping them
// is named: 0 and NaN are what writers put where an array has no value
// (meshdec's own files, on their tagged faces), and go without a word.
// `at(i)`: the i-th of `count` values.
template <class At>
bool any_value_said(size_t count, At&& at) {
  for (size_t i = 0; i < count; ++i) {
    const double v = static_cast<double>(at(i));
    if (v != 0 && !std::isnan(v)) return true;
  }
  return false;
}

// One per-vertex array of the input (or, as InputMesh::cell_fields, one
// per-cell array): `components` values per point, point after point
// (values.size() == components * points), and the type the file
// stores them in (what a lossless coding must give back). Held as doubles:
// exact for every type but 64-bit integers beyond 2^53.
struct VertexField {
  std::string name;
  int components = 1;
  std::vector<double> values;
  ScalarType type = ScalarType::kFloat64;
  // At InputMesh::edge_points (set_edge_nodes_aside() moves them here),
  // `components` each.
  std::vector<double> edge_values{};
  // Given at the corners only (a solver's results on a second-order mesh's
  // linear cells): set_edge_nodes_aside() leaves edge_values empty, and the
  // stream gives the edge nodes their corners' mean.
  bool at_corners_only = false;
};

struct InputMesh {
  std::vector<InputPoint> points;
  // Tetrahedra of the input (0-based indices into points): the reference
  // shape for error measurement. Empty for point sets, surfaces and volumes.
  std::vector<std::array<uint32_t, 4>> tets;
  std::vector<VertexField> fields;
  // Per tetrahedron, its region (material), as the file labels it: gmsh's
  // physical volume, a Medit ref, a TetGen region attribute, a VTK cell
  // array's value; empty when the file has none. `region_names`: the
  // labels' names where the file has them ($PhysicalNames);
  // `region_source`: what the labels are, in words, for the tools' report.
  std::vector<int32_t> tet_regions;
  std::map<int32_t, std::string> region_names;
  std::string region_source;
  // A VTU's integer cell arrays of one component, on the tetrahedra (per
  // tetrahedron, in the order of `tets`): one of them may be the regions
  // (choose_regions(), tools/formats/input.h).
  std::map<std::string, std::vector<int32_t>> tet_arrays;
  // Every cell array's name in the file's order (VTK's): the cell data keep
  // it, those of tet_arrays among the others (choose_regions()).
  std::vector<std::string> cell_array_order;
  std::map<std::string, ScalarType> tet_array_types;  // the type each one is stored in
  // Per-cell arrays on the tetrahedra (element results, material
  // properties: a VTU/VTK cell array, gmsh $ElementData), `components`
  // values per tetrahedron in the order of `tets`. The integer arrays of
  // tet_arrays that are not the regions join them (choose_regions()).
  std::vector<VertexField> cell_fields;
  // The file's triangles with their tags (gmsh physical surfaces, Medit
  // triangle refs, a .vtu's triangles with the regions' array): where a
  // simulation sets its boundary conditions. Indices into points.
  std::vector<std::array<uint32_t, 3>> tagged_faces;
  std::vector<int32_t> face_tags;
  std::map<int32_t, std::string> face_tag_names;
  std::string face_tag_source;
  std::map<std::string, std::vector<int32_t>> triangle_arrays;  // a .vtu's, as tet_arrays
  // Second-order elements (gmsh's 10-node tetrahedra, 6-node triangles and
  // 20- or 27-node hexahedra, VTK's quadratic ones, Netgen's second-order
  // elements) are read as their linear cells: their corners in `tets` (a
  // hexahedron's split, cell_split.h) and the triangles above. The nodes
  // on their edges (and faces, and a 27-node hexahedron's centre), as the
  // readers leave them: per tetrahedron (in the order of `tets`, every one
  // once any has them; kNoEdgeNode for a linear one) its six, on the edges
  // (0,1) (0,2) (0,3) (1,2) (1,3) (2,3) of its corners, indices into
  // `points`; the other elements' in other_edge_nodes, in no order, and
  // how many second-order cells other than tetrahedra they came from.
  // set_edge_nodes_aside() (second_order.h) then moves the points that are
  // only such nodes to edge_points, tet_edge_nodes indexing them.
  static constexpr uint32_t kNoEdgeNode = UINT32_MAX;
  std::vector<std::array<uint32_t, 6>> tet_edge_nodes;
  std::vector<uint32_t> other_edge_nodes;
  uint64_t second_order_cells = 0;
  std::vector<InputPoint> edge_points;
  // Per node of the file in its order, once set_edge_nodes_aside() has
  // moved some: 1 where it went to edge_points, 0 where it stayed in
  // `points` (both keep the file's order): the file's numbering of the
  // two kinds together, which meshenc --keep-order keeps (format 21.0).
  std::vector<uint8_t> node_is_edge_point;
  // The file's own node ids (gmsh's node tags, Abaqus's node numbers, an
  // Exodus node map), per node of the file in its order (node_is_edge_point
  // says which of `points` and `edge_points` each is), where they are not
  // 1 to n in that order; empty where they are (node_labels.h).
  std::vector<int64_t> node_labels;
  // Voxel inputs on an isotropic lattice: the lattice itself as the
  // quantization grid, so that positions are coded losslessly. `points` then
  // holds the same positions as doubles.
  std::optional<QuantizedPoints> on_grid;
  // Voxel inputs: which voxels are the solid, the reference every level is
  // carved to (core/voxel_solid.h).
  std::optional<VoxelMask> voxels;
  // A TetGen .node read without its .ele (read_input's tetgen_ele false):
  // the .ele beside it, if there is one, and the .node's first index, for
  // read_tetgen_ele() later.
  std::string tetgen_ele;
  int tetgen_index_base = 0;
  // What the file holds that is not read into the mesh above (cell tags
  // and arrays, elements other than tetrahedra, named groups), one phrase
  // each: the tools say it, so that nothing of a user's input is left out
  // without a word.
  std::vector<std::string> left_out;
};

}  // namespace dtm
