// meshenc's input: one entry point for every format it reads, chosen by the
// file's extension or by name (--format).
//
//   point sets, surfaces   .ply .off .obj .xyz          (CGAL's readers)
//   volume meshes          .node(+.ele) .mesh .vtk .vtu .msh .vol .inp   (ours)
//                          .e .exo .ex2 .g .gen           (libexodusii)
//   voxel volumes          .nrrd .nhdr                  (ours; needs VolumeOptions)
#pragma once

#include <functional>
#include <optional>
#include <string>
#include <string_view>

#include "format_error.h"
#include "input_mesh.h"
#include "tetgen.h"
#include "voxel_points.h"

namespace dtm {

enum class InputFormat {
  kTetgen,
  kMedit,
  kVtk,
  kVtu,
  kPvtu,
  kGmsh,
  kNetgen,
  kAbaqus,
  kExodus,
  kNrrd,
  kPly,
  kOff,
  kObj,
  kXyz
};

// "node" (or "tetgen"), "mesh" ("medit"), "vtk", "vtu", "pvtu", "msh" ("gmsh"),
// "vol" ("netgen"), "inp" ("abaqus", "calculix"), "e" ("exo", "ex2", "g", "gen", "exodus"), "nrrd" ("nhdr"),
// "ply", "off", "obj", "xyz"; nullopt for anything else.
std::optional<InputFormat> input_format_named(std::string_view name);
// The names input_format_named accepts, for help texts.
inline constexpr const char* kInputFormatNames =
    "node, mesh, vtk, vtu, pvtu, msh, vol, inp, e, nrrd, ply, off, obj, xyz";

// By extension, ignoring case (.vol.gz: Netgen's, gzipped). Throws
// FormatError naming the path otherwise.
InputFormat input_format_for_path(const std::string& path);

// Reads `path` (format: given, or by extension) and checks that it can make
// a tetrahedral mesh: at least 4 distinct points, not all coplanar. A TetGen
// .node brings the .ele beside it when there is one, unless
// `tetgen_ele` is false (a large .ele costs time to read; InputMesh then
// says where it is, to be read later, or in part). Throws FormatError
// naming the file, where, and the problem.
// `read_node`, when given, reads a TetGen .node in its stead (meshenc under
// mpirun: each rank a part, joined). `time_step`: an Exodus II file's time
// step whose variables to read (1 the first; 0 the last).
InputMesh read_input(const std::string& path, std::optional<InputFormat> format = {},
                     const VolumeOptions& volume = {}, bool tetgen_ele = true,
                     const std::function<NodeFile(const std::string&)>& read_node = {}, int time_step = 0);

// Whether the TetGen .node at `path` has a .face beside it whose boundary
// markers are tags (some other than 1, TetGen's default): they need every
// tetrahedron, so meshenc under mpirun reads the .ele whole on every rank.
// False for a file that is not a TetGen .node, or a .face that does not read
// (its reader says why later).
bool tetgen_face_is_marked(const std::string& path);

// The names of cell arrays taken as the regions when the user names none,
// in this order: what gmsh, Medit and meshio's converters write, and the
// usual names.
inline constexpr const char* kRegionArrayNames[] = {"gmsh:physical", "medit:ref",   "netgen:index", "region",
                                                    "material",      "MaterialIds", "CellEntityIds"};
// Makes `name` (empty: the first of kRegionArrayNames the file has) of
// in.tet_arrays the regions, and the other arrays cell data (cell_fields).
// Throws FormatError naming `path` if a name is given and absent.
void choose_regions(InputMesh& in, const std::string& name, const std::string& path);

// Throws FormatError("path: ...") if `points` has fewer than 4 distinct
// points or they are all coplanar (exact predicates).
void check_spans_3d(const std::vector<InputPoint>& points, const std::string& path);

}  // namespace dtm
