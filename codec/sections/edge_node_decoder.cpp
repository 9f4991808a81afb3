// The edge node section read (spec/FORMAT.md §3.11), and the walk of a
// level's edges both sides make.
#include <algorithm>
#include <bit>
#include <unordered_map>

#include "codec/sections/edge_node_coder.h"
#include "codec/sections/edge_node_coder_shared.h"
#include "codec/sections/face_coder.h"

namespace dtm {

LevelEdges level_edges(const TetMesh& mesh, std::span<const uint8_t> kept, std::span<const uint32_t> order) {
  LevelEdges out;
  size_t kept_cells = 0;
  for (uint32_t c : order) kept_cells += kept[c] != 0;
  out.cell_edges.reserve(kept_cells);
  // (A tetrahedral mesh has about 1.2 edges a cell.)
  std::unordered_map<uint64_t, uint32_t> index;
  index.reserve(kept_cells * 3 / 2);
  out.corners.reserve(kept_cells * 3 / 2);
  for (uint32_t c : order) {
    if (!kept[c]) continue;
    // (Its corners ascending: the walk does not depend on how a cell
    // lists them.)
    std::array<uint32_t, 4> cell = mesh.cells[c];
    std::sort(cell.begin(), cell.end());
    std::array<uint32_t, 6> edges;
    for (size_t k = 0; k < 6; ++k) {
      const uint32_t a = cell[kCellEdges[k][0]], b = cell[kCellEdges[k][1]];
      const auto [it, fresh] = index.try_emplace(edge_key(a, b), static_cast<uint32_t>(out.corners.size()));
      if (fresh) out.corners.push_back({std::min(a, b), std::max(a, b)});
      edges[k] = it->second;
    }
    out.cell_edges.push_back(edges);
  }
  // The surface's edges: those of its faces.
  out.on_surface.assign(out.corners.size(), 0);
  for (const SurfaceFace& f : surface_faces(mesh, kept).faces)
    for (size_t k = 0; k < 3; ++k)
      if (const auto it = index.find(edge_key(f.key[k], f.key[(k + 1) % 3])); it != index.end())
        out.on_surface[it->second] = 1;
  return out;
}

std::vector<Neighbours> edge_node_neighbours(const LevelEdges& edges, std::span<const uint8_t> present) {
  std::vector<Neighbours> out;
  for (size_t e = 0; e < edges.corners.size(); ++e) {
    if (!present[e]) continue;
    // (Two neighbours at one distance: the prediction is their mean.)
    Neighbours& n = out.emplace_back();
    n.count = 2;
    n.index[0] = edges.corners[e][0], n.index[1] = edges.corners[e][1];
    n.d2[0] = n.d2[1] = 1;
  }
  return out;
}

Status decode_edge_node_values(std::span<const uint8_t> section, std::span<const FieldDescription> fields,
                               std::span<const FieldValues> vertex_values, const LevelEdges& edges,
                               std::span<const uint8_t> present, std::vector<FieldValues>& out) {
  // (The vertices' values, a row each per field: what every neighbour
  // index refers to.)
  if (vertex_values.size() != fields.size())
    return {StatusCode::kInvalidInput, "edge values: the vertices' values are not the fields'"};
  const size_t vertices =
      fields.empty() ? 0 : vertex_values[0].bits.size() / static_cast<size_t>(fields[0].components);
  std::vector<std::span<const uint64_t>> known_bits;
  for (size_t f = 0; f < fields.size(); ++f) {
    if (vertex_values[f].bits.size() != vertices * static_cast<size_t>(fields[f].components))
      return {StatusCode::kInvalidInput, "edge values: the vertices' values are not one row per vertex"};
    known_bits.emplace_back(vertex_values[f].bits);
  }
  for (size_t e = 0; e < edges.corners.size(); ++e)
    if (present[e] && !fields.empty() && std::max(edges.corners[e][0], edges.corners[e][1]) >= vertices)
      return {StatusCode::kInvalidInput, "edge values: an edge's corner has no values"};
  return decode_chunk_values(fields, section, known_bits, edge_node_neighbours(edges, present), out)
      .with_context("edge values");
}

Status decode_edge_nodes(std::span<const uint8_t> section, const LevelEdges& edges, int qbits,
                         EdgeNodeOffsets& nodes, const EdgeNodePredictor* predictor) {
  const size_t n = edges.corners.size();
  nodes.present.assign(n, 0);
  nodes.offset.assign(n, {0, 0, 0});
  RangeDecoder rc(section);
  EdgeNodeModels m;
  bool last_surface_moved = false;
  const int longest = longest_length(qbits, predictor != nullptr);
  const int64_t reach = edge_node_reach(qbits);
  constexpr std::array<int64_t, 3> kZero = {0, 0, 0};
  for (size_t e = 0; e < n; ++e) {
    nodes.present[e] = rc.decode(m.present);
    if (!nodes.present[e]) continue;
    const std::array<int64_t, 3> p = predictor && edges.on_surface[e]
                                         ? predictor->offset(edges.corners[e][0], edges.corners[e][1])
                                         : kZero;
    const bool guessed = p != kZero;
    const bool moved = rc.decode(m.moved[moved_context(edges.on_surface[e], last_surface_moved, guessed)]);
    if (edges.on_surface[e]) last_surface_moved = moved;
    if (!moved) continue;
    const size_t set = guessed ? 1 : 0;
    auto& d = nodes.offset[e];
    for (size_t axis = 0; axis < 3; ++axis) {
      int64_t r = 0;
      if (rc.decode(m.nonzero[set][axis])) {
        const bool negative = rc.decode(m.negative[set][axis]);
        int length = 0;
        while (length < longest && rc.decode(m.longer[set][axis][static_cast<size_t>(length)])) ++length;
        const int64_t magnitude =
            (int64_t{1} << length) + static_cast<int64_t>(length > 0 ? rc.decode_raw(length) : 0);
        r = negative ? -magnitude : magnitude;
      }
      d[axis] = p[axis] + r;
      if (d[axis] <= -reach || d[axis] >= reach)
        return {StatusCode::kCorrupt, "edge nodes: a node twice the grid's extent or more from its edge"};
    }
    if (d == kZero) return {StatusCode::kCorrupt, "edge nodes: a moved node without an offset"};
    if (rc.overran()) return {StatusCode::kCorrupt, "edge nodes: the section ends early"};
  }
  if (!rc.finished_cleanly()) return {StatusCode::kCorrupt, "edge nodes: the section does not end with them"};
  return Status::Ok();
}

}  // namespace dtm
