#include "surface_writers.h"

#include <algorithm>

#include "render_util.h"

namespace dtm {

std::vector<std::array<uint32_t, 3>> boundary_triangles(std::span<const std::array<uint32_t, 4>> cells) {
  // Outward faces of a positively oriented (a, b, c, d): d lies on the
  // right-hand normal side of (a, b, c), so that face turns the other way.
  static constexpr int kFaces[4][3] = {{1, 2, 3}, {0, 3, 2}, {0, 1, 3}, {0, 2, 1}};
  struct Face {
    uint32_t second, third;             // the sorted key after its smallest vertex
    std::array<uint32_t, 3> oriented;
  };
  if (cells.empty()) return {};
  // Faces are bucketed by their smallest vertex (a counting sort), then each
  // small bucket is sorted: the two sides of an inner face meet in one
  // bucket. The output is in ascending key order, as one global sort would
  // give, at a fraction of its cost (this runs once per level in meshenc).
  uint32_t top = 0;
  for (const auto& t : cells) top = std::max({top, t[0], t[1], t[2], t[3]});
  std::vector<uint32_t> first(static_cast<size_t>(top) + 2, 0);
  const auto smallest = [](const std::array<uint32_t, 4>& t, const int* f) {
    return std::min({t[f[0]], t[f[1]], t[f[2]]});
  };
  for (const auto& t : cells)
    for (const auto& f : kFaces) ++first[smallest(t, f) + 1];
  for (size_t v = 0; v + 1 < first.size(); ++v) first[v + 1] += first[v];
  std::vector<Face> faces(4 * cells.size());
  std::vector<uint32_t> fill(first.begin(), first.end() - 1);
  for (const auto& t : cells)
    for (const auto& f : kFaces) {
      std::array<uint32_t, 3> key = {t[f[0]], t[f[1]], t[f[2]]};
      std::sort(key.begin(), key.end());
      faces[fill[key[0]]++] = {key[1], key[2], {t[f[0]], t[f[1]], t[f[2]]}};
    }
  std::vector<std::array<uint32_t, 3>> out;
  for (size_t v = 0; v + 1 < first.size(); ++v) {
    const auto begin = faces.begin() + first[v], end = faces.begin() + first[v + 1];
    std::sort(begin, end, [](const Face& a, const Face& b) {
      return a.second != b.second ? a.second < b.second : a.third < b.third;
    });
    for (auto i = begin; i != end;) {
      auto j = i;
      while (j != end && j->second == i->second && j->third == i->third) ++j;
      if (j - i == 1) out.push_back(i->oriented);
      i = j;
    }
  }
  return out;
}

BoundarySurface boundary_surface(const OutputMesh& m) {
  const auto kept = boundary_triangles(m.cells);
  BoundarySurface out;
  std::vector<int64_t> local(m.points.size(), -1);
  for (const auto& f : kept)
    for (uint32_t v : f) local[v] = 0;
  for (uint32_t v = 0; v < m.points.size(); ++v)
    if (local[v] == 0) {
      local[v] = static_cast<int64_t>(out.vertices.size());
      out.vertices.push_back(v);
    }
  for (const auto& f : kept)
    out.triangles.push_back({static_cast<uint32_t>(local[f[0]]), static_cast<uint32_t>(local[f[1]]),
                             static_cast<uint32_t>(local[f[2]])});
  return out;
}

std::string render_ply(const OutputMesh& m) {
  const BoundarySurface s = boundary_surface(m);
  const bool level = !m.level.empty();
  std::string out = "ply\nformat binary_little_endian 1.0\ncomment written by dtmesh: boundary surface\n";
  out += "element vertex " + std::to_string(s.vertices.size()) + "\n";
  out += "property double x\nproperty double y\nproperty double z\n";
  if (level) out += "property int level\n";
  out += "element face " + std::to_string(s.triangles.size()) + "\n";
  out += "property list uchar int vertex_indices\nend_header\n";
  for (uint32_t v : s.vertices) {
    const InputPoint p = m.grid.to_input(m.points[v]);
    append_binary(out, p.x);
    append_binary(out, p.y);
    append_binary(out, p.z);
    if (level) append_binary(out, int32_t{m.level[v]});
  }
  for (const auto& t : s.triangles) {
    append_binary(out, uint8_t{3});
    for (uint32_t v : t) append_binary(out, static_cast<int32_t>(v));
  }
  return out;
}

std::string render_off(const OutputMesh& m) {
  const BoundarySurface s = boundary_surface(m);
  std::string out = "OFF\n";
  out += std::to_string(s.vertices.size()) + " " + std::to_string(s.triangles.size()) + " 0\n";
  for (uint32_t v : s.vertices) {
    const InputPoint p = m.grid.to_input(m.points[v]);
    append_xyz_line(out, p);
  }
  for (const auto& t : s.triangles) {
    out += '3';
    for (uint32_t v : t) {
      out += ' ';
      append_number(out, v);
    }
    out += '\n';
  }
  return out;
}

std::string render_xyz(const OutputMesh& m) {
  std::string out;
  out.reserve(m.points.size() * 60);
  for (const GridPoint& g : m.points) {
    const InputPoint p = m.grid.to_input(g);
    append_xyz_line(out, p);
  }
  return out;
}

}  // namespace dtm
