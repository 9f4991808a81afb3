// layer_structure STREAM.dtm [LEVEL ...] -- how much structure a layer's new
// points have beyond what the coder uses: the measurements behind
// docs/STREAM_SIZE.md. For each layer (new points of level l given level l+1):
//
// - spacing bound: the gain, in bits per new point, of the best coder whose
//   density depends only on u = d(x) / s(v), where v is the coarse vertex
//   nearest to x, d(x) its distance and s(v) the distance from v to its
//   nearest coarse neighbour. It is KL(new points' u || the volume's u), both
//   histogrammed in steps of 1/32; the volume's is sampled uniformly in the
//   coarse level's convex hull. An upper bound for a model of the spacing
//   alone, against a uniform density in the hull. A histogram of few points
//   overstates it: the Miller-Madow term (occupied bins - 1) / (2 n ln 2) is
//   taken off.
// - at a circumcentre: the share of new points within one grid step of the
//   circumcentre of a cell of the coarse Delaunay tetrahedralization (TetGen
//   inserts its Steiner points at circumcentres).
//
// No level given: every layer but the base.
#include <CGAL/Delaunay_triangulation_3.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Triangulation_vertex_base_with_info_3.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <iterator>
#include <random>
#include <vector>

#include "codec/decode.h"

namespace {

using K = CGAL::Exact_predicates_inexact_constructions_kernel;
using Vb = CGAL::Triangulation_vertex_base_with_info_3<double, K>;  // info: nearest-neighbour distance
using Tds = CGAL::Triangulation_data_structure_3<Vb>;
using DT = CGAL::Delaunay_triangulation_3<K, Tds>;
using Point = K::Point_3;

constexpr int kBins = 64;  // u in [0, 2), steps of 1/32
constexpr int kSamplesPerPoint = 40;

int bin_of(double u) { return std::min(kBins - 1, static_cast<int>(u * 32)); }

double u_of(const DT& dt, const Point& x, DT::Cell_handle hint) {
  const auto v = dt.nearest_vertex(x, hint);
  return std::sqrt(CGAL::squared_distance(x, v->point())) / v->info();
}

// A uniform point of tetrahedron c (Rocchini and Cignoni's folding).
Point uniform_in(DT::Cell_handle c, std::mt19937_64& rng) {
  std::uniform_real_distribution<double> U(0, 1);
  double s = U(rng), t = U(rng), u = U(rng);
  if (s + t > 1) s = 1 - s, t = 1 - t;
  if (t + u > 1) {
    const double tmp = u;
    u = 1 - s - t;
    t = 1 - tmp;
  } else if (s + t + u > 1) {
    const double tmp = u;
    u = s + t + u - 1;
    s = 1 - t - tmp;
  }
  const double a = 1 - s - t - u;
  const Point p[4] = {c->vertex(0)->point(), c->vertex(1)->point(), c->vertex(2)->point(),
                      c->vertex(3)->point()};
  return {a * p[0].x() + s * p[1].x() + t * p[2].x() + u * p[3].x(),
          a * p[0].y() + s * p[1].y() + t * p[2].y() + u * p[3].y(),
          a * p[0].z() + s * p[1].z() + t * p[2].z() + u * p[3].z()};
}

struct LayerFigures {
  size_t coarse = 0, fresh = 0;
  double spacing_bound = 0;    // bits per new point
  double at_circumcentre = 0;  // share of new points
};

LayerFigures measure(const std::vector<dtm::GridPoint>& points, size_t coarse, size_t fine) {
  LayerFigures out;
  out.coarse = coarse;
  out.fresh = fine - coarse;
  std::vector<Point> pts;
  for (size_t i = 0; i < coarse; ++i) pts.emplace_back(points[i].x, points[i].y, points[i].z);
  DT dt(pts.begin(), pts.end());
  for (auto v = dt.finite_vertices_begin(); v != dt.finite_vertices_end(); ++v) {
    std::vector<DT::Vertex_handle> adjacent;
    dt.finite_adjacent_vertices(v, std::back_inserter(adjacent));
    double nearest = std::numeric_limits<double>::infinity();
    for (auto w : adjacent)
      nearest = std::min(nearest, std::sqrt(CGAL::squared_distance(v->point(), w->point())));
    v->info() = nearest;
  }
  // The volume's histogram of u.
  std::vector<DT::Cell_handle> cells;
  std::vector<double> cumulative;
  double volume = 0;
  for (auto c = dt.finite_cells_begin(); c != dt.finite_cells_end(); ++c) {
    volume += std::abs(CGAL::volume(c->vertex(0)->point(), c->vertex(1)->point(), c->vertex(2)->point(),
                                    c->vertex(3)->point()));
    cells.push_back(c);
    cumulative.push_back(volume);
  }
  std::vector<double> in_volume(kBins, 0), at_new(kBins, 0);
  std::mt19937_64 rng(1);
  std::uniform_real_distribution<double> U(0, volume);
  const size_t samples = std::max<size_t>(100000, kSamplesPerPoint * out.fresh);
  for (size_t s = 0; s < samples; ++s) {
    const size_t k = std::lower_bound(cumulative.begin(), cumulative.end(), U(rng)) - cumulative.begin();
    const auto c = cells[std::min(k, cells.size() - 1)];
    in_volume[bin_of(u_of(dt, uniform_in(c, rng), c))] += 1;
  }
  size_t inside = 0, near_centre = 0;
  for (size_t i = coarse; i < fine; ++i) {
    const Point x(points[i].x, points[i].y, points[i].z);
    const auto c = dt.locate(x);
    if (dt.is_infinite(c)) continue;  // outside the coarse hull: not in either histogram
    ++inside;
    at_new[bin_of(u_of(dt, x, c))] += 1;
    const auto v = dt.nearest_vertex(x, c);
    std::vector<DT::Cell_handle> around;
    dt.finite_incident_cells(v, std::back_inserter(around));
    double best = std::numeric_limits<double>::infinity();
    for (auto a : around)
      best = std::min(
          best, CGAL::squared_distance(x, CGAL::circumcenter(a->vertex(0)->point(), a->vertex(1)->point(),
                                                             a->vertex(2)->point(), a->vertex(3)->point())));
    if (best <= 1.0) ++near_centre;
  }
  if (inside == 0) return out;
  double kl = 0;
  int occupied = 0;
  for (int b = 0; b < kBins; ++b)
    if (at_new[b] > 0) {
      const double p = at_new[b] / inside, q = std::max(in_volume[b], 0.5) / samples;
      kl += p * std::log2(p / q);
      ++occupied;
    }
  out.spacing_bound = std::max(0.0, kl - (occupied - 1) / (2.0 * inside * std::log(2.0)));
  out.at_circumcentre = static_cast<double>(near_centre) / inside;
  return out;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr, "usage: layer_structure STREAM.dtm [LEVEL ...]\n");
    return 2;
  }
  std::ifstream file(argv[1], std::ios::binary);
  const std::vector<uint8_t> bytes((std::istreambuf_iterator<char>(file)), {});
  dtm::ProgressiveDecoder decoder;
  const dtm::Status status = decoder.feed(bytes);
  if (!status.ok() || !decoder.complete()) {
    std::fprintf(stderr, "layer_structure: %s: not a complete .dtm stream\n", argv[1]);
    return 1;
  }
  const int finest = decoder.finest_level();
  std::vector<int> levels;
  for (int i = 2; i < argc; ++i) levels.push_back(std::atoi(argv[i]));
  if (levels.empty())
    for (int l = 0; l + 1 < static_cast<int>(decoder.levels().size()); ++l) levels.push_back(l);
  std::printf(
      "| level | coarse vertices | new vertices | spacing bound (bits per new vertex) | "
      "new vertices at a coarse circumcentre |\n|---:|---:|---:|---:|---:|\n");
  double weighted = 0;
  for (int l : levels) {
    if (l < finest || l + 1 >= static_cast<int>(decoder.levels().size())) continue;
    const LayerFigures f =
        measure(decoder.points(), decoder.level_vertices(l + 1), decoder.level_vertices(l));
    weighted += f.spacing_bound * f.fresh;
    std::printf("| %d | %zu | %zu | %.2f | %.1f%% |\n", l, f.coarse, f.fresh, f.spacing_bound,
                100 * f.at_circumcentre);
    std::fflush(stdout);
  }
  std::printf("\nspacing bound over these layers: %.2f bits per vertex of level 0 (%u vertices)\n",
              weighted / decoder.level_vertices(0), decoder.level_vertices(0));
  return 0;
}
