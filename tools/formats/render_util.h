// Small helpers shared by the writers: numbers as text that read back to the
// same value, and fixed-width binary values in a chosen byte order.
#pragma once

#include <bit>
#include <charconv>
#include <cstdint>
#include <string>
#include <type_traits>

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

}  // namespace dtm
