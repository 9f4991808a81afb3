// Netgen's own mesh file, .vol (what Netgen's GUI and Mesh.Save() write;
// .vol.gz gzipped), ASCII: "mesh3d", then sections of a keyword, a count
// and one record a line: "points" (x y z), "volumeelements" (matnr np
// p1..p_np, 1-based), "surfaceelements" (surfnr bcnr domin domout np
// p1..p_np), "materials" (domain name), "bcnames" (bcnr name), others
// (edge segments, face colours, identifications, ...) read past, until
// "endmesh" (the geometry Netgen may append after it is not read).
// https://github.com/NGSolve/netgen/blob/master/libsrc/meshing/meshclass.cpp
// (Mesh::Save, Mesh::Load)
#pragma once

#include <string>
#include <vector>

#include "input_mesh.h"
#include "mesh_writers.h"

namespace dtm {

// Points, the 4-node tetrahedra with their material (the regions, named by
// "materials") and the 3-node surface elements with their boundary
// condition number (the tagged faces, named by "bcnames"; a name is the
// rest of its line); second-order and
// other elements, and the other sections, named as left out. Throws
// FormatError naming the file and line.
InputMesh read_netgen_vol(const std::string& path);

// What Netgen loads (and NGSolve's Mesh("x.vol") through it): the points, the
// tetrahedra in Netgen's orientation with their region as the material
// (numbered 1..K in the labels' order, named by the region's name or
// "region_L"), and every face of the level's surface (its boundary and its
// interfaces between regions) as a surface element from its domain to the
// one outside (0) or the higher region (a tagged face inside a region: that
// region on both sides); one boundary condition a kind of face (its tag
// and its two domains), numbered as Netgen numbers its face descriptors and
// named by the tag's name ("bc_L" without one, "default" for the faces
// without a tag). Names lose their blanks (Netgen 6.2 reads a name as one
// word).
std::string render_netgen_vol(const OutputMesh& mesh);
// What render_netgen_vol() numbers or names otherwise than the stream
// (regions as materials 1 to K, names made one word, face tags as boundary
// condition numbers), for meshdec's "written as" lines.
std::vector<std::string> netgen_renumbering(const OutputMesh& mesh);

}  // namespace dtm
