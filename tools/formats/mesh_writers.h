// Output of decoded levels: TetGen .node/.ele (the corpus format, see
// data/README.md), VTK XML .vtu and legacy .vtk (ParaView), Medit
// .mesh, gmsh .msh 4.1, the boundary surface as PLY, OFF, glTF 2.0 (.glb, or
// .gltf + .bin; Draco-compressed or plain) or Draco .drc, the points as XYZ.
// The writers only render bytes; the caller writes them (atomically).
#pragma once

#include <array>
#include <cstdint>
#include <map>
#include <span>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "common/grid.h"
#include "tools/formats/scalar_type.h"

namespace dtm {

// A per-vertex field as decoded: raw bits of `type`, vertex-major.
struct OutputField {
  std::string name;
  ScalarType type = ScalarType::kFloat64;
  int components = 1;
  std::vector<uint64_t> bits;
};

// A decoded level ready to write. Vertex i is at grid.to_input(points[i]).
inline constexpr uint32_t kNoEdgePoint = UINT32_MAX;

struct OutputMesh {
  Grid grid;  // dequantization
  std::vector<GridPoint> points;
  std::vector<std::array<uint32_t, 4>> cells;  // tetrahedra, indices into points, positively oriented
  std::vector<int32_t> level;     // optional (empty = absent): per vertex, the coarsest level containing it
  std::vector<uint8_t> boundary;  // optional (empty = absent): per vertex, 1 on the boundary
  // The stream's fields, written where the format carries point data
  // (VTU/VTK point data, gmsh $NodeData, PLY vertex properties, TetGen
  // attributes; a 1-component integer field named boundary_marker is the
  // TetGen marker column). Medit, OFF and XYZ have no place for them.
  std::vector<OutputField> fields;
  // Optional (empty = absent): per cell, its region's label (the stream's
  // region table, format 9.0), and the labels' names where it has them.
  // Written as VTU/VTK cell data "region", gmsh physical volumes (with
  // $PhysicalNames), Medit tetrahedron refs and a TetGen .ele attribute.
  std::vector<int32_t> region;
  std::map<int32_t, std::string> region_names;
  // Optional: the tagged faces of the level's surface (outward from their
  // cell; an interface's from its lower region) and each one's tag, with
  // the tags' names. Written as gmsh triangles in physical surfaces, Medit
  // Triangles with refs, VTU/VTK triangles after the tetrahedra (cell data
  // "face_tag"; a tetrahedron's is 0).
  std::vector<std::array<uint32_t, 3>> faces;
  std::vector<int32_t> face_tags;
  std::map<int32_t, std::string> face_tag_names;
  // Optional: per-cell arrays (level 0 of a 10.0 stream), cell-major bits
  // of each cell of `cells`. Written as VTU/VTK cell data (a tagged face's
  // row 0) and gmsh $ElementData (1, 3 or 9 components); Medit, TetGen
  // and the surface formats have no place for them.
  std::vector<OutputField> cell_fields;
  // A piece of a parallel grid (.pvtu) declares the arrays every piece
  // holds, even with no point or cell of its own (ParaView warns of a
  // piece that lacks one): `level`, and `region` when the stream has
  // regions.
  bool declare_level = false, declare_region = false;
  // Optional (level 0 of an 18.0 stream, a second-order input's: meshenc
  // --exact): the nodes on the cells' edges, `edge_nodes` of the points,
  // after the vertices (with --keep-order, 21.0: where the input numbered
  // them, among the vertices; no node is a cell's or face's corner) (the
  // grid then has half the stream's step, so that an edge's
  // midpoint is one of its points: every coordinate the same double). Per
  // cell, the points on its edges (0,1) (0,2) (0,3) (1,2) (1,3) (2,3);
  // per tagged face, on its edges (0,1) (1,2) (2,0); kNoEdgePoint
  // where there is none. Written as 10-node tetrahedra and 6-node
  // triangles (VTU, VTK, gmsh); the formats without them write the linear
  // cells (without_edge_nodes()).
  size_t edge_nodes = 0;
  // Optional (level 0 of a 22.0 stream, meshenc --keep-order of a file with
  // its own node ids): per point, its id in the input, each in [1, 2^62 -
  // 1], no two alike; empty: point k is node k + 1. The gmsh, Abaqus and
  // Exodus writers number the nodes so (node tags, node numbers, the node
  // number map); the others have no place for them.
  std::vector<int64_t> node_labels;
  std::vector<std::array<uint32_t, 6>> cell_edge_nodes;
  std::vector<std::array<uint32_t, 3>> face_edge_nodes;
};

// The cell arrays padded to the cells and the faces after them (a face's
// row 0), as VTU and VTK files hold them.
std::vector<OutputField> cell_and_face_fields(const OutputMesh& m);

// Per cell of a VTU/VTK file (the tetrahedra, then the tagged faces): the
// cell data "region", as gmsh's physical tags: a tetrahedron's region (0
// without regions), a face's tag. Empty without either.
std::vector<int32_t> physical_tags(const OutputMesh& m);

// A path's extension in lower case (".VTU" names a .vtu).
std::string lower_extension(const std::string& path);

enum class MeshFormat {
  kTetgen,    // X.node + X.ele; `boundary` becomes the marker column, `level` is not written
  kVtu,       // VTK XML, format="binary": base64 of [UInt64 byte count][little-endian data]
  kVtuAscii,  // VTK XML, format="ascii"
  kVtk,       // VTK legacy 4.2, BINARY (big-endian); point data level, boundary
  kVtkAscii,  // VTK legacy 4.2, ASCII
  kMedit,     // Medit .mesh, ASCII; `boundary` becomes the vertex ref
  kGmsh,      // gmsh .msh 4.1 ASCII; $NodeData level, boundary
  kNetgen,    // Netgen .vol; every surface face a surface element, the regions the materials
  kAbaqus,    // Abaqus/CalculiX .inp; regions as element sets, face tags as surfaces, node set fields
  kExodus,    // Exodus II .e; regions as element blocks, face tags as side sets, fields as variables
  kPly,       // boundary surface, binary PLY, outward normals
  kOff,       // boundary surface, ASCII OFF, outward normals
  kXyz,       // the points only
  kGlb,       // boundary surface, binary glTF 2.0 (tools/formats/gltf_writer.h)
  kGltf,      // boundary surface, glTF 2.0 JSON + its .bin beside it (same stem)
  kDrc,       // boundary surface, Draco's own file
};

// A cell's or tagged face's nodes as a format lists them: its corners, then,
// when all its edges have nodes, those of the edges `edge_order` names
// (slots of OutputMesh::cell_edge_nodes): 4 or 10 of a cell, 3 or 6 of a
// face (in the order (0,1) (1,2) (2,0), VTK's and gmsh's alike).
struct ListedNodes {
  std::array<uint32_t, 10> nodes{};
  size_t count = 0;
  bool second_order() const { return count > 4; }
};
// VTK's and gmsh's 10-node tetrahedra: their edge nodes' slots.
inline constexpr std::array<uint8_t, 6> kVtkEdgeSlots = {0, 3, 1, 2, 4, 5};
inline constexpr std::array<uint8_t, 6> kGmshEdgeSlots = {0, 3, 1, 2, 5, 4};
ListedNodes cell_nodes(const OutputMesh& m, size_t cell, const std::array<uint8_t, 6>& edge_slots);
ListedNodes face_nodes(const OutputMesh& m, size_t face);

// Whether a format writes second-order cells (OutputMesh::edge_nodes).
bool writes_edge_nodes(MeshFormat format);
// The mesh's linear cells: without the points on their edges.
OutputMesh without_edge_nodes(OutputMesh mesh);

// How the surface formats that carry colours draw them (glTF, .drc;
// tools/formats/gltf_writer.h says what each means).
struct SurfaceStyle {
  std::string colour = "level";  // "level", "boundary", "region" or a field's name
  bool draco = true;             // glTF: KHR_draco_mesh_compression, or plain accessors
};

// What of the stream's data `format` has no place for, named for a
// "not written" line (the fields, regions, tagged faces and cell data a
// user gave; `level` and `boundary`, which meshdec derives, are not named).
// Empty when it holds everything. A glTF or Draco surface drawn by region
// (`style`) holds the regions.
std::vector<std::string> not_written(const OutputMesh& m, MeshFormat format, const SurfaceStyle& style = {});

// The format named by the output path's extension: ".node" -> kTetgen (the
// .ele goes beside it, same stem), ".vtu" -> kVtu, ".vtk" -> kVtk, ".mesh"
// -> kMedit, ".msh" -> kGmsh, ".vol" -> kNetgen, ".inp" -> kAbaqus, ".e" and ".exo" -> kExodus, ".ply",
// ".off", ".xyz", ".glb", ".gltf",
// ".drc". Extensions are
// case-sensitive, as TetGen's own are: "X.NODE" would otherwise get an
// "X.ele" that `tetgen X` cannot find. Throws std::invalid_argument naming the
// path for anything else.
MeshFormat format_for_path(const std::string& path);

// The format meshdec --format names: node, vtu, vtu-ascii, vtk, vtk-ascii,
// mesh, msh, vol, inp, e, ply, off, xyz, glb, gltf, drc. Throws std::invalid_argument for
// anything else.
MeshFormat format_named(const std::string& name);
inline constexpr const char* kOutputFormatNames =
    "node, vtu, vtu-ascii, vtk, vtk-ascii, mesh, msh, vol, inp, e, ply, off, xyz, glb, gltf, drc";

// The files of `mesh` in `format` as (path, bytes) pairs: two for kTetgen
// (`path`, which must end in ".node", and the .ele beside it) and kGltf (the
// .bin beside it), one for the others (`path` as given). `style` is for the
// formats with colours. Throws std::invalid_argument for a cell index out of
// range, a `level` or `boundary` whose size is neither 0 nor the number of
// points, a TetGen path not ending in ".node", or a surface format asked of
// a level whose surface is empty.
std::vector<std::pair<std::string, std::string>> render_mesh(const OutputMesh& mesh, MeshFormat format,
                                                             const std::string& path,
                                                             const SurfaceStyle& style = {});

// A VTK parallel unstructured grid (.pvtu) naming `pieces` (.vtu files,
// paths relative to the .pvtu) written by render_mesh as kVtu from meshes
// with the point and cell data of `like` (level, boundary, fields; region,
// cell fields: the same names, types and components in every piece).
std::string render_pvtu(const OutputMesh& like, std::span<const std::string> pieces);

// Standard base64 (RFC 4648, with '=' padding), as VTK's binary format wants.
// Exposed for its test.
std::string base64_encode(std::string_view bytes);

}  // namespace dtm
