// Decoding a region of a bricked stream against decoding the whole level
// (issue 25, spec/FORMAT.md §4.1): for random boxes of a share of the level's
// bounding box, the bytes the region reads from the file, its time, and its
// cells, checked against the whole level filtered to the box.
//
//   build/bench/region_decode STREAM.dtm [LEVEL]     (env BOXES=12, SHARE=0.01)
//
// Prints one line per box, then a markdown row: boxes, the share of the
// level's points the boxes hold, bytes read (mean, max) and time against the
// whole decode (mean). Exit status 1 if a region differs from the whole
// level's.
#include "codec/region_decode.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iterator>
#include <random>
#include <string>

#include "bench/bench_env.h"

namespace {

double seconds_since(std::chrono::steady_clock::time_point t) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();
}

}  // namespace

using dtm::bench::env_or;

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr, "usage: %s STREAM.dtm [LEVEL]   (env BOXES, SHARE)\n", argv[0]);
    return 2;
  }
  const std::string path = argv[1];
  const int level = argc > 2 ? std::atoi(argv[2]) : 0;
  const int boxes = static_cast<int>(env_or("BOXES", 12));
  const double share = env_or("SHARE", 0.01);
  std::ifstream file(path, std::ios::binary);
  const std::vector<uint8_t> bytes((std::istreambuf_iterator<char>(file)), {});

  // The whole level, timed as a reader of the file would: read, decode, carve.
  const auto start = std::chrono::steady_clock::now();
  dtm::DecoderOptions options;
  options.stop_after_level = level;
  dtm::ProgressiveDecoder whole(options);
  {
    std::ifstream again(path, std::ios::binary);
    const std::vector<uint8_t> read((std::istreambuf_iterator<char>(again)), {});
    if (const dtm::Status s = dtm::decode_stream(read, whole); !s.ok()) {
      std::fprintf(stderr, "%s: %s\n", path.c_str(), s.message().c_str());
      return 2;
    }
  }
  const size_t whole_cells = whole.carved_cells().size();
  const double whole_seconds = seconds_since(start);

  dtm::GridBox bounds{{INT64_MAX, INT64_MAX, INT64_MAX}, {INT64_MIN, INT64_MIN, INT64_MIN}};
  for (const dtm::GridPoint& p : whole.points()) {
    const int64_t c[3] = {p.x, p.y, p.z};
    for (int a = 0; a < 3; ++a)
      bounds.lo[a] = std::min(bounds.lo[a], c[a]), bounds.hi[a] = std::max(bounds.hi[a], c[a]);
  }
  std::printf("%s level %d: %zu points, %zu cells, %zu bytes; whole decode %.3f s\n", path.c_str(), level,
              whole.points().size(), whole_cells, bytes.size(), whole_seconds);

  std::mt19937 rng(1);
  const double side = std::cbrt(share);
  double read_sum = 0, read_max = 0, time_sum = 0, points_sum = 0;
  int wrong = 0;
  for (int b = 0; b < boxes; ++b) {
    dtm::GridBox box;
    for (int a = 0; a < 3; ++a) {
      const int64_t w = static_cast<int64_t>(side * static_cast<double>(bounds.hi[a] - bounds.lo[a]));
      box.lo[a] = std::uniform_int_distribution<int64_t>(bounds.lo[a], bounds.hi[a] - w)(rng);
      box.hi[a] = box.lo[a] + w;
    }
    size_t inside = 0;
    for (const dtm::GridPoint& p : whole.points()) inside += box.contains(p);
    const auto t = std::chrono::steady_clock::now();
    auto source = dtm::FileSource::open(path);
    if (!source.ok()) return 2;
    const auto region = dtm::decode_region(*source, box, level);
    const double s = seconds_since(t);
    if (!region.ok()) {
      std::fprintf(stderr, "box %d: %s\n", b, region.status().message().c_str());
      return 1;
    }
    const dtm::RegionMesh want = dtm::region_of(whole, box);
    const bool same = region->cells == want.cells && region->vertex_ids == want.vertex_ids;
    wrong += !same;
    const double read = static_cast<double>(region->bytes_read) / static_cast<double>(bytes.size());
    const double points = static_cast<double>(inside) / static_cast<double>(whole.points().size());
    std::printf(
        "box %2d: %6.2f%% of the points, %7zu cells%s; read %6.2f%% of the bytes (%llu chunks), %.3f s = "
        "%.2fx the whole decode\n",
        b, 100 * points, region->cells.size(), same ? "" : " DIFFERENT", 100 * read,
        static_cast<unsigned long long>(region->chunks_read), s, s / whole_seconds);
    read_sum += read, read_max = std::max(read_max, read), time_sum += s / whole_seconds,
                      points_sum += points;
  }
  std::printf("| %d | %.2f%% | %.1f%% | %.1f%% | %.2fx |\n", boxes, 100 * points_sum / boxes,
              100 * read_sum / boxes, 100 * read_max, time_sum / boxes);
  return wrong ? 1 : 0;
}
