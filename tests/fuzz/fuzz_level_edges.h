// The level the edge node targets (fuzz_edge_nodes.cpp, fuzz_edge_values.cpp)
// read their sections over: the Delaunay cells of one of fuzz_point_sets.h's
// point sets, those of them a pattern keeps (0-3: all, every other, two in
// three, one in five), and the edges of the kept cells in the cells' order.
#pragma once

#include <array>
#include <cstdint>
#include <numeric>
#include <vector>

#include "codec/sections/edge_node_coder.h"
#include "fuzz_point_sets.h"
#include "mesh/delaunay.h"

struct FuzzLevel {
  const dtm::TetMesh& mesh;
  std::vector<uint8_t> kept;
  dtm::LevelEdges edges;
};

inline FuzzLevel fuzz_level(bool cloud, int pattern) {
  static const std::array<dtm::TetMesh, 2> meshes = {
      dtm::delaunay_tetrahedralize(fuzz_point_set(false)).value(),
      dtm::delaunay_tetrahedralize(fuzz_point_set(true)).value()};
  const dtm::TetMesh& mesh = meshes[cloud ? 1 : 0];
  std::vector<uint8_t> kept(mesh.cells.size());
  constexpr int kEvery[] = {1, 2, 3, 5};
  for (size_t c = 0; c < kept.size(); ++c)
    kept[c] = pattern == 2 ? c % 3 != 0 : c % static_cast<size_t>(kEvery[pattern]) == 0;
  std::vector<uint32_t> order(mesh.cells.size());
  std::iota(order.begin(), order.end(), 0u);
  dtm::LevelEdges edges = dtm::level_edges(mesh, kept, order);
  return {mesh, std::move(kept), std::move(edges)};
}
