// A level's surface faces, as encoder and decoder find them (face_coder.h).
#include "codec/sections/face_coder.h"

#include <algorithm>

namespace dtm {

SurfaceFaces surface_faces(const TetMesh& dt, std::span<const uint8_t> kept) {
  static constexpr int kFace[4][3] = {{1, 2, 3}, {0, 2, 3}, {0, 1, 3}, {0, 1, 2}};
  SurfaceFaces s;
  for (uint32_t c = 0; c < dt.cells.size(); ++c) {
    if (!kept[c]) continue;
    for (int i = 0; i < 4; ++i) {
      const int32_t n = dt.neighbors[c][static_cast<size_t>(i)];
      const uint8_t other = n < 0 ? 0 : kept[static_cast<size_t>(n)];
      // The boundary, and each interface once (from its lower region).
      if (other != 0 && other <= kept[c]) continue;
      SurfaceFace f;
      f.cell = c;
      f.opposite = static_cast<uint8_t>(i);
      for (int k = 0; k < 3; ++k)
        f.key[static_cast<size_t>(k)] = dt.cells[c][static_cast<size_t>(kFace[i][k])];
      std::sort(f.key.begin(), f.key.end());
      s.faces.push_back(f);
    }
  }
  std::sort(s.faces.begin(), s.faces.end(),
            [](const SurfaceFace& a, const SurfaceFace& b) { return a.key < b.key; });
  // Faces sharing an edge: each face's three edges, sorted by edge.
  std::vector<std::pair<std::array<uint32_t, 2>, uint32_t>> edges;
  edges.reserve(3 * s.faces.size());
  for (uint32_t f = 0; f < s.faces.size(); ++f) {
    const auto& k = s.faces[f].key;
    edges.push_back({{k[0], k[1]}, f});
    edges.push_back({{k[0], k[2]}, f});
    edges.push_back({{k[1], k[2]}, f});
  }
  std::sort(edges.begin(), edges.end());
  s.neighbours = build_csr(s.faces.size(), [&](auto&& add) {
    for (size_t a = 0; a < edges.size();) {
      size_t b = a;
      while (b < edges.size() && edges[b].first == edges[a].first) ++b;
      for (size_t i = a; i < b; ++i)
        for (size_t j = a; j < b; ++j)
          if (i != j) add(edges[i].second, edges[j].second);
      a = b;
    }
  });
  return s;
}

}  // namespace dtm
