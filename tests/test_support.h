// Helpers shared by the tests: corpus access and canonical comparisons.
#pragma once

#include <algorithm>
#include <array>
#include <cstdio>
#include <random>
#include <set>
#include <string>
#include <vector>

#include "common/grid.h"
#include "common/threads.h"
#include "core/quantize.h"
#include "mesh/delaunay.h"
#include "tools/formats/tetgen.h"

namespace dtm::test {

inline const std::vector<std::string> kCorpus = {"torus_288", "bunny_10k", "elephant_10k", "fandisk_11k",
                                                 "hand_10k",  "knot1_10k", "torus_10k",    "triceratops_10k"};

inline std::string data_path(const std::string& name) { return std::string(DTM_TEST_DATA_DIR) + "/" + name; }

// Sets the process's thread count (common/threads.h) while it lives.
struct Threads {
  explicit Threads(int n) { set_thread_count(n); }
  ~Threads() { set_thread_count(0); }
  Threads(const Threads&) = delete;
  Threads& operator=(const Threads&) = delete;
};

// A command run through the shell, as a user runs the tools: its exit
// status (pclose's; -1 if it could not start) and what it printed.
struct CommandRun {
  int status;
  std::string output;  // stdout and stderr
};
inline CommandRun run_command(const std::string& cmd) {
  CommandRun r{-1, {}};
  std::FILE* p = popen((cmd + " 2>&1").c_str(), "r");
  if (!p) return r;
  char buf[4096];
  while (size_t n = std::fread(buf, 1, sizeof buf, p)) r.output.append(buf, n);
  r.status = pclose(p);
  return r;
}

inline QuantizedPoints load_quantized(const std::string& model, int qbits = 14) {
  return quantize(read_tetgen_node(data_path(model + ".node")).points, qbits).value();
}

// A tetrahedron named by its corner coordinates, corners sorted: independent
// of vertex ids and of CGAL's cell and vertex order.
using CellByCoords = std::array<GridPoint, 4>;

inline std::vector<CellByCoords> cells_by_coords(const TetMesh& mesh,
                                                 const std::vector<GridPoint>& point_of_id) {
  std::vector<CellByCoords> out;
  out.reserve(mesh.cells.size());
  for (const auto& c : mesh.cells) {
    CellByCoords t = {point_of_id[c[0]], point_of_id[c[1]], point_of_id[c[2]], point_of_id[c[3]]};
    std::sort(t.begin(), t.end());
    out.push_back(t);
  }
  std::sort(out.begin(), out.end());
  return out;
}

// Every point of an n x n x n block of the grid: the most cospherical input.
inline std::vector<GridPoint> full_grid(int n) {
  std::vector<GridPoint> out;
  for (int x = 0; x < n; ++x)
    for (int y = 0; y < n; ++y)
      for (int z = 0; z < n; ++z) out.push_back({x, y, z});
  return out;
}

// `count` distinct random points of a `bits`-bit grid.
inline std::vector<GridPoint> random_grid_points(size_t count, int bits, uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_int_distribution<int32_t> coord(0, (1 << bits) - 1);
  std::set<GridPoint> set;
  while (set.size() < count) set.insert({coord(rng), coord(rng), coord(rng)});
  return {set.begin(), set.end()};
}

}  // namespace dtm::test
