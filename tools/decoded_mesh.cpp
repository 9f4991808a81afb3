#include "tools/decoded_mesh.h"

#include <algorithm>
#include <cmath>
#include <optional>
#include <set>
#include <stdexcept>
#include <unordered_map>
#include <unordered_set>

#include "codec/region_decode.h"
#include "common/parallel_for.h"
#include "mesh/carving.h"
#include "mesh/topology.h"
#include "tools/field_types.h"

namespace dtm {

namespace {

// Point k becomes order[k]'s: the points and every per-point array
// gathered, the cells' and faces' corners and edge nodes renamed (their
// orientation is the points', which do not move).
void renumber(OutputMesh& mesh, std::span<const uint32_t> order) {
  std::vector<uint32_t> new_of_old(order.size());
  for (uint32_t k = 0; k < order.size(); ++k) new_of_old[order[k]] = k;
  const auto gather = [&](auto& values, size_t per) {
    if (values.empty()) return;
    std::remove_reference_t<decltype(values)> out(values.size());
    for (size_t k = 0; k < order.size(); ++k)
      for (size_t c = 0; c < per; ++c) out[k * per + c] = values[order[k] * per + c];
    values = std::move(out);
  };
  gather(mesh.points, 1);
  gather(mesh.level, 1);
  gather(mesh.boundary, 1);
  for (OutputField& f : mesh.fields) gather(f.bits, static_cast<size_t>(f.components));
  for (auto& c : mesh.cells)
    for (uint32_t& v : c) v = new_of_old[v];
  for (auto& f : mesh.faces)
    for (uint32_t& v : f) v = new_of_old[v];
  const auto rename_nodes = [&](auto& elements) {
    for (auto& e : elements)
      for (uint32_t& v : e)
        if (v != kNoEdgePoint) v = new_of_old[v];
  };
  rename_nodes(mesh.cell_edge_nodes);
  rename_nodes(mesh.face_edge_nodes);
}

// The nodes on level 0's edges (18.0), found before the vertices may be
// renumbered: per cell and tagged face of `mesh`, each edge's node as its
// rank among the nodes (kNone: none), and per node its edge's corners (the
// decoder's numbering), where it lies (grid units) and whether its edge is
// on the level's boundary (an edge of a face of a kept cell of `dt` with no
// kept cell across: as boundary_vertices() finds the corners'; not the
// interfaces between regions, which the section's surface has too); with
// a 19.0 stream's fields, their values at the nodes.
struct EdgeNodeParts {
  std::vector<std::array<uint32_t, 6>> cells;
  std::vector<std::array<uint32_t, 3>> faces;
  std::vector<std::array<uint32_t, 2>> corners;
  std::vector<std::array<double, 3>> at;
  std::vector<uint8_t> on_boundary;
  std::vector<FieldValues> values;
};

constexpr uint32_t kNone = UINT32_MAX;

EdgeNodeParts edge_node_parts(ProgressiveDecoder::EdgeNodes nodes, const OutputMesh& mesh, const TetMesh& dt,
                              std::span<const uint8_t> kept) {
  EdgeNodeParts out;
  out.values = std::move(nodes.values);
  std::unordered_set<uint64_t> boundary;
  for (size_t c = 0; c < dt.cells.size(); ++c) {
    if (!kept[c]) continue;
    for (size_t k = 0; k < 4; ++k) {
      const int64_t across = dt.neighbors[c][k];
      if (across >= 0 && kept[static_cast<size_t>(across)]) continue;
      for (size_t i = 0; i < 4; ++i)
        for (size_t j = i + 1; j < 4; ++j)
          if (i != k && j != k) boundary.insert(edge_key(dt.cells[c][i], dt.cells[c][j]));
    }
  }
  std::unordered_map<uint64_t, uint32_t> rank;  // of each node, by its edge's corners
  rank.reserve(nodes.edges.corners.size());
  for (size_t e = 0; e < nodes.edges.corners.size(); ++e) {
    if (!nodes.present[e]) continue;
    const auto& c = nodes.edges.corners[e];
    rank.emplace(edge_key(c[0], c[1]), static_cast<uint32_t>(out.corners.size()));
    out.corners.push_back(c);
    out.at.push_back(nodes.points[e]);
    out.on_boundary.push_back(boundary.count(edge_key(c[0], c[1])) != 0);
  }
  const auto node = [&](uint32_t a, uint32_t b) {
    const auto it = rank.find(edge_key(a, b));
    return it == rank.end() ? kNone : it->second;
  };
  out.cells.reserve(mesh.cells.size());
  for (const auto& c : mesh.cells) {
    std::array<uint32_t, 6> n;
    for (size_t k = 0; k < 6; ++k) n[k] = node(c[kCellEdges[k][0]], c[kCellEdges[k][1]]);
    out.cells.push_back(n);
  }
  for (const auto& f : mesh.faces)
    out.faces.push_back({node(f[0], f[1]), node(f[1], f[2]), node(f[2], f[0])});
  return out;
}

// The nodes as points of `mesh`, after its vertices (`new_of_old`: the
// vertices' new numbers, empty for none), on a grid of half the step (an
// edge's midpoint is a point of it; every coordinate the same double): each
// at level 0, on the boundary with its edge, each field's value there the
// stream's (19.0) or else its edge's corners' mean (a float field's; an
// integer field's the lesser).
void append_edge_nodes(OutputMesh& mesh, const EdgeNodeParts& parts, std::span<const uint32_t> new_of_old) {
  mesh.grid.step /= 2;
  ++mesh.grid.qbits;  // (the same extent: twice the grid points)
  for (GridPoint& p : mesh.points) p = {2 * p.x, 2 * p.y, 2 * p.z};
  const auto base = static_cast<uint32_t>(mesh.points.size());
  const auto vertex = [&](uint32_t v) { return new_of_old.empty() ? v : new_of_old[v]; };
  for (size_t n = 0; n < parts.at.size(); ++n) {
    const auto& at = parts.at[n];
    mesh.points.push_back({static_cast<int32_t>(std::llround(2 * at[0])),
                           static_cast<int32_t>(std::llround(2 * at[1])),
                           static_cast<int32_t>(std::llround(2 * at[2]))});
    if (!mesh.level.empty()) mesh.level.push_back(0);
    if (!mesh.boundary.empty()) mesh.boundary.push_back(parts.on_boundary[n]);
    const uint32_t a = vertex(parts.corners[n][0]), b = vertex(parts.corners[n][1]);
    for (size_t k = 0; k < mesh.fields.size(); ++k) {
      OutputField& f = mesh.fields[k];
      const auto components = static_cast<size_t>(f.components);
      if (k < parts.values.size()) {
        const auto& bits = parts.values[k].bits;
        f.bits.insert(f.bits.end(), bits.begin() + static_cast<std::ptrdiff_t>(n * components),
                      bits.begin() + static_cast<std::ptrdiff_t>((n + 1) * components));
        continue;
      }
      const ValueType type = value_type(f.type);
      for (size_t c = 0; c < components; ++c) {
        const double va = value_of(f.bits[a * components + c], type),
                     vb = value_of(f.bits[b * components + c], type);
        f.bits.push_back(bits_of(is_float(type) ? (va + vb) / 2 : std::min(va, vb), type));
      }
    }
  }
  const auto point = [&](uint32_t rank) { return rank == kNone ? kNoEdgePoint : base + rank; };
  mesh.edge_nodes = parts.at.size();
  mesh.cell_edge_nodes.reserve(parts.cells.size());
  for (const auto& c : parts.cells)
    mesh.cell_edge_nodes.push_back(
        {point(c[0]), point(c[1]), point(c[2]), point(c[3]), point(c[4]), point(c[5])});
  for (const auto& f : parts.faces) mesh.face_edge_nodes.push_back({point(f[0]), point(f[1]), point(f[2])});
}

// A face's corners turned (an even permutation: its orientation kept) so
// that the one at the smallest grid point comes first: the rotation a cell's
// corners left it in depends on how the cells were made (a level decoded
// whole or as a stream fed in chunks, a region's cells), its points do not.
std::array<uint32_t, 3> smallest_point_first(std::array<uint32_t, 3> t, std::span<const GridPoint> points) {
  const auto at = [&](int i) {
    return std::array<int32_t, 3>{points[t[i]].x, points[t[i]].y, points[t[i]].z};
  };
  int first = 0;
  for (int i = 1; i < 3; ++i)
    if (at(i) < at(first)) first = i;
  std::rotate(t.begin(), t.begin() + first, t.end());
  return t;
}

}  // namespace

OutputMesh decoded_mesh(const ProgressiveDecoder& decoder, const std::string& input, bool with_edge_nodes) {
  OutputMesh mesh;
  mesh.grid = decoder.header().grid;
  mesh.points = decoder.points();
  // DT's cells, and at level 0 of an exact stream the input's other cells.
  const ProgressiveDecoder::LevelCells level = decoder.level_cells();
  if (!decoder.mesh_status().ok()) throw std::runtime_error(input + ": " + decoder.mesh_status().message());
  const TetMesh& dt = level.mesh;
  const std::vector<uint32_t>& order = level.order;
  const std::vector<uint8_t>& in_mesh = level.kept;
  // With regions (format 9.0), each cell's label from the region table.
  const std::vector<RegionLabel>& regions = decoder.regions();
  // (Each cell's corners ascending but for the last two, in a positive
  // order: the level's cells are positively oriented, so the parity of the
  // sort tells it; on every core.)
  constexpr size_t kRange = size_t{1} << 16;
  mesh.cells =
      collect_in_order<std::array<uint32_t, 4>>(order.size(), kRange, [&](size_t a, size_t b, auto& out) {
        for (size_t i = a; i < b; ++i)
          if (in_mesh[order[i]]) out.push_back(sorted_positive(dt.cells[order[i]]));
      });
  if (!regions.empty())
    for (uint32_t k : order)
      if (in_mesh[k]) mesh.region.push_back(regions[in_mesh[k] - 1u].label);
  for (const RegionLabel& r : regions)
    if (!r.name.empty()) mesh.region_names[r.label] = r.name;
  // With tagged faces (9.0): the surface's faces that have a tag.
  if (decoder.header().flags & kFlagFaces) {
    SurfaceFaces surface;
    const std::vector<uint8_t> tag = decoder.face_tags(dt, in_mesh, surface);
    if (!decoder.mesh_status().ok()) throw std::runtime_error(input + ": " + decoder.mesh_status().message());
    const std::vector<RegionLabel>& table = decoder.face_tag_table();
    for (size_t f = 0; f < surface.faces.size(); ++f) {
      if (tag[f] < 2) continue;
      mesh.faces.push_back(smallest_point_first(
          outward_triangle(dt, mesh.points, {surface.faces[f].cell, surface.faces[f].opposite}),
          mesh.points));
      mesh.face_tags.push_back(table[tag[f] - 2u].label);
    }
    for (const RegionLabel& t : table)
      if (!t.name.empty()) mesh.face_tag_names[t.label] = t.name;
  }
  // With cell data (10.0), level 0's cells carry it, in the same order.
  if (!decoder.cell_field_table().empty()) {
    const std::vector<FieldValues> cell_values = decoder.cell_data(dt, in_mesh, order);
    if (!decoder.mesh_status().ok()) throw std::runtime_error(input + ": " + decoder.mesh_status().message());
    for (const FieldValues& f : cell_values)
      mesh.cell_fields.push_back(
          {f.description.name, scalar_type(f.description.type), f.description.components, f.bits});
  }
  mesh.level = decoder.vertex_levels();
  mesh.boundary = boundary_vertices(dt, mesh.points.size(), in_mesh);
  for (const FieldValues& f : decoder.fields())
    mesh.fields.push_back(
        {f.description.name, scalar_type(f.description.type), f.description.components, f.bits});
  // With the nodes on level 0's edges (18.0, a second-order input's), which
  // edges have them, in the decoder's numbering.
  // With the input's numbering too (21.0), where the input put them among
  // the vertices.
  std::optional<EdgeNodeParts> edge_nodes;
  std::vector<uint32_t> node_numbering;
  if (with_edge_nodes && decoder.has_edge_nodes()) {
    ProgressiveDecoder::EdgeNodes nodes = decoder.edge_nodes(level);
    if (!decoder.mesh_status().ok()) throw std::runtime_error(input + ": " + decoder.mesh_status().message());
    node_numbering = decoder.node_order(nodes);
    if (!decoder.mesh_status().ok()) throw std::runtime_error(input + ": " + decoder.mesh_status().message());
    edge_nodes = edge_node_parts(std::move(nodes), mesh, dt, in_mesh);
  }
  // With the input's numbering (10.0, --keep-order): vertex k of the output
  // is the input's vertex k.
  std::vector<uint32_t> new_of_old;
  if (decoder.header().flags & kFlagVertexOrder) {
    const std::vector<uint32_t> numbering = decoder.vertex_order(dt);
    if (!decoder.mesh_status().ok()) throw std::runtime_error(input + ": " + decoder.mesh_status().message());
    if (!numbering.empty()) {
      renumber(mesh, numbering);
      new_of_old.resize(numbering.size());
      for (uint32_t k = 0; k < numbering.size(); ++k) new_of_old[numbering[k]] = k;
    }
  }
  if (edge_nodes) append_edge_nodes(mesh, *edge_nodes, new_of_old);
  // (The numbering names the vertices in the order just given, and node r
  // as the point after them that append_edge_nodes() made it.)
  if (!node_numbering.empty()) {
    if (new_of_old.empty() || node_numbering.size() != mesh.points.size())
      throw std::runtime_error(input + ": the node order does not name the level's vertices and nodes");
    renumber(mesh, node_numbering);
  }
  // With the input's node ids (22.0), each node's, in the numbering just
  // given: of all the nodes the stream labels (with edge nodes, only where
  // they are written).
  if ((decoder.header().flags & kFlagNodeLabels) && (!decoder.has_edge_nodes() || edge_nodes)) {
    mesh.node_labels = decoder.node_labels(mesh.points.size());
    if (!decoder.mesh_status().ok()) throw std::runtime_error(input + ": " + decoder.mesh_status().message());
  }
  return mesh;
}

bool numbers_edge_nodes(const ProgressiveDecoder& decoder) { return decoder.numbers_edge_nodes(); }

bool in_input_numbering(const ProgressiveDecoder& decoder) {
  return decoder.has_header() && (decoder.header().flags & kFlagVertexOrder) && decoder.finest_level() == 0;
}

OutputMesh cut_to_box(const OutputMesh& whole, const std::array<double, 3>& lo,
                      const std::array<double, 3>& hi, bool input_numbered) {
  constexpr uint32_t kNone = UINT32_MAX;
  const GridBox box = grid_box_of(whole.grid, lo, hi);
  OutputMesh out;
  out.grid = whole.grid;
  out.region_names = whole.region_names;
  out.face_tag_names = whole.face_tag_names;
  std::vector<uint32_t> index(whole.points.size(), kNone);
  std::vector<size_t> cells;
  for (size_t c = 0; c < whole.cells.size(); ++c) {
    if (!cell_meets(whole.points, whole.cells[c], box)) continue;
    cells.push_back(c);
    for (uint32_t v : whole.cells[c]) index[v] = 0;
  }
  OutputField ids{"vertex_id", ScalarType::kUInt32, 1, {}};
  for (uint32_t v = 0; v < whole.points.size(); ++v) {
    if (index[v] == kNone) continue;
    index[v] = static_cast<uint32_t>(out.points.size());
    out.points.push_back(whole.points[v]);
    ids.bits.push_back(v);
    if (!whole.node_labels.empty())
      out.node_labels.push_back(whole.node_labels[v]);
    else if (input_numbered)
      out.node_labels.push_back(int64_t{v} + 1);
    if (!whole.level.empty()) out.level.push_back(whole.level[v]);
    if (!whole.boundary.empty()) out.boundary.push_back(whole.boundary[v]);
  }
  // The rows `rows` of a field.
  const auto rows_of = [](const OutputField& f, const auto& rows) {
    OutputField kept{f.name, f.type, f.components, {}};
    const auto n = static_cast<size_t>(f.components);
    for (const size_t r : rows)
      kept.bits.insert(kept.bits.end(), f.bits.begin() + static_cast<std::ptrdiff_t>(r * n),
                       f.bits.begin() + static_cast<std::ptrdiff_t>((r + 1) * n));
    return kept;
  };
  out.fields.reserve(whole.fields.size() + 1);
  out.fields.push_back(std::move(ids));  // first, as region_output() puts it
  for (const OutputField& f : whole.fields) out.fields.push_back(rows_of(f, out.fields.front().bits));
  // The box's cells' faces, each turned out of its cell and starting at its
  // least corner (whole's numbers): a tagged face goes with the cell the
  // level's surface takes it from (out of which it is turned), as a bricked
  // stream's box and pieces give it (spec/FORMAT.md §3.5).
  static constexpr int kOutward[4][3] = {{1, 2, 3}, {0, 3, 2}, {0, 1, 3}, {0, 2, 1}};
  const auto from_least = [](std::array<uint32_t, 3> f) {
    std::rotate(f.begin(), std::min_element(f.begin(), f.end()), f.end());
    return f;
  };
  std::set<std::array<uint32_t, 3>> faces;
  for (const size_t c : cells) {
    const std::array<uint32_t, 4>& t = whole.cells[c];  // positively oriented
    out.cells.push_back({index[t[0]], index[t[1]], index[t[2]], index[t[3]]});
    if (!whole.region.empty()) out.region.push_back(whole.region[c]);
    if (whole.faces.empty()) continue;
    for (const auto& o : kOutward)
      faces.insert(from_least(
          {t[static_cast<size_t>(o[0])], t[static_cast<size_t>(o[1])], t[static_cast<size_t>(o[2])]}));
  }
  for (const OutputField& f : whole.cell_fields) out.cell_fields.push_back(rows_of(f, cells));
  for (size_t i = 0; i < whole.faces.size(); ++i) {
    if (!faces.contains(from_least(whole.faces[i]))) continue;
    const std::array<uint32_t, 3>& f = whole.faces[i];
    out.faces.push_back({index[f[0]], index[f[1]], index[f[2]]});
    out.face_tags.push_back(whole.face_tags[i]);
  }
  return out;
}

OutputMesh region_output(const RegionMesh& region, const Grid& grid) {
  OutputMesh mesh;
  mesh.grid = grid;
  mesh.declare_level = true;
  // (A tagged face is written as a cell whose region is its tag.)
  mesh.declare_region = !region.regions.empty() || !region.face_tags.empty();
  mesh.points = region.points;
  mesh.cells = region.cells;  // positively oriented, as the whole level's
  mesh.level = region.vertex_levels;
  OutputField ids{"vertex_id", ScalarType::kUInt32, 1, {}};
  ids.bits.assign(region.vertex_ids.begin(), region.vertex_ids.end());
  mesh.fields.push_back(std::move(ids));
  for (const FieldValues& f : region.fields)
    mesh.fields.push_back(
        {f.description.name, scalar_type(f.description.type), f.description.components, f.bits});
  // With regions, each cell's label and the labels' names.
  mesh.region.reserve(region.cell_regions.size());
  for (uint8_t r : region.cell_regions) mesh.region.push_back(region.regions.at(r - 1u).label);
  for (const RegionLabel& r : region.regions)
    if (!r.name.empty()) mesh.region_names[r.label] = r.name;
  for (const FieldValues& f : region.cell_fields)
    mesh.cell_fields.push_back(
        {f.description.name, scalar_type(f.description.type), f.description.components, f.bits});
  // With tagged faces, the cells' tagged surface faces and the tags' names.
  mesh.faces.reserve(region.faces.size());
  for (const auto& face : region.faces) mesh.faces.push_back(smallest_point_first(face, mesh.points));
  for (uint8_t t : region.face_labels) mesh.face_tags.push_back(region.face_tags.at(t - 2u).label);
  for (const RegionLabel& t : region.face_tags)
    if (!t.name.empty()) mesh.face_tag_names[t.label] = t.name;
  return mesh;
}

}  // namespace dtm
