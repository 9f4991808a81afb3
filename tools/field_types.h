// The readers' ScalarType and the codec's ValueType name the same ten types
// in the same order: a field passes between them by its index.
#pragma once

#include "codec/sections/value_coder.h"
#include "tools/formats/scalar_type.h"

namespace dtm {

static_assert(static_cast<int>(ScalarType::kInt8) == static_cast<int>(ValueType::kI8) &&
                  static_cast<int>(ScalarType::kUInt64) == static_cast<int>(ValueType::kU64) &&
                  static_cast<int>(ScalarType::kFloat32) == static_cast<int>(ValueType::kF32) &&
                  static_cast<int>(ScalarType::kFloat64) == static_cast<int>(ValueType::kF64),
              "ScalarType and ValueType must list the types in the same order");

constexpr ValueType value_type(ScalarType t) { return static_cast<ValueType>(t); }
constexpr ScalarType scalar_type(ValueType t) { return static_cast<ScalarType>(t); }

}  // namespace dtm
