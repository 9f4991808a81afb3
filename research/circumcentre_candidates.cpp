// circumcentre_candidates STREAM.dtm ... -- research for the layer coder
// (issue 23, research/point_models.md §4): would a layer cost less if
// the points near the coarse level's circumcentres were sent as "a new point
// beside this circumcentre"?
//
// TetGen refines by inserting Steiner points at circumcentres of bad cells,
// so a finer level's new points often sit at (within a grid step of) the
// circumcentre of a cell of the coarser level's Delaunay tetrahedralization,
// which the decoder holds before the layer arrives. The candidate model:
//   1. the candidates are the coarse cells' circumcentres rounded to the grid
//      (distinct, inside the grid, not a known point), in Morton order;
//   2. each candidate gets one adaptive bit: is there a new point within one
//      grid step (Chebyshev) of it; its context is what the decoder knows of
//      the cell (its circumradius against its shortest edge, whether the
//      circumcentre is inside the cell);
//   3. a hit sends which of the 27 positions, adaptively;
//   4. the layer's other points go through the shipped set coder, the hits
//      known to it like the coarser levels' points.
// Reported per layer, in bits: the shipped coder on the whole layer (real
// range-coder bytes, fresh models), and the candidate model's flags +
// offsets (ideal adaptive lengths) + the shipped coder on the rest.
//
// Variants by environment: KINDS=cells,faces,edges (which candidates:
// circumcentres of cells and of faces, midpoints of edges; default cells),
// RADIUS=r (a hit is within r grid steps per axis; default 1), NOINSIDE=1
// (the centre context without "inside its cell"). Format 7.0 shipped cells
// and edges, radius 1, without "inside" (spec/FORMAT.md §3.4).
#include <CGAL/Delaunay_triangulation_3.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Triangulation_vertex_base_with_info_3.h>

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iterator>
#include <string>
#include <unordered_map>
#include <vector>

#include "codec/decode.h"
#include "codec/stream/layer_coder.h"

namespace {

using K = CGAL::Exact_predicates_inexact_constructions_kernel;
using Vb = CGAL::Triangulation_vertex_base_with_info_3<uint32_t, K>;
using Tds = CGAL::Triangulation_data_structure_3<Vb>;
using DT = CGAL::Delaunay_triangulation_3<K, Tds>;
using Point = K::Point_3;
using dtm::GridPoint;
using dtm::MortonCode;

// An ideal adaptive binary model (Krichevsky-Trofimov counts).
struct IdealBit {
  double n[2] = {0.4, 0.4};
  double code(int bit) {
    const double cost = -std::log2(n[bit] / (n[0] + n[1]));
    n[bit] += 1;
    return cost;
  }
};

struct IdealSymbol {
  std::vector<double> n;
  explicit IdealSymbol(int k) : n(k, 0.4) {}
  double code(int s) {
    double total = 0;
    for (double c : n) total += c;
    const double cost = -std::log2(n[s] / total);
    n[s] += 1;
    return cost;
  }
};

struct Candidate {
  MortonCode code;
  GridPoint at;
  int context;
};

constexpr int kRatioBuckets = 12;  // log2(R / shortest edge) in half octaves from 2^-1

int context_of(const DT::Cell_handle c, const Point& centre) {
  // What the shipped rule can compute exactly: the rounded centre's squared
  // distance to vertex 0 against the shortest edge's, by bit widths.
  int64_t shortest = INT64_MAX;
  auto sq = [](const Point& a, const Point& b) {
    const int64_t dx = std::llround(a.x() - b.x()), dy = std::llround(a.y() - b.y()),
                  dz = std::llround(a.z() - b.z());
    return dx * dx + dy * dy + dz * dz;
  };
  for (int i = 0; i < 4; ++i)
    for (int j = i + 1; j < 4; ++j)
      shortest = std::min(shortest, sq(c->vertex(i)->point(), c->vertex(j)->point()));
  const Point rounded(std::round(centre.x()), std::round(centre.y()), std::round(centre.z()));
  const int64_t r2 = sq(rounded, c->vertex(0)->point());
  const int bucket = std::clamp(static_cast<int>(std::bit_width(static_cast<uint64_t>(r2))) -
                                    static_cast<int>(std::bit_width(static_cast<uint64_t>(shortest))) + 2,
                                0, kRatioBuckets - 1);
  if (std::getenv("NOINSIDE")) return bucket * 2;
  // Inside the cell: the centre is on the inner side of every face.
  bool inside = true;
  for (int i = 0; i < 4 && inside; ++i) {
    const Point& a = c->vertex((i + 1) & 3)->point();
    const Point& b = c->vertex((i + 2) & 3)->point();
    const Point& d = c->vertex((i + 3) & 3)->point();
    const Point& opposite = c->vertex(i)->point();
    inside = CGAL::orientation(a, b, d, centre) == CGAL::orientation(a, b, d, opposite);
  }
  return bucket * 2 + (inside ? 1 : 0);
}

int radius() {
  const char* r = std::getenv("RADIUS");
  return r ? std::atoi(r) : 1;
}

struct LayerResult {
  size_t fresh = 0, candidates = 0, hits = 0;
  double shipped = 0, flags = 0, offsets = 0, rest = 0;
};

LayerResult measure(const std::vector<GridPoint>& points, size_t coarse, size_t fine, int qbits) {
  LayerResult out;
  out.fresh = fine - coarse;
  std::vector<MortonCode> known;
  for (size_t i = 0; i < coarse; ++i) known.push_back(dtm::morton_encode(points[i], qbits));
  std::sort(known.begin(), known.end());
  const std::vector<GridPoint> fresh(points.begin() + coarse, points.begin() + fine);
  {
    dtm::SetCoderModels models;
    models.enable_coordinate_reuse(qbits);
    out.shipped = 8.0 * dtm::encode_point_set(known, fresh, qbits, models).size();
  }
  std::vector<std::pair<Point, uint32_t>> pts;
  for (size_t i = 0; i < coarse; ++i)
    pts.emplace_back(Point(points[i].x, points[i].y, points[i].z), static_cast<uint32_t>(i));
  DT dt(pts.begin(), pts.end());
  const int64_t side = int64_t{1} << qbits;
  std::vector<Candidate> candidates;
  const std::string kinds = std::getenv("KINDS") ? std::getenv("KINDS") : "cells";
  auto add = [&](const Point& centre, int context) {
    const double x = std::round(centre.x()), y = std::round(centre.y()), z = std::round(centre.z());
    if (!(x >= 0 && y >= 0 && z >= 0 && x < side && y < side && z < side)) return;
    const GridPoint g{static_cast<int32_t>(x), static_cast<int32_t>(y), static_cast<int32_t>(z)};
    candidates.push_back({dtm::morton_encode(g, qbits), g, context});
  };
  if (kinds.find("cells") != std::string::npos)
    for (auto c = dt.finite_cells_begin(); c != dt.finite_cells_end(); ++c) {
      const Point centre = CGAL::circumcenter(c->vertex(0)->point(), c->vertex(1)->point(),
                                              c->vertex(2)->point(), c->vertex(3)->point());
      add(centre, context_of(c, centre));
    }
  if (kinds.find("faces") != std::string::npos)
    for (auto f = dt.finite_facets_begin(); f != dt.finite_facets_end(); ++f) {
      const auto c = f->first;
      const int i = f->second;
      add(CGAL::circumcenter(c->vertex((i + 1) & 3)->point(), c->vertex((i + 2) & 3)->point(),
                             c->vertex((i + 3) & 3)->point()),
          2 * kRatioBuckets + (dt.is_infinite(c) || dt.is_infinite(c->neighbor(i)) ? 1 : 0));
    }
  if (kinds.find("edges") != std::string::npos)
    for (auto e = dt.finite_edges_begin(); e != dt.finite_edges_end(); ++e) {
      const auto c = e->first;
      add(CGAL::midpoint(c->vertex(e->second)->point(), c->vertex(e->third)->point()), 2 * kRatioBuckets + 2);
    }
  std::sort(candidates.begin(), candidates.end(), [](const Candidate& a, const Candidate& b) {
    return a.code != b.code ? a.code < b.code : a.context < b.context;
  });
  candidates.erase(std::unique(candidates.begin(), candidates.end(),
                               [](const Candidate& a, const Candidate& b) { return a.code == b.code; }),
                   candidates.end());
  candidates.erase(std::remove_if(candidates.begin(), candidates.end(),
                                  [&](const Candidate& c) {
                                    return std::binary_search(known.begin(), known.end(), c.code);
                                  }),
                   candidates.end());
  out.candidates = candidates.size();
  // The new points by position, to find what lies beside a candidate.
  auto key = [](int64_t x, int64_t y, int64_t z) { return (x * 73856093) ^ (y * 19349663) ^ (z * 83492791); };
  std::unordered_multimap<int64_t, size_t> at;
  for (size_t i = 0; i < fresh.size(); ++i) at.emplace(key(fresh[i].x, fresh[i].y, fresh[i].z), i);
  std::vector<bool> taken(fresh.size(), false);
  std::vector<IdealBit> flag(2 * kRatioBuckets + 3);
  const int r = radius(), width = 2 * r + 1, positions = width * width * width;
  IdealSymbol offset(positions);
  std::vector<GridPoint> hits;
  for (const Candidate& c : candidates) {
    int found = -1, which = 0;
    for (int s = 0; s < positions && found < 0; ++s) {
      const int64_t x = int64_t{c.at.x} + s % width - r, y = int64_t{c.at.y} + (s / width) % width - r,
                    z = int64_t{c.at.z} + s / (width * width) - r;
      auto [b, e] = at.equal_range(key(x, y, z));
      for (auto it = b; it != e; ++it) {
        const GridPoint& p = fresh[it->second];
        if (!taken[it->second] && p.x == x && p.y == y && p.z == z) {
          found = static_cast<int>(it->second), which = s;
          break;
        }
      }
    }
    out.flags += flag[c.context].code(found >= 0);
    if (found < 0) continue;
    out.offsets += offset.code(which);
    taken[found] = true;
    hits.push_back(fresh[found]);
  }
  out.hits = hits.size();
  std::vector<GridPoint> rest;
  for (size_t i = 0; i < fresh.size(); ++i)
    if (!taken[i]) rest.push_back(fresh[i]);
  dtm::merge_known(known, hits, qbits);
  dtm::SetCoderModels models;
  models.enable_coordinate_reuse(qbits);
  out.rest = 8.0 * dtm::encode_point_set(known, rest, qbits, models).size();
  return out;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr, "usage: circumcentre_candidates STREAM.dtm ...\n");
    return 2;
  }
  std::printf(
      "| stream | level | new points | candidates | hits | shipped (bits) | flags | offsets | rest | "
      "candidate model | change |\n|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n");
  for (int a = 1; a < argc; ++a) {
    std::ifstream file(argv[a], std::ios::binary);
    const std::vector<uint8_t> bytes((std::istreambuf_iterator<char>(file)), {});
    dtm::ProgressiveDecoder decoder;
    if (!decoder.feed(bytes).ok() || !decoder.complete()) {
      std::fprintf(stderr, "circumcentre_candidates: %s: not a complete .dtm stream\n", argv[a]);
      return 1;
    }
    const int qbits = decoder.header().grid.qbits;
    double shipped = 0, model = 0;
    for (int l = static_cast<int>(decoder.levels().size()) - 2; l >= 0; --l) {
      const LayerResult r =
          measure(decoder.points(), decoder.level_vertices(l + 1), decoder.level_vertices(l), qbits);
      const double total = r.flags + r.offsets + r.rest;
      shipped += r.shipped, model += total;
      std::printf("| %s | %d | %zu | %zu | %zu | %.0f | %.0f | %.0f | %.0f | %.0f | %+.1f%% |\n", argv[a], l,
                  r.fresh, r.candidates, r.hits, r.shipped, r.flags, r.offsets, r.rest, total,
                  100 * (total / r.shipped - 1));
      std::fflush(stdout);
    }
    std::printf("| %s | all | | | | %.0f | | | | %.0f | %+.2f%% (%.2f bpv) |\n", argv[a], shipped, model,
                100 * (model / shipped - 1), (model - shipped) / decoder.level_vertices(0));
  }
  return 0;
}
