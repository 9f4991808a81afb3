// NRRD scalar volumes (http://teem.sourceforge.net/nrrd/format.html): a text
// header ("NRRD0001".."NRRD0005", "field: value" lines) followed by the data
// (.nrrd) or naming a detached data file (.nhdr + "data file: X.raw").
// Three axes, one scalar per voxel, the first axis varying fastest.
// Encodings raw, gzip and ascii; any integer type up to 32 bits, float, double.
#pragma once

#include <array>
#include <cstdint>
#include <string>

#include "scalar_type.h"

namespace dtm {

struct Volume {
  std::array<uint64_t, 3> sizes{0, 0, 0};
  // Voxel (i, j, k) is at origin + i * directions[0] + j * directions[1] +
  // k * directions[2] ("space directions", or diagonal "spacings"; default
  // 1 on each axis).
  std::array<std::array<double, 3>, 3> directions{{{1, 0, 0}, {0, 1, 0}, {0, 0, 1}}};
  std::array<double, 3> origin{0, 0, 0};
  ScalarType type = ScalarType::kUInt8;
  bool big_endian = false;
  std::string data;  // sizes[0] * sizes[1] * sizes[2] values, decoded

  uint64_t voxels() const { return sizes[0] * sizes[1] * sizes[2]; }
  double at(uint64_t i, uint64_t j, uint64_t k) const {
    return scalar_at(data.data() + ((k * sizes[1] + j) * sizes[0] + i) * scalar_size(type), type, big_endian);
  }
};

// Throws FormatError naming the header (and line) or the data file and the problem.
Volume read_nrrd(const std::string& path);

// Decompresses a gzip (or zlib) stream that must inflate to exactly
// `expected` bytes; throws FormatError naming `path` otherwise.
std::string gunzip(std::string_view compressed, uint64_t expected, const std::string& path);

}  // namespace dtm
