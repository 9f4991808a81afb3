// What the vertex order section's encoder and decoder share (spec/FORMAT.md
// §3.9): the model, the unvisited vertices as a Fenwick tree of counts, and
// the candidates a step offers. Both sides must compute them identically.
#pragma once

#include <cstdint>
#include <vector>

#include "bitstream/range_coder.h"
#include "common/csr.h"

namespace dtm {

struct VertexOrderModels {
  // Whether the next vertex is an unvisited neighbour of the last, by how
  // many there are (1, 2-3, 4-7, 8-15, 16+).
  AdaptiveBit near[5];
  AdaptiveBit& near_for(size_t candidates) {
    size_t k = 0;
    while (k < 4 && (size_t{2} << k) <= candidates) ++k;
    return near[k];
  }
};

// The vertices not yet named, in ascending number: count, rank of a vertex,
// the vertex of a rank, removal; each O(log n).
class UnvisitedVertices {
 public:
  explicit UnvisitedVertices(size_t n) : tree_(n + 1, 0), visited_(n, 0), left_(n) {
    for (size_t i = 1; i <= n; ++i) {
      tree_[i] += 1;
      if (const size_t up = i + (i & (~i + 1)); up <= n) tree_[up] += tree_[i];
    }
    while ((top_ << 1) <= n) top_ <<= 1;
  }
  size_t left() const { return left_; }
  bool visited(uint32_t v) const { return visited_[v] != 0; }
  // How many unvisited vertices come before v.
  uint32_t rank(uint32_t v) const {
    uint32_t r = 0;
    for (size_t i = v; i > 0; i &= i - 1) r += tree_[i];
    return r;
  }
  // The unvisited vertex of rank r (r < left()).
  uint32_t at(uint32_t r) const {
    size_t pos = 0;
    for (size_t step = top_; step > 0; step >>= 1)
      if (pos + step < tree_.size() && tree_[pos + step] <= r) {
        pos += step;
        r -= tree_[pos];
      }
    return static_cast<uint32_t>(pos);
  }
  void visit(uint32_t v) {
    visited_[v] = 1;
    --left_;
    for (size_t i = size_t{v} + 1; i < tree_.size(); i += i & (~i + 1)) --tree_[i];
  }

 private:
  std::vector<uint32_t> tree_;
  std::vector<uint8_t> visited_;
  size_t left_;
  size_t top_ = 1;
};

// The unvisited neighbours of `last`, ascending.
inline void unvisited_neighbours(const Csr& neighbours, uint32_t last, const UnvisitedVertices& unvisited,
                                 std::vector<uint32_t>& out) {
  out.clear();
  for (uint32_t v : neighbours.row(last))
    if (!unvisited.visited(v)) out.push_back(v);
}

}  // namespace dtm
