// A decoded-level stand-in shared by the writer tests: torus_288 with its
// TetGen tetrahedra, boundary markers and made-up levels, and a helper that
// renders and writes it.
#pragma once

#include <gtest/gtest.h>

#include <string>

#include "test_support.h"
#include "tools/atomic_file.h"
#include "tools/formats/mesh_writers.h"
#include "tools/formats/tetgen.h"

namespace dtm::test {

inline OutputMesh torus_mesh() {
  const NodeFile node = read_tetgen_node(data_path("torus_288.node"));
  const QuantizedPoints q = quantize(node.points, 14).value();
  OutputMesh m;
  m.grid = q.grid;
  m.points = q.points;
  for (auto t : read_tetgen_ele(data_path("torus_288.ele"), node.points.size()))
    m.cells.push_back(
        {q.input_to_point[t[0]], q.input_to_point[t[1]], q.input_to_point[t[2]], q.input_to_point[t[3]]});
  m.boundary.assign(m.points.size(), 0);
  for (size_t i = 0; i < node.points.size(); ++i)
    if (node.markers[i]) m.boundary[q.input_to_point[i]] = 1;
  for (size_t i = 0; i < m.points.size(); ++i) m.level.push_back(static_cast<int32_t>(i % 7));
  return m;
}

// Renders `m` in `f` and writes the files under the test's temporary
// directory; returns the first path.
inline std::string write(const OutputMesh& m, MeshFormat f, const std::string& name) {
  const std::string path = ::testing::TempDir() + "/" + name;
  write_files_atomically(render_mesh(m, f, path));
  return path;
}

}  // namespace dtm::test
