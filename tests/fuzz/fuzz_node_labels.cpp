// The node label section (spec/FORMAT.md §3.14) on arbitrary bytes, below
// the layer checksum that keeps the stream targets from reaching it
// damaged: never a crash; a section that decodes gives the ids asked for,
// each in range and no two alike, which code again to a section that
// decodes to the same ids.
//
// Input: bytes 0-1: how many ids (1 + their value modulo 4096, little
// endian); then the section.
#include <cstdint>
#include <span>
#include <vector>

#include "codec/sections/node_label_coder.h"
#include "fuzz_check.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size < 2) return 0;
  const size_t count = 1 + (size_t{data[0]} | size_t{data[1]} << 8) % 4096;
  std::vector<int64_t> labels;
  const dtm::Status s = dtm::decode_node_labels(std::span(data + 2, size - 2), count, labels);
  if (!s.ok()) {
    FUZZ_CHECK(s.code() == dtm::StatusCode::kCorrupt);
    return 0;
  }
  FUZZ_CHECK(labels.size() == count && dtm::valid_node_labels(labels));
  std::vector<int64_t> back;
  FUZZ_CHECK(dtm::decode_node_labels(dtm::encode_node_labels(labels), count, back).ok());
  FUZZ_CHECK(back == labels);
  return 0;
}
