// The fixed-width number types of binary mesh and volume files (VTK, NRRD),
// and how to read one value of each from raw bytes in either byte order.
#pragma once

#include <bit>
#include <cstdint>
#include <cstring>
#include <string_view>

namespace dtm {

enum class ScalarType {
  kInt8,
  kUInt8,
  kInt16,
  kUInt16,
  kInt32,
  kUInt32,
  kInt64,
  kUInt64,
  kFloat32,
  kFloat64
};

constexpr int scalar_size(ScalarType t) {
  switch (t) {
    case ScalarType::kInt8:
    case ScalarType::kUInt8:
      return 1;
    case ScalarType::kInt16:
    case ScalarType::kUInt16:
      return 2;
    case ScalarType::kInt32:
    case ScalarType::kUInt32:
    case ScalarType::kFloat32:
      return 4;
    default:
      return 8;
  }
}

// "int8" ... "uint64", "float32", "float64".
constexpr const char* scalar_name(ScalarType t) {
  constexpr const char* kNames[] = {"int8",   "uint8", "int16",  "uint16",  "int32",
                                    "uint32", "int64", "uint64", "float32", "float64"};
  return kNames[static_cast<int>(t)];
}

constexpr bool is_integer(ScalarType t) { return t != ScalarType::kFloat32 && t != ScalarType::kFloat64; }

// The value at `p` (scalar_size(t) bytes) as a double. 64-bit integers above
// 2^53 lose precision; indices that large are rejected by range checks anyway.
// The `size`-byte unsigned integer at p (a header word: a count that may
// be anything in a damaged file, so never read through a double).
inline uint64_t unsigned_at(const char* p, int size, bool big_endian) {
  uint64_t u = 0;
  for (int k = 0; k < size; ++k)
    u |= uint64_t{static_cast<uint8_t>(p[big_endian ? k : size - 1 - k])} << (8 * (size - 1 - k));
  return u;
}

inline double scalar_at(const char* p, ScalarType t, bool big_endian) {
  uint8_t b[8];
  const int n = scalar_size(t);
  for (int k = 0; k < n; ++k) b[k] = static_cast<uint8_t>(p[big_endian ? n - 1 - k : k]);
  uint64_t u = 0;
  for (int k = n - 1; k >= 0; --k) u = (u << 8) | b[k];  // little-endian value in u
  switch (t) {
    case ScalarType::kInt8:
      return static_cast<int8_t>(u);
    case ScalarType::kUInt8:
      return static_cast<uint8_t>(u);
    case ScalarType::kInt16:
      return static_cast<int16_t>(u);
    case ScalarType::kUInt16:
      return static_cast<uint16_t>(u);
    case ScalarType::kInt32:
      return static_cast<int32_t>(u);
    case ScalarType::kUInt32:
      return static_cast<uint32_t>(u);
    case ScalarType::kInt64:
      return static_cast<double>(static_cast<int64_t>(u));
    case ScalarType::kUInt64:
      return static_cast<double>(u);
    case ScalarType::kFloat32:
      return std::bit_cast<float>(static_cast<uint32_t>(u));
    case ScalarType::kFloat64:
      return std::bit_cast<double>(u);
  }
  return 0;
}

}  // namespace dtm
