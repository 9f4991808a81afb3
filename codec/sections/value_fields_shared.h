// What the value section's encoder (value_fields_encoder.cpp) and decoder
// (value_fields_decoder.cpp) share beyond value_fields.h: the range of a
// type's ordered integers and what a bricked chunk knows of a coarser
// point's value (spec/FORMAT.md §3.3, §3.5). Both sides must compute them
// identically; they are written here once.
#pragma once

#include <cstdint>
#include <utility>

#include "codec/sections/value_fields.h"

namespace dtm {

// The smallest and largest ordered integers of a type (to_ordered's range).
std::pair<Int128, Int128> ordered_range(ValueType t);

// What a chunk's predictor knows of a coarser point's value (spec §3.5):
// its ordered integer, for a lossy field the quantized value nearest the
// decoded one, from the decoded bits alone (encoder and decoder agree).
Int128 known_ordered(const FieldDescription& f, int component, uint64_t decoded_bits);

}  // namespace dtm
