// Tagged faces as sides of their cells (face_sides.h).
#include "face_sides.h"

#include <algorithm>
#include <unordered_map>

namespace dtm {

std::vector<CellSide> tagged_face_sides(
    const OutputMesh& m, const std::function<std::array<uint32_t, 3>(uint32_t cell, uint8_t side)>& outward) {
  struct FaceHash {
    size_t operator()(const std::array<uint32_t, 3>& f) const {
      return std::hash<uint64_t>()((uint64_t{f[0]} << 42) ^ (uint64_t{f[1]} << 21) ^ f[2]);
    }
  };
  const auto sorted = [](std::array<uint32_t, 3> f) {
    std::sort(f.begin(), f.end());
    return f;
  };
  // The tagged faces by their corners, sorted; then each cell side that is
  // one.
  std::unordered_map<std::array<uint32_t, 3>, uint32_t, FaceHash> face_of;
  for (uint32_t f = 0; f < m.faces.size(); ++f) face_of.emplace(sorted(m.faces[f]), f);
  std::vector<CellSide> out(m.faces.size());
  std::vector<bool> turned_out(m.faces.size(), false);
  for (uint32_t c = 0; c < m.cells.size(); ++c)
    for (uint8_t s = 0; s < 4; ++s) {
      const std::array<uint32_t, 3> o = outward(c, s);
      const auto it = face_of.find(sorted(o));
      if (it == face_of.end()) continue;
      const uint32_t f = it->second;
      bool turns_out = false;
      for (int r = 0; r < 3; ++r)
        turns_out |= o[static_cast<size_t>(r)] == m.faces[f][0] &&
                     o[static_cast<size_t>((r + 1) % 3)] == m.faces[f][1];
      if (out[f].cell == CellSide::kNoCell || (turns_out && !turned_out[f]))
        out[f] = {c, s}, turned_out[f] = turns_out;
    }
  return out;
}

}  // namespace dtm
