// One tag a face (tagged_faces.h).
#include "tagged_faces.h"

#include <algorithm>
#include <map>
#include <set>
#include <unordered_map>

namespace dtm {

std::string add_tagged_faces_once(InputMesh& mesh, const std::vector<std::array<uint32_t, 3>>& faces,
                                  const std::vector<int32_t>& tags) {
  std::set<std::array<uint32_t, 3>> seen;
  uint64_t twice = 0;
  for (size_t i = 0; i < faces.size(); ++i) {
    auto key = faces[i];
    std::sort(key.begin(), key.end());
    if (!seen.insert(key).second) {
      ++twice;
      continue;
    }
    mesh.tagged_faces.push_back(faces[i]);
    mesh.face_tags.push_back(tags[i]);
  }
  return twice ? std::to_string(twice) + " faces tagged a second time (each keeps its first tag)"
               : std::string();
}

uint64_t tagged_faces_inside(const std::vector<std::array<uint32_t, 4>>& tets,
                             const std::vector<int32_t>& regions,
                             const std::vector<std::array<uint32_t, 3>>& faces) {
  if (faces.empty()) return 0;
  // Per tagged face (sorted corners): the tetrahedra met on it, and whether
  // two of them lie in different regions.
  struct Seen {
    uint8_t cells = 0;
    bool interface = false;
    int32_t region = 0;
  };
  const auto key = [](std::array<uint32_t, 3> f) {
    std::sort(f.begin(), f.end());
    return f;
  };
  struct Hash {
    size_t operator()(const std::array<uint32_t, 3>& f) const {
      return (uint64_t{f[0]} * 0x9E3779B97F4A7C15ull) ^ (uint64_t{f[1]} * 0xC2B2AE3D27D4EB4Full) ^ f[2];
    }
  };
  std::unordered_map<std::array<uint32_t, 3>, Seen, Hash> seen;
  seen.reserve(faces.size());
  for (const auto& f : faces) seen.emplace(key(f), Seen{});
  for (size_t t = 0; t < tets.size(); ++t)
    for (int k = 0; k < 4; ++k) {
      const auto& c = tets[t];
      const auto it = seen.find(key({c[(k + 1) % 4], c[(k + 2) % 4], c[(k + 3) % 4]}));
      if (it == seen.end()) continue;
      const int32_t region = regions.empty() ? 0 : regions[t];
      Seen& s = it->second;
      if (s.cells > 0 && region != s.region) s.interface = true;
      s.region = region;
      s.cells = static_cast<uint8_t>(std::min(2, s.cells + 1));
    }
  uint64_t inside = 0;
  for (const auto& f : faces) {
    const Seen& s = seen.at(key(f));
    inside += s.cells == 0 || (s.cells == 2 && !s.interface);
  }
  return inside;
}

std::string tagged_faces_inside_note(uint64_t inside, uint64_t total) {
  return std::to_string(inside) + " of the " + std::to_string(total) +
         " tagged triangles, inside a region or no face of the tetrahedra (a tagged face is one of the "
         "surface's, or between two regions)";
}

}  // namespace dtm
