// Helpers for the format tests: running the tools and Debian's Python (the
// independent readers meshio and VTK live there), and reading files whole.
#pragma once

#include <gtest/gtest.h>

#include <bit>
#include <fstream>
#include <sstream>
#include <string>

#include "test_support.h"  // run_command()

namespace dtm::test {

// Debian's python3-meshio and python3-vtk9 live in /usr/lib/python3/dist-packages,
// which only Debian's interpreter sees (a pyenv or venv python3 would not).
inline const std::string kPython = "/usr/bin/python3";

inline std::string slurp(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

inline std::string bad_file(const std::string& name) {
  return std::string(DTM_TEST_SOURCE_DIR) + "/bad/" + name;
}

inline bool same_double(double a, double b) {
  return std::bit_cast<uint64_t>(a) == std::bit_cast<uint64_t>(b);
}

}  // namespace dtm::test
