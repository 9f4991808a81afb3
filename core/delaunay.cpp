#include "delaunay.h"

#include <CGAL/Delaunay_triangulation_3.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Triangulation_cell_base_with_info_3.h>
#include <CGAL/Triangulation_vertex_base_with_info_3.h>

#include <limits>
#include <stdexcept>
#include <string>
#include <utility>

#include "geometry.h"

namespace dtm {
namespace {

using K = CGAL::Exact_predicates_inexact_constructions_kernel;
using Vb = CGAL::Triangulation_vertex_base_with_info_3<uint32_t, K>;
using Cb = CGAL::Triangulation_cell_base_with_info_3<int32_t, K,
                                                     CGAL::Delaunay_triangulation_cell_base_3<K>>;
using Tds = CGAL::Triangulation_data_structure_3<Vb, Cb>;
using DT = CGAL::Delaunay_triangulation_3<K, Tds>;
using Point = K::Point_3;

Point to_point(const GridPoint& p) { return Point(p.x, p.y, p.z); }

void insert_batch(DT& dt, std::span<const GridPoint> points, std::span<const uint32_t> ids) {
  if (points.size() != ids.size()) throw std::invalid_argument("points and ids differ in size");
  std::vector<std::pair<Point, uint32_t>> batch;
  batch.reserve(points.size());
  for (size_t i = 0; i < points.size(); ++i) batch.emplace_back(to_point(points[i]), ids[i]);
  dt.insert(batch.begin(), batch.end());  // spatially sorted by CGAL
}

TetMesh export_mesh(DT& dt) {
  TetMesh out;
  if (dt.dimension() < 3) return out;
  out.cells.reserve(dt.number_of_finite_cells());
  int32_t next = 0;
  for (auto c = dt.all_cells_begin(); c != dt.all_cells_end(); ++c)
    c->info() = dt.is_infinite(c) ? -1 : next++;
  out.neighbors.reserve(next);
  for (auto c : dt.finite_cell_handles()) {
    std::array<uint32_t, 4> v;
    std::array<int32_t, 4> n;
    for (int i = 0; i < 4; ++i) {
      v[i] = c->vertex(i)->info();
      n[i] = c->neighbor(i)->info();
    }
    out.cells.push_back(v);
    out.neighbors.push_back(n);
  }
  return out;
}

}  // namespace

TetMesh delaunay_tetrahedralize(std::span<const GridPoint> points) {
  std::vector<uint32_t> ids(points.size());
  for (size_t i = 0; i < ids.size(); ++i) ids[i] = static_cast<uint32_t>(i);
  DT dt;
  insert_batch(dt, points, ids);
  if (dt.number_of_vertices() != points.size())
    throw std::invalid_argument("delaunay_tetrahedralize: points are not distinct");
  if (dt.dimension() < 3)
    throw DegenerateInput("the " + std::to_string(points.size()) +
                          " points span only " + std::to_string(std::max(dt.dimension(), 0)) +
                          " dimension(s); a tetrahedral mesh needs 4 points not in one plane");
  return export_mesh(dt);
}

struct IncrementalDelaunay::Impl {
  DT dt;
};

IncrementalDelaunay::IncrementalDelaunay() : impl_(std::make_unique<Impl>()) {}
IncrementalDelaunay::~IncrementalDelaunay() = default;

void IncrementalDelaunay::insert(std::span<const GridPoint> points, std::span<const uint32_t> ids) {
  insert_batch(impl_->dt, points, ids);
}

void IncrementalDelaunay::insert_one_by_one(std::span<const GridPoint> points,
                                            std::span<const uint32_t> ids) {
  if (points.size() != ids.size()) throw std::invalid_argument("points and ids differ in size");
  DT::Cell_handle hint;
  for (size_t i = 0; i < points.size(); ++i) {
    auto v = impl_->dt.insert(to_point(points[i]), hint);
    v->info() = ids[i];
    hint = v->cell();
  }
}

void IncrementalDelaunay::remove(std::span<const GridPoint> points) {
  for (const GridPoint& p : points) {
    DT::Vertex_handle v;
    if (!impl_->dt.is_vertex(to_point(p), v))
      throw std::invalid_argument("remove: point is not a vertex");
    impl_->dt.remove(v);
  }
}

int IncrementalDelaunay::dimension() const { return impl_->dt.dimension(); }
size_t IncrementalDelaunay::number_of_vertices() const { return impl_->dt.number_of_vertices(); }
TetMesh IncrementalDelaunay::mesh() const { return export_mesh(impl_->dt); }

double cavity_min_solid_angle(std::span<const GridPoint> link, const GridPoint& apex,
                              double max_radius) {
  DT dt;
  for (const GridPoint& p : link) dt.insert(to_point(p));
  if (dt.dimension() < 3) return 0.0;
  const Point q = to_point(apex);
  std::vector<DT::Cell_handle> conflicts;
  DT::Locate_type lt;
  int li, lj;
  DT::Cell_handle start = dt.locate(q, lt, li, lj);
  if (lt == DT::VERTEX) return 0.0;
  dt.find_conflicts(q, start, CGAL::Emptyset_iterator(), std::back_inserter(conflicts));
  double best = std::numeric_limits<double>::infinity();
  for (DT::Cell_handle c : conflicts) {
    if (dt.is_infinite(c)) continue;
    std::array<Vec3, 4> t;
    for (int i = 0; i < 4; ++i) {
      const Point& p = c->vertex(i)->point();
      t[i] = {p.x(), p.y(), p.z()};
    }
    if (circumradius(t[0], t[1], t[2], t[3]) > max_radius) continue;
    for (double a : solid_angles(t)) best = std::min(best, a);
  }
  return best;
}

}  // namespace dtm
