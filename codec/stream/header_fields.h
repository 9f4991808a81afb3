// The stream's field lists (its header and each layer's), written and read
// field by field as visit_fields() (format.h) lists them: what the reader
// (format.cpp, the decoder library) and the writers (format_encoder.cpp,
// the encoder library) share. Internal to codec/stream/.
#pragma once

#include <span>
#include <type_traits>

#include "codec/stream/format.h"
#include "common/byte_io.h"
#include "common/checksum.h"

namespace dtm::header_fields {

template <class Wire>
void put(ByteWriter& w, Wire v) {
  if constexpr (std::is_same_v<Wire, double>)
    w.f64(v);
  else if constexpr (sizeof(Wire) == 1)
    w.u8(v);
  else if constexpr (sizeof(Wire) == 2)
    w.u16(v);
  else if constexpr (sizeof(Wire) == 4)
    w.u32(v);
  else
    w.u64(v);
}

template <class Wire>
Wire get(ByteReader& r) {
  Wire v{};
  if constexpr (std::is_same_v<Wire, double>)
    r.f64(v);
  else if constexpr (sizeof(Wire) == 1)
    r.u8(v);
  else if constexpr (sizeof(Wire) == 2)
    r.u16(v);
  else if constexpr (sizeof(Wire) == 4)
    r.u32(v);
  else
    r.u64(v);
  return v;
}

// Writes a field list. The checksum covers the bytes before it, then
// `trailer` (a layer's payload; empty for the stream header), and keeps
// only as many low bits as its field holds.
struct FieldWriter {
  ByteWriter w;
  std::span<const uint8_t> trailer;
  void magic(const char*) { w.bytes(kMagic); }
  template <class Wire, class T>
  void field(const char*, const T& v) {
    put<Wire>(w, static_cast<Wire>(v));
  }
  template <class Wire, class T, size_t N>
  void field(const char* name, const std::array<T, N>& a) {
    for (const T& v : a) field<Wire>(name, v);
  }
  template <class Wire, class T>
  void checksum(const char*, T& v) {
    v = static_cast<T>(xxh3_64(w.data(), trailer));
    put<Wire>(w, static_cast<Wire>(v));
  }
};

// Reads a field list from bytes known to hold it whole.
struct FieldReader {
  ByteReader r;
  void magic(const char*) {
    for (size_t i = 0; i < kMagic.size(); ++i) get<uint8_t>(r);
  }
  template <class Wire, class T>
  void field(const char*, T& v) {
    v = static_cast<T>(get<Wire>(r));
  }
  template <class Wire, class T, size_t N>
  void field(const char* name, std::array<T, N>& a) {
    for (T& v : a) field<Wire>(name, v);
  }
  template <class Wire, class T>
  void checksum(const char* name, T& v) {
    field<Wire>(name, v);
  }
};

template <class Header>
Header read_fields(std::span<const uint8_t> bytes, uint8_t format_major = kVersionMajor, bool bricked = false,
                   uint16_t stream_flags = 0) {
  Header h;
  if constexpr (requires { h.format_major; })
    h.format_major = format_major, h.bricked = bricked, h.stream_flags = stream_flags;
  FieldReader reader{ByteReader(bytes)};
  visit_fields(h, reader);
  return h;
}

}  // namespace dtm::header_fields
