#include "codec/sections/value_fields.h"

#include <cmath>
#include <utility>

#include "codec/sections/value_fields_shared.h"

namespace dtm {
namespace {

// std::bit_cast, which the WebAssembly build's libc++ (emscripten 3.1.6)
// does not have yet; the compiler builtin behind it is in both compilers.
template <class To, class From>
To bit_cast(const From& from) {
  return __builtin_bit_cast(To, from);
}

}  // namespace

// The smallest and largest ordered integers of a type (to_ordered's range).
std::pair<Int128, Int128> ordered_range(ValueType t) {
  switch (t) {
    case ValueType::kI8:
      return {INT8_MIN, INT8_MAX};
    case ValueType::kU8:
      return {0, UINT8_MAX};
    case ValueType::kI16:
      return {INT16_MIN, INT16_MAX};
    case ValueType::kU16:
      return {0, UINT16_MAX};
    case ValueType::kI32:
    case ValueType::kF32:
      return {INT32_MIN, INT32_MAX};
    case ValueType::kU32:
      return {0, UINT32_MAX};
    case ValueType::kI64:
    case ValueType::kF64:
      return {INT64_MIN, INT64_MAX};
    case ValueType::kU64:
      return {0, UINT64_MAX};
  }
  return {0, 0};
}

// What a chunk's predictor knows of a coarser point's value (spec §3.5):
// its ordered integer, for a lossy field the quantized value nearest the
// decoded one, from the decoded bits alone (encoder and decoder agree).
Int128 known_ordered(const FieldDescription& f, int component, uint64_t decoded_bits) {
  if (!f.lossy) return to_ordered(decoded_bits, f.type);
  const LossyScale& s = f.lossy_scales[static_cast<size_t>(component)];
  return static_cast<Int128>(std::llround((value_of(decoded_bits, f.type) - s.origin) / s.step));
}

const char* value_type_name(ValueType t) {
  constexpr const char* kNames[] = {"int8",   "uint8", "int16",  "uint16",  "int32",
                                    "uint32", "int64", "uint64", "float32", "float64"};
  return kNames[static_cast<int>(t)];
}

bool is_float(ValueType t) { return t == ValueType::kF32 || t == ValueType::kF64; }

uint64_t bits_of(double v, ValueType t) {
  switch (t) {
    case ValueType::kF32:
      return bit_cast<uint32_t>(static_cast<float>(v));
    case ValueType::kF64:
      return bit_cast<uint64_t>(v);
    case ValueType::kU64:
      v = std::round(v);
      return std::isfinite(v) && v >= 0 && v < 0x1p64 ? static_cast<uint64_t>(v) : 0;
    default: {
      // Every narrower integer fits an int64; its two's complement bits.
      const auto [lowest, highest] = ordered_range(t);
      v = std::round(v);
      if (!std::isfinite(v) || v < static_cast<double>(lowest) || v >= 0x1p63 ||
          v > static_cast<double>(highest))
        return 0;
      return static_cast<uint64_t>(static_cast<int64_t>(v));
    }
  }
}

double value_of(uint64_t bits, ValueType t) {
  switch (t) {
    case ValueType::kF32:
      return bit_cast<float>(static_cast<uint32_t>(bits));
    case ValueType::kF64:
      return bit_cast<double>(bits);
    case ValueType::kU64:
      return static_cast<double>(bits);
    default:
      return static_cast<double>(to_ordered(bits, t));
  }
}

}  // namespace dtm
