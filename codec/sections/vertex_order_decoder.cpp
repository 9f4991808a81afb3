// The vertex order section read (spec/FORMAT.md §3.9), and the neighbour
// lists both sides build.
#include <algorithm>

#include "codec/sections/vertex_order_coder.h"
#include "codec/sections/vertex_order_coder_shared.h"

namespace dtm {

Csr vertex_neighbours(size_t vertices, std::span<const std::array<uint32_t, 4>> cells) {
  Csr all = build_csr(vertices, [&](auto&& emit) {
    for (const auto& c : cells)
      for (int a = 0; a < 4; ++a)
        for (int b = 0; b < 4; ++b)
          if (a != b) emit(c[static_cast<size_t>(a)], c[static_cast<size_t>(b)]);
  });
  // Each row ascending, without repeats (an edge is in several cells).
  Csr out;
  out.offsets.assign(vertices + 1, 0);
  out.items.reserve(all.items.size() / 4);
  for (size_t v = 0; v < vertices; ++v) {
    std::vector<uint32_t> row(all.row(v).begin(), all.row(v).end());
    std::sort(row.begin(), row.end());
    row.erase(std::unique(row.begin(), row.end()), row.end());
    out.items.insert(out.items.end(), row.begin(), row.end());
    out.offsets[v + 1] = static_cast<uint32_t>(out.items.size());
  }
  return out;
}

Status decode_vertex_order(std::span<const uint8_t> section, const Csr& neighbours,
                           std::vector<uint32_t>& order) {
  const size_t n = neighbours.rows();
  order.clear();
  order.reserve(n);
  RangeDecoder rc(section);
  VertexOrderModels models;
  UnvisitedVertices unvisited(n);
  std::vector<uint32_t> near;
  for (size_t k = 0; k < n; ++k) {
    uint32_t v = 0;
    if (k > 0) unvisited_neighbours(neighbours, order.back(), unvisited, near);
    if (k > 0 && !near.empty() && rc.decode(models.near_for(near.size()))) {
      uint64_t i = 0;
      if (!rc.decode_index(near.size(), i).ok()) return {StatusCode::kCorrupt, "vertex order: a bad index"};
      v = near[i];
    } else {
      uint64_t r = 0;
      if (!rc.decode_index(unvisited.left(), r).ok())
        return {StatusCode::kCorrupt, "vertex order: a bad rank"};
      v = unvisited.at(static_cast<uint32_t>(r));
    }
    if (rc.overran()) return {StatusCode::kCorrupt, "vertex order: the section ends early"};
    unvisited.visit(v);
    order.push_back(v);
  }
  if (!rc.finished_cleanly()) return {StatusCode::kCorrupt, "vertex order: bytes after its last vertex's"};
  return Status::Ok();
}

}  // namespace dtm
