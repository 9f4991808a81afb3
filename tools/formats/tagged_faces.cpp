// One tag a face (tagged_faces.h).
#include "tagged_faces.h"

#include <algorithm>
#include <set>

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

}  // namespace dtm
