// The finest level a progressive decoder holds, as the writers take it
// (tools/formats/mesh_writers.h) and as the Python package hands it to numpy:
// its points, its carved cells in the canonical order (each cell's corners
// ascending but for the orientation: the same arrays from every run, though
// the triangulation is built on every core), each vertex's coarsest level,
// the boundary vertices and the stream's fields; with a vertex order
// (meshenc --keep-order) level 0's vertices in the input's numbering.
#pragma once

#include <array>
#include <string>

#include "codec/decode.h"
#include "codec/region_decode.h"
#include "tools/formats/mesh_writers.h"

namespace dtm {

// Throws std::runtime_error naming `input` if the points cannot make the
// level's triangulation (a hostile stream). `with_edge_nodes`: level 0 of
// an 18.0 stream (meshenc --exact of a second-order mesh) with the nodes on
// its cells' edges (OutputMesh::edge_nodes: second-order cells), for the
// writers that hold them; without, its linear cells.
OutputMesh decoded_mesh(const ProgressiveDecoder& decoder, const std::string& input,
                        bool with_edge_nodes = false);

// Whether level 0 of `decoder`'s stream numbers its vertices among its edge
// nodes (21.0, meshenc --exact --keep-order of a second-order mesh): a box
// cut from it must be cut from the level with its nodes (decoded_mesh(...,
// true)) for its vertices' numbers (vertex_id) to be the input's.
bool numbers_edge_nodes(const ProgressiveDecoder& decoder);

// The cells of `whole` whose bounding box meets the box from `lo` to `hi`
// (input units, on whole's own grid: with a second-order mesh's nodes that
// is half the stream's step), with what the level carries on them: their vertices in the whole's order
// with each one's number there (point data vertex_id, first), its fields,
// level and `boundary` (the level's own surface), the cells' regions and
// cell data, and the tagged faces of those cells (each with the cell the
// level's surface takes it from: the kept one, at an interface the lower
// region's).
// `input_numbered`: whole is level 0 in the input's numbering (10.0,
// --keep-order: in_input_numbering()), so that a box without the input's
// node ids (22.0) numbers its nodes with their numbers there (vertex_id +
// 1), as the whole level does.
OutputMesh cut_to_box(const OutputMesh& whole, const std::array<double, 3>& lo,
                      const std::array<double, 3>& hi, bool input_numbered = false);

// Whether the level `decoder` decoded is level 0 in the input's numbering
// (meshenc --keep-order): its vertex k the input's node k.
bool in_input_numbering(const ProgressiveDecoder& decoder);

// A box or piece a region reader decoded (codec/region_decode.h), as
// meshdec --box, the pieces of -o X.pvtu and the Python package write it:
// its points, cells, each vertex's coarsest level and its number in the
// whole level (point data vertex_id, first), the fields, the cells' regions
// and, at level 0, their cell data; every piece declares `level` and, with
// regions, `region`. No `boundary`: a part's own surface is not the level's,
// and the rest of the level is not decoded to tell.
OutputMesh region_output(const RegionMesh& region, const Grid& grid);

}  // namespace dtm
