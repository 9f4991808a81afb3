// Small helpers shared by the writers: numbers as text that read back to the
// same value, and fixed-width binary values in a chosen byte order.
#pragma once

#include <algorithm>
#include <bit>
#include <charconv>
#include <cstdint>
#include <string>
#include <type_traits>
#include <vector>

#include "common/parallel_for.h"
#include "common/threads.h"
#include "tools/formats/scalar_type.h"

namespace dtm {

// Shortest text that reads back to the same value (doubles bit-identical).
template <class T>
void append_number(std::string& out, T value) {
  char buf[32];
  if constexpr (sizeof(T) == 1 && std::is_integral_v<T>) {
    const auto [end, ec] = std::to_chars(buf, buf + sizeof buf, int{value});  // a number, not a char
    out.append(buf, end);
  } else {
    const auto [end, ec] = std::to_chars(buf, buf + sizeof buf, value);
    out.append(buf, end);
  }
}

// Appends line(0, s), ..., line(n - 1, s) to `out`, each writing one record
// to the string it is given: ranges of records on every core, appended in
// order a batch at a time (so that a large file's text is held about once,
// not twice).
template <class Line>
void append_lines(std::string& out, size_t n, const Line& line) {
  constexpr size_t kRecords = 16384;  // a range
  const size_t batch = 4 * static_cast<size_t>(std::max(1, thread_count())) * kRecords;
  std::vector<std::string> parts(batch / kRecords);
  for (size_t first = 0; first < n; first += batch) {
    const size_t count = std::min(batch, n - first);
    parallel_ranges(count, kRecords, [&](size_t a, size_t b) {
      std::string& part = parts[a / kRecords];
      part.clear();
      for (size_t i = a; i < b; ++i) line(first + i, part);
    });
    for (size_t p = 0; p < (count + kRecords - 1) / kRecords; ++p) out += parts[p];
  }
}

// "x y z\n", each coordinate as append_number writes it.
template <class P>
void append_xyz_line(std::string& out, const P& p) {
  append_number(out, p.x);
  out += ' ';
  append_number(out, p.y);
  out += ' ';
  append_number(out, p.z);
  out += '\n';
}

// `v` as little-endian (or big-endian) bytes whatever the host's byte order.
template <class T>
void append_binary(std::string& out, T v, bool big_endian = false) {
  using U = std::conditional_t<
      sizeof(T) == 1, uint8_t,
      std::conditional_t<sizeof(T) == 2, uint16_t, std::conditional_t<sizeof(T) == 4, uint32_t, uint64_t>>>;
  static_assert(sizeof(U) == sizeof(T));
  const U u = std::bit_cast<U>(v);
  for (size_t k = 0; k < sizeof(U); ++k) {
    const size_t shift = 8 * (big_endian ? sizeof(U) - 1 - k : k);
    out += static_cast<char>((u >> shift) & 0xff);
  }
}

// A value of type `t` given by its raw bits (an integer's two's complement,
// a float's IEEE bits), as scalar_size(t) bytes.
inline void append_scalar_binary(std::string& out, uint64_t bits, ScalarType t, bool big_endian = false) {
  const int n = scalar_size(t);
  for (int k = 0; k < n; ++k) out += static_cast<char>((bits >> (8 * (big_endian ? n - 1 - k : k))) & 0xff);
}

// The same as text that reads back to the same bits, NaN and infinities as
// "nan", "inf", "-inf". A float32 is written as the shortest text of its
// exact double, so that a reader of doubles (gmsh, TetGen) gets the value
// itself and one of floats the same float.
inline void append_scalar_text(std::string& out, uint64_t bits, ScalarType t) {
  switch (t) {
    case ScalarType::kFloat32:
      return append_number(out, static_cast<double>(std::bit_cast<float>(static_cast<uint32_t>(bits))));
    case ScalarType::kFloat64:
      return append_number(out, std::bit_cast<double>(bits));
    case ScalarType::kUInt64:
      return append_number(out, bits);
    default: {
      // Sign-extend from the type's width.
      const int shift = 64 - 8 * scalar_size(t);
      const bool is_signed = t == ScalarType::kInt8 || t == ScalarType::kInt16 || t == ScalarType::kInt32 ||
                             t == ScalarType::kInt64;
      if (is_signed) return append_number(out, static_cast<int64_t>(bits << shift) >> shift);
      return append_number(out, bits);
    }
  }
}

// The value of raw bits of type `t` as a double (64-bit integers above 2^53
// rounded).
inline double scalar_value(uint64_t bits, ScalarType t) {
  switch (t) {
    case ScalarType::kFloat32:
      return static_cast<double>(std::bit_cast<float>(static_cast<uint32_t>(bits)));
    case ScalarType::kFloat64:
      return std::bit_cast<double>(bits);
    case ScalarType::kUInt64:
      return static_cast<double>(bits);
    default: {
      const int shift = 64 - 8 * scalar_size(t);
      const bool is_signed = t == ScalarType::kInt8 || t == ScalarType::kInt16 || t == ScalarType::kInt32 ||
                             t == ScalarType::kInt64;
      if (is_signed) return static_cast<double>(static_cast<int64_t>(bits << shift) >> shift);
      return static_cast<double>(bits);
    }
  }
}

}  // namespace dtm
