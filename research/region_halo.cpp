// region_halo STREAM.dtm -- research for region decoding (issue 25,
// research/bricks_plan.md §3): how much of a level must a reader decode
// to give exactly the cells of its finest level (the carved Delaunay
// tetrahedralization) that meet a box?
//
// Bricks are the nodes of the grid's octree at depth b (each axis cut into
// 2^b slabs). A reader decodes the points of the bricks meeting the box, plus
// r rings of neighbouring bricks, and builds their tetrahedralization. A cell
// of it is *certified* when its circumsphere (with a grid step to spare) lies
// inside the decoded bricks: no other point can be inside it, so it is a cell
// of the whole level's tetrahedralization. The carving keeps cells whose
// circumradius is at most alpha, give or take the corrections: cells far
// larger (the convex hull's, across the object's concavities) are carved
// away and need no certificate. The reader grows r until every cell meeting
// the box with a circumradius up to 2 alpha is certified. Per depth and over
// random boxes of a
// given share of the points' bounding box, this tool reports the rings that
// took, the share of the level's points decoded (what the chunks would cost
// in bytes), and checks the claim: every certified cell is a cell of the
// whole tetrahedralization, and every cell the level keeps that meets the
// box is among them ("meeting": the cell's bounding box meets the box; both
// sides use the same test).
//
// Environment: BOXES=n (default 20), SHARE=s (the box's volume over the
// bounding box's, default 0.01), DEPTHS=list (default 2,3,4,5).
#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iterator>
#include <random>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "bench/bench_env.h"
#include "codec/decode.h"
#include "mesh/delaunay.h"
#include "mesh/geometry.h"

namespace {

using dtm::GridPoint;
using Cell = std::array<uint32_t, 4>;

struct Box {
  std::array<double, 3> lo, hi;
};

Cell sorted(Cell c) {
  std::sort(c.begin(), c.end());
  return c;
}

std::array<double, 3> at(const GridPoint& p) {
  return {static_cast<double>(p.x), static_cast<double>(p.y), static_cast<double>(p.z)};
}

bool cell_meets(const Cell& c, std::span<const GridPoint> points, const Box& box) {
  for (int a = 0; a < 3; ++a) {
    double lo = 1e300, hi = -1e300;
    for (uint32_t v : c) lo = std::min(lo, at(points[v])[a]), hi = std::max(hi, at(points[v])[a]);
    if (hi < box.lo[a] || lo > box.hi[a]) return false;
  }
  return true;
}

// The circumsphere's centre and radius, in doubles (a grid step of margin
// covers their rounding on these grids); false for a flat cell.
bool circumsphere(const Cell& c, std::span<const GridPoint> points, dtm::Vec3& centre, double& radius) {
  using dtm::cross, dtm::dot;
  const dtm::Vec3 a = dtm::to_vec(points[c[0]]);
  const dtm::Vec3 u = dtm::to_vec(points[c[1]]) - a, v = dtm::to_vec(points[c[2]]) - a,
                  w = dtm::to_vec(points[c[3]]) - a;
  const double det = dot(u, cross(v, w));
  if (det == 0) return false;
  const dtm::Vec3 offset =
      (cross(v, w) * dot(u, u) + cross(w, u) * dot(v, v) + cross(u, v) * dot(w, w)) * (1 / (2 * det));
  centre = a + offset;
  radius = dtm::norm(offset);
  return true;
}

struct Bricks {
  int depth = 0, shift = 0;  // brick of coordinate v: v >> shift
  int side() const { return 1 << depth; }
  int of(int32_t v) const { return v >> shift; }
};

// The bricks within r rings of those meeting the box, as a 3D mask.
std::vector<uint8_t> decoded_bricks(const Bricks& b, const Box& box, int rings) {
  const int side = b.side();
  std::vector<uint8_t> mask(static_cast<size_t>(side) * side * side, 0);
  int lo[3], hi[3];
  for (int a = 0; a < 3; ++a) {
    lo[a] = std::max(0, b.of(static_cast<int32_t>(std::floor(box.lo[a]))) - rings);
    hi[a] = std::min(side - 1, b.of(static_cast<int32_t>(std::floor(box.hi[a]))) + rings);
  }
  for (int x = lo[0]; x <= hi[0]; ++x)
    for (int y = lo[1]; y <= hi[1]; ++y)
      for (int z = lo[2]; z <= hi[2]; ++z) mask[(static_cast<size_t>(x) * side + y) * side + z] = 1;
  return mask;
}

// The sphere, a grid step larger, inside decoded bricks only (outside the
// grid there are no points: that counts as decoded).
bool sphere_inside(const Bricks& b, const std::vector<uint8_t>& mask, const dtm::Vec3& centre, double r) {
  const double c[3] = {centre.x, centre.y, centre.z};
  const int side = b.side();
  int lo[3], hi[3];
  for (int a = 0; a < 3; ++a) {
    lo[a] = std::max(0, static_cast<int>(std::floor((c[a] - r - 1) / (1 << b.shift))));
    hi[a] = std::min(side - 1, static_cast<int>(std::floor((c[a] + r + 1) / (1 << b.shift))));
  }
  for (int x = lo[0]; x <= hi[0]; ++x)
    for (int y = lo[1]; y <= hi[1]; ++y)
      for (int z = lo[2]; z <= hi[2]; ++z)
        if (!mask[(static_cast<size_t>(x) * side + y) * side + z]) return false;
  return true;
}

}  // namespace

using dtm::bench::env_or;

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr, "usage: region_halo STREAM.dtm\n");
    return 2;
  }
  std::ifstream in(argv[1], std::ios::binary);
  const std::vector<uint8_t> bytes((std::istreambuf_iterator<char>(in)), {});
  dtm::ProgressiveDecoder decoder;
  if (const dtm::Status s = dtm::decode_stream(bytes, decoder); !s.ok()) {
    std::fprintf(stderr, "%s: %s\n", argv[1], s.message().c_str());
    return 1;
  }
  const int level = decoder.finest_level();
  const int qbits = decoder.header().grid.qbits;
  const double alpha = decoder.levels().back().alpha;
  const std::span<const GridPoint> points(decoder.points());
  const auto whole = dtm::delaunay_tetrahedralize(points);
  if (!whole.ok()) return 1;
  std::set<Cell> global;
  for (const Cell& c : whole.value().cells) global.insert(sorted(c));
  std::vector<Cell> kept;
  for (const Cell& c : decoder.carved_cells()) kept.push_back(sorted(c));
  size_t kept_large = 0;
  for (const Cell& c : kept) {
    dtm::Vec3 centre;
    double radius = 0;
    kept_large += circumsphere(c, points, centre, radius) && radius > 2 * alpha;
  }

  Box bounds{{1e300, 1e300, 1e300}, {-1e300, -1e300, -1e300}};
  for (const GridPoint& p : points)
    for (int a = 0; a < 3; ++a)
      bounds.lo[a] = std::min(bounds.lo[a], at(p)[a]), bounds.hi[a] = std::max(bounds.hi[a], at(p)[a]);
  const int boxes = static_cast<int>(env_or("BOXES", 20));
  const double share = env_or("SHARE", 0.01);
  std::vector<int> depths;
  {
    std::stringstream list(std::getenv("DEPTHS") ? std::getenv("DEPTHS") : "2,3,4,5");
    for (std::string item; std::getline(list, item, ',');) depths.push_back(std::stoi(item));
  }
  std::printf(
      "%s, level %d: %zu points, %zu cells, %zu kept (%zu of them with a circumradius over 2 alpha); %d "
      "boxes of "
      "%.3g of the bounding box's volume\n\n",
      argv[1], level, points.size(), global.size(), kept.size(), kept_large, boxes, share);
  std::printf(
      "| depth | bricks with points | points per brick | rings needed (min / mean / max) | points in the box "
      "(mean) | "
      "points decoded (mean, max) | kept cells meeting the box (mean) | certified cells not in the "
      "tetrahedralization | "
      "kept cells meeting the box not found (of them over 2 alpha) "
      "|\n|---:|---:|---:|---|---:|---|---:|---:|---:|\n");
  for (const int depth : depths) {
    Bricks b{depth, qbits - depth};
    std::set<int> occupied;
    for (const GridPoint& p : points)
      occupied.insert((b.of(p.x) * b.side() + b.of(p.y)) * b.side() + b.of(p.z));
    std::mt19937 rng(7);
    int ring_min = 1 << 30, ring_max = 0;
    double ring_sum = 0, inside_sum = 0, decoded_sum = 0, decoded_max = 0, meeting_sum = 0;
    size_t wrong = 0, missing = 0, missing_large = 0;
    for (int t = 0; t < boxes; ++t) {
      Box box;
      const double scale = std::cbrt(share);
      for (int a = 0; a < 3; ++a) {
        const double extent = (bounds.hi[a] - bounds.lo[a]) * scale;
        std::uniform_real_distribution<double> start(bounds.lo[a], bounds.hi[a] - extent);
        box.lo[a] = start(rng), box.hi[a] = box.lo[a] + extent;
      }
      size_t inside = 0;
      for (const GridPoint& p : points) {
        bool in = true;
        for (int a = 0; a < 3; ++a) in = in && at(p)[a] >= box.lo[a] && at(p)[a] <= box.hi[a];
        inside += in;
      }
      inside_sum += static_cast<double>(inside) / static_cast<double>(points.size());
      std::vector<Cell> expected;
      for (const Cell& c : kept)
        if (cell_meets(c, points, box)) expected.push_back(c);
      for (int rings = 0;; ++rings) {
        const std::vector<uint8_t> mask = decoded_bricks(b, box, rings);
        std::vector<GridPoint> local;
        std::vector<uint32_t> ids;
        for (uint32_t i = 0; i < points.size(); ++i) {
          const GridPoint& p = points[i];
          if (mask[(static_cast<size_t>(b.of(p.x)) * b.side() + b.of(p.y)) * b.side() + b.of(p.z)])
            local.push_back(p), ids.push_back(i);
        }
        bool complete = local.size() >= 4;
        std::vector<Cell> found;
        if (complete) {
          const auto dt = dtm::delaunay_tetrahedralize(local);
          complete = dt.ok();
          for (size_t k = 0; complete && k < dt.value().cells.size(); ++k) {
            const Cell& c = dt.value().cells[k];
            if (!cell_meets(c, local, box)) continue;
            dtm::Vec3 centre;
            double radius = 0;
            if (!circumsphere(c, local, centre, radius)) continue;  // flat: no cell of the level
            if (radius > 2 * alpha) continue;                       // carved away
            if (!sphere_inside(b, mask, centre, radius)) {
              complete = false;
              break;
            }
            found.push_back(sorted({ids[c[0]], ids[c[1]], ids[c[2]], ids[c[3]]}));
          }
        }
        if (!complete && rings < b.side()) continue;
        std::sort(found.begin(), found.end());
        for (const Cell& c : found) wrong += !global.count(c);
        for (const Cell& c : expected) {
          if (std::binary_search(found.begin(), found.end(), c)) continue;
          ++missing;
          dtm::Vec3 centre;
          double radius = 0;
          missing_large += circumsphere(c, points, centre, radius) && radius > 2 * alpha;
        }
        ring_min = std::min(ring_min, rings), ring_max = std::max(ring_max, rings);
        ring_sum += rings;
        const double decoded = static_cast<double>(local.size()) / static_cast<double>(points.size());
        decoded_sum += decoded, decoded_max = std::max(decoded_max, decoded);
        meeting_sum += static_cast<double>(expected.size());
        break;
      }
    }
    std::printf("| %d | %zu | %.0f | %d / %.2f / %d | %.2f%% | %.1f%%, %.1f%% | %.0f | %zu | %zu (%zu) |\n",
                depth, occupied.size(),
                static_cast<double>(points.size()) / static_cast<double>(occupied.size()), ring_min,
                ring_sum / boxes, ring_max, 100 * inside_sum / boxes, 100 * decoded_sum / boxes,
                100 * decoded_max, meeting_sum / boxes, wrong, missing, missing_large);
    std::fflush(stdout);
  }
  return 0;
}
