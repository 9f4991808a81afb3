// web/level_view.h, natively (and so under ASan and UBSan in CI): each
// level's view agrees with the decoder's own mesh functions, its cell
// neighbours are mutual, and hostile bytes (every truncation of a golden
// stream, random bit flips) end in an error or a prefix of the levels, never
// a crash.
#include <gtest/gtest.h>

#include <algorithm>
#include <fstream>
#include <iterator>
#include <random>

#include "codec/decode.h"
#include "mesh/carving.h"
#include "mesh/topology.h"
#include "web/level_view.h"

namespace dtm {
namespace {

std::vector<uint8_t> golden_bytes(const std::string& name) {
  std::ifstream in(std::string(DTM_TEST_SOURCE_DIR) + "/golden/" + name, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), {}};
}

// Triangles with their smallest vertex first, sorted: a set to compare.
std::vector<std::array<uint32_t, 3>> canonical(std::vector<std::array<uint32_t, 3>> triangles) {
  for (auto& t : triangles) std::rotate(t.begin(), std::min_element(t.begin(), t.end()), t.end());
  std::sort(triangles.begin(), triangles.end());
  return triangles;
}

TEST(LevelView, EveryLevelAgreesWithTheDecodersMesh) {
  for (const char* name : {"torus_288.dtm", "torus_288_grid_q10_hull.dtm", "v4/torus_288_paper.dtm",
                           "two_materials.dtm", "two_materials_exact.dtm"}) {
    const auto bytes = golden_bytes(name);
    ASSERT_FALSE(bytes.empty()) << name;
    LevelViewer viewer;
    ProgressiveDecoder reference;
    size_t levels = 0;
    // The reference decoder, fed the same bytes, stops at each level in turn.
    for (size_t at = 0; at < bytes.size(); at += 100) {
      ASSERT_TRUE(viewer.feed(std::span(bytes.data() + at, std::min<size_t>(100, bytes.size() - at))).ok());
      while (viewer.has_level()) {
        const LevelView view = viewer.take_level();
        DecoderOptions options;
        options.stop_after_level = view.level;
        ProgressiveDecoder one(options);
        ASSERT_TRUE(decode_stream(bytes, one).ok());
        const auto cells = one.carved_cells();
        EXPECT_EQ(view.vertices, one.points().size()) << name;
        EXPECT_EQ(cell_set_hash(one.points(), view.cells), cell_set_hash(one.points(), cells)) << name;
        EXPECT_EQ(canonical(view.surface), canonical(boundary_triangles(cells)))
            << name << " level " << view.level;
        // Each cell's and each surface face's region: the decoder's (1 where
        // the stream has none).
        const ProgressiveDecoder::LevelCells level = one.level_cells();
        ASSERT_EQ(view.cell_regions.size(), view.cells.size()) << name;
        ASSERT_EQ(view.surface_regions.size(), view.surface.size()) << name;
        const size_t regions = std::max<size_t>(1, one.regions().size());
        for (uint8_t r = 1; r <= regions; ++r) {
          std::vector<std::array<uint32_t, 4>> seen, decoded;
          for (size_t c = 0; c < view.cells.size(); ++c)
            if (view.cell_regions[c] == r) seen.push_back(view.cells[c]);
          for (size_t c = 0; c < level.mesh.cells.size(); ++c)
            if (level.kept[c] == r) decoded.push_back(level.mesh.cells[c]);
          EXPECT_FALSE(seen.empty()) << name << " region " << int{r};
          EXPECT_EQ(cell_set_hash(one.points(), seen), cell_set_hash(one.points(), decoded))
              << name << " level " << view.level << " region " << int{r};
          std::vector<std::array<uint32_t, 3>> faces;
          for (size_t f = 0; f < view.surface.size(); ++f)
            if (view.surface_regions[f] == r) faces.push_back(view.surface[f]);
          // (A region's faces on the level's surface: those of its own
          // surface that are no other region's.)
          std::vector<std::array<uint32_t, 3>> outer;
          const auto whole = canonical(boundary_triangles(cells));
          for (const auto& t : canonical(boundary_triangles(decoded)))
            if (std::binary_search(whole.begin(), whole.end(), t)) outer.push_back(t);
          EXPECT_EQ(canonical(faces), outer) << name << " level " << view.level << " region " << int{r};
        }
        // The boundary flags: on a face of exactly one cell, or in no cell.
        std::vector<uint8_t> flags(one.points().size(), 1);
        for (const auto& t : cells)
          for (uint32_t v : t) flags[v] = 0;
        for (const auto& f : boundary_triangles(cells))
          for (uint32_t v : f) flags[v] = 1;
        EXPECT_EQ(view.boundary, flags) << name << " level " << view.level;
        // Neighbours are mutual and share the face.
        for (size_t c = 0; c < view.cells.size(); ++c)
          for (int i = 0; i < 4; ++i) {
            const int32_t n = view.cell_neighbors[c][i];
            if (n < 0) continue;
            const auto& back = view.cell_neighbors[n];
            EXPECT_NE(std::find(back.begin(), back.end(), static_cast<int32_t>(c)), back.end());
            int shared = 0;
            for (int k = 0; k < 4; ++k)
              shared += k != i && std::count(view.cells[n].begin(), view.cells[n].end(), view.cells[c][k]);
            EXPECT_EQ(shared, 3);
          }
        // The new points in input units about the grid's centre, as floats.
        const auto centre = grid_centre(one.header().grid);
        ASSERT_EQ(view.new_positions.size(), 3 * size_t{view.vertices - view.first_new});
        for (uint32_t v = view.first_new; v < view.vertices; ++v) {
          const InputPoint p = one.header().grid.to_input(one.points()[v]);
          EXPECT_EQ(view.new_positions[3 * (v - view.first_new)], static_cast<float>(p.x - centre[0]));
          EXPECT_EQ(view.new_positions[3 * (v - view.first_new) + 2], static_cast<float>(p.z - centre[2]));
        }
        ++levels;
      }
    }
    EXPECT_TRUE(viewer.finish().ok()) << name;
    EXPECT_EQ(levels, viewer.decoder().header().level_count) << name;
  }
}

TEST(LevelView, EveryTruncationEndsOnAWholeLevel) {
  const auto bytes = golden_bytes("torus_288.dtm");
  ProgressiveDecoder whole;
  ASSERT_TRUE(decode_stream(bytes, whole).ok());
  for (size_t n = 0; n < bytes.size(); ++n) {
    LevelViewer viewer;
    ASSERT_TRUE(viewer.feed(std::span(bytes.data(), n)).ok()) << n;
    EXPECT_EQ(viewer.finish().code(), StatusCode::kTruncated) << n;
    size_t levels = 0;
    while (viewer.has_level()) {
      const LevelView view = viewer.take_level();
      EXPECT_EQ(view.vertices, whole.levels()[levels].vertices);
      EXPECT_LE(view.stream_bytes, n);
      ++levels;
    }
    EXPECT_EQ(levels, viewer.decoder().levels().size());
  }
}

TEST(LevelView, BitFlipsEndInAnErrorOrTheSameLevels) {
  const auto bytes = golden_bytes("torus_288.dtm");
  ProgressiveDecoder whole;
  ASSERT_TRUE(decode_stream(bytes, whole).ok());
  std::mt19937 random(14);
  for (int trial = 0; trial < 3000; ++trial) {
    std::vector<uint8_t> damaged = bytes;
    damaged[random() % damaged.size()] ^= static_cast<uint8_t>(1u << (random() % 8));
    LevelViewer viewer;
    const Status fed = viewer.feed(damaged);
    const Status end = viewer.finish();
    // Damage is said by feed(), or, where a layer's length was damaged so
    // that it runs past the stream's end, by finish(), once the end is known.
    if (!fed.ok()) {
      EXPECT_FALSE(end.ok() || end.code() == StatusCode::kTruncated);
    } else if (!end.ok() && end.code() != StatusCode::kTruncated) {
      EXPECT_NE(end.message().find("a section length in its layer header is damaged"), std::string::npos)
          << end.message();
    }
    // Every byte is under a checksum: a flip never decodes as the whole.
    EXPECT_FALSE(fed.ok() && end.ok()) << "trial " << trial;
    // The levels shown before the damage are the stream's own.
    for (size_t k = 0; viewer.has_level(); ++k) {
      const LevelView view = viewer.take_level();
      ASSERT_LT(k, whole.levels().size());
      EXPECT_EQ(view.level, whole.levels()[k].level) << "trial " << trial;
      EXPECT_EQ(view.vertices, whole.levels()[k].vertices) << "trial " << trial;
    }
  }
}

}  // namespace
}  // namespace dtm
