#include "tools/formats/surface_writers.h"

#include <algorithm>

#include "mesh/topology.h"
#include "render_util.h"

namespace dtm {

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
  // Fields as properties in their own type (PLY has no 64-bit integers:
  // those become doubles), one per component. Of PLY's two names for a
  // type, the one meshio's binary reader knows: it knows neither of int16's
  // (short, int16) and takes uchar for signed.
  constexpr const char* kTypeNames[] = {"int8", "uint8",  "short",  "uint16", "int",
                                        "uint", "double", "double", "float",  "double"};
  for (const OutputField& f : m.fields)
    for (int c = 0; c < f.components; ++c) {
      // A PLY name ends at a blank.
      std::string name = f.components > 1 ? f.name + "_" + std::to_string(c) : f.name;
      std::replace(name.begin(), name.end(), ' ', '_');
      out += std::string("property ") + kTypeNames[static_cast<int>(f.type)] + " " + name + "\n";
    }
  out += "element face " + std::to_string(s.triangles.size()) + "\n";
  out += "property list uint8 int vertex_indices\nend_header\n";
  for (uint32_t v : s.vertices) {
    const InputPoint p = m.grid.to_input(m.points[v]);
    append_binary(out, p.x);
    append_binary(out, p.y);
    append_binary(out, p.z);
    if (level) append_binary(out, int32_t{m.level[v]});
    for (const OutputField& f : m.fields)
      for (int c = 0; c < f.components; ++c) {
        const uint64_t bits = f.bits[size_t{v} * f.components + c];
        if (f.type == ScalarType::kInt64)
          append_binary(out, static_cast<double>(static_cast<int64_t>(bits)));
        else if (f.type == ScalarType::kUInt64)
          append_binary(out, static_cast<double>(bits));
        else
          append_scalar_binary(out, bits, f.type);
      }
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
