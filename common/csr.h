// Compressed sparse rows: variable-length rows stored back to back, built in
// linear time by a counting sort (who touches whom in a tetrahedralization,
// which original points each vertex stands for), no hashing.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

namespace dtm {

// Row r is items[offsets[r] .. offsets[r+1]).
struct Csr {
  std::vector<uint32_t> offsets;
  std::vector<uint32_t> items;
  std::span<const uint32_t> row(size_t r) const {
    return {items.data() + offsets[r], items.data() + offsets[r + 1]};
  }
  size_t rows() const { return offsets.empty() ? 0 : offsets.size() - 1; }
};

// The CSR of `rows` rows holding the (row, item) pairs that
// `for_each_pair(emit)` passes to emit(row, item). It is called twice (once
// to count, once to fill) and must emit the same pairs both times; within a
// row, items keep the order they were emitted in.
template <class ForEachPair>
Csr build_csr(size_t rows, ForEachPair&& for_each_pair) {
  Csr out;
  out.offsets.assign(rows + 1, 0);
  for_each_pair([&](uint32_t row, uint32_t) { ++out.offsets[row + 1]; });
  for (size_t r = 0; r < rows; ++r) out.offsets[r + 1] += out.offsets[r];
  out.items.resize(out.offsets.back());
  std::vector<uint32_t> fill(out.offsets.begin(), out.offsets.end() - 1);
  for_each_pair([&](uint32_t row, uint32_t item) { out.items[fill[row]++] = item; });
  return out;
}

}  // namespace dtm
