#include "core/face_tags.h"

#include <algorithm>

#include "common/checksum.h"

namespace dtm {
namespace {

std::array<uint32_t, 3> sorted(std::array<uint32_t, 3> t) {
  std::sort(t.begin(), t.end());
  return t;
}

}  // namespace

FaceTagger::FaceTagger(std::span<const GridPoint> points, std::span<const std::array<uint32_t, 3>> surface,
                       std::span<const std::array<uint32_t, 3>> tagged, std::span<const uint8_t> label)
    : points_(points), surface_(points, surface) {
  tagged_.reserve(tagged.size());
  for (size_t i = 0; i < tagged.size(); ++i) tagged_.emplace_back(sorted(tagged[i]), label[i]);
  // A triangle given twice keeps its first tag.
  std::stable_sort(tagged_.begin(), tagged_.end(),
                   [](const auto& a, const auto& b) { return a.first < b.first; });
  tagged_.erase(std::unique(tagged_.begin(), tagged_.end(),
                            [](const auto& a, const auto& b) { return a.first == b.first; }),
                tagged_.end());
  surface_label_.reserve(surface.size());
  for (const auto& t : surface) {
    const uint8_t own = own_label(sorted(t));
    surface_label_.push_back(own ? own : 1);
  }
}

uint8_t FaceTagger::own_label(std::array<uint32_t, 3> key) const {
  const auto it = std::lower_bound(tagged_.begin(), tagged_.end(), key,
                                   [](const auto& entry, const auto& k) { return entry.first < k; });
  return it != tagged_.end() && it->first == key ? it->second : 0;
}

std::vector<uint8_t> FaceTagger::labels(std::span<const std::array<uint32_t, 3>> faces) const {
  std::vector<uint8_t> out(faces.size(), 1);
  std::vector<uint32_t> other;
  std::vector<std::array<double, 3>> centroids;
  for (uint32_t f = 0; f < faces.size(); ++f) {
    if (const uint8_t own = own_label(sorted(faces[f]))) {
      out[f] = own;
      continue;
    }
    std::array<double, 3> c{0, 0, 0};
    for (uint32_t v : faces[f]) {
      c[0] += points_[v].x / 3.0, c[1] += points_[v].y / 3.0, c[2] += points_[v].z / 3.0;
    }
    other.push_back(f);
    centroids.push_back(c);
  }
  const std::vector<uint32_t> nearest = surface_.nearest_triangles(centroids);
  for (size_t i = 0; i < nearest.size(); ++i) out[other[i]] = surface_label_[nearest[i]];
  return out;
}

uint64_t FaceTagger::fingerprint() const {
  std::vector<uint8_t> bytes;
  bytes.reserve(tagged_.size() * 13 + surface_label_.size());
  for (const auto& [key, label] : tagged_) {
    for (uint32_t v : key)
      for (int b = 0; b < 4; ++b) bytes.push_back(static_cast<uint8_t>(v >> (8 * b)));
    bytes.push_back(label);
  }
  bytes.insert(bytes.end(), surface_label_.begin(), surface_label_.end());
  return xxh3_64(bytes);
}

size_t FaceTagger::tagged_among(std::span<const std::array<uint32_t, 3>> faces) const {
  size_t n = 0;
  for (const auto& f : faces) n += own_label(sorted(f)) != 0;
  return n;
}

}  // namespace dtm
