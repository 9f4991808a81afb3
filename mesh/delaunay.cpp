#include "mesh/delaunay.h"

#include <CGAL/Delaunay_triangulation_3.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Spatial_sort_traits_adapter_3.h>
#include <CGAL/Triangulation_cell_base_with_info_3.h>
#include <CGAL/Triangulation_vertex_base_with_info_3.h>
#include <CGAL/property_map.h>
#include <CGAL/spatial_sort.h>

#include <exception>
#include <string>
#include <utility>

namespace dtm {
namespace {

using K = CGAL::Exact_predicates_inexact_constructions_kernel;
using Vb = CGAL::Triangulation_vertex_base_with_info_3<uint32_t, K>;
using Cb = CGAL::Triangulation_cell_base_with_info_3<int32_t, K, CGAL::Delaunay_triangulation_cell_base_3<K>>;
using Tds = CGAL::Triangulation_data_structure_3<Vb, Cb>;
using DT = CGAL::Delaunay_triangulation_3<K, Tds>;
using Point = K::Point_3;

Point to_point(const GridPoint& p) { return Point(p.x, p.y, p.z); }

// CGAL reports failures (a violated precondition, no memory) by exceptions;
// this door turns them into a Status, so that nothing above it throws.
template <class F>
Status guarded(F&& f) {
  try {
    return f();
  } catch (const std::bad_alloc&) {
    return {StatusCode::kLimitExceeded, "out of memory building a Delaunay tetrahedralization"};
  } catch (const std::exception& e) {
    return {StatusCode::kInternal, std::string("CGAL: ") + e.what()};
  }
}

// kLimitExceeded once the triangulation holds more cells than
// kMaxCellsPerVertex per vertex: checked every few insertions, so the excess
// it can allocate is bounded.
Status check_cells(const DT& dt) {
  const size_t v = dt.number_of_vertices();
  if (dt.number_of_cells() <= kMaxCellsPerVertex * v + 4096) return Status::Ok();
  return {StatusCode::kLimitExceeded,
          "the Delaunay tetrahedralization of these points has over " + std::to_string(kMaxCellsPerVertex) +
              " cells per vertex (" + std::to_string(dt.number_of_cells()) + " cells for " +
              std::to_string(v) +
              " vertices): the points lie in a degenerate configuration such as two lines"};
}

// Inserts item_of(0), ..., item_of(n - 1) (point and id) in that order, each
// located from the previous one, with the cell check every 256 insertions.
template <class ItemOf>
Status insert_in_order(DT& dt, size_t n, ItemOf&& item_of) {
  DT::Cell_handle hint;
  for (size_t i = 0; i < n; ++i) {
    const auto [point, id] = item_of(i);
    auto v = dt.insert(point, hint);
    v->info() = id;
    hint = v->cell();
    if ((i & 255) == 255) DTM_RETURN_IF_ERROR(check_cells(dt));
  }
  return check_cells(dt);
}

// What CGAL's range insertion does (spatial sort, then insertion with the
// previous vertex as hint), plus the cell check.
Status insert_batch(DT& dt, std::span<const GridPoint> points, std::span<const uint32_t> ids) {
  DTM_CHECK(points.size() == ids.size());
  using Item = std::pair<Point, uint32_t>;
  std::vector<Item> batch;
  batch.reserve(points.size());
  for (size_t i = 0; i < points.size(); ++i) batch.emplace_back(to_point(points[i]), ids[i]);
  CGAL::spatial_sort(batch.begin(), batch.end(),
                     CGAL::Spatial_sort_traits_adapter_3<K, CGAL::First_of_pair_property_map<Item>>());
  return insert_in_order(dt, batch.size(), [&](size_t i) { return batch[i]; });
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

StatusOr<TetMesh> delaunay_tetrahedralize(std::span<const GridPoint> points) {
  std::vector<uint32_t> ids(points.size());
  for (size_t i = 0; i < ids.size(); ++i) ids[i] = static_cast<uint32_t>(i);
  DT dt;
  DTM_RETURN_IF_ERROR(guarded([&] { return insert_batch(dt, points, ids); }));
  if (dt.number_of_vertices() != points.size())
    return Status{StatusCode::kInvalidInput, "the points to tetrahedralize are not distinct"};
  if (dt.dimension() < 3)
    return Status{StatusCode::kInvalidInput,
                  "the " + std::to_string(points.size()) + " points span only " +
                      std::to_string(std::max(dt.dimension(), 0)) +
                      " dimension(s); a tetrahedral mesh needs 4 points not in one plane"};
  return export_mesh(dt);
}

struct IncrementalDelaunay::Impl {
  DT dt;
};

IncrementalDelaunay::IncrementalDelaunay() : impl_(std::make_unique<Impl>()) {}
IncrementalDelaunay::~IncrementalDelaunay() = default;

Status IncrementalDelaunay::insert(std::span<const GridPoint> points, std::span<const uint32_t> ids) {
  return guarded([&] { return insert_batch(impl_->dt, points, ids); });
}

Status IncrementalDelaunay::insert_one_by_one(std::span<const GridPoint> points,
                                              std::span<const uint32_t> ids) {
  DTM_CHECK(points.size() == ids.size());
  return guarded([&] {
    return insert_in_order(impl_->dt, points.size(),
                           [&](size_t i) { return std::make_pair(to_point(points[i]), ids[i]); });
  });
}

Status IncrementalDelaunay::remove(std::span<const GridPoint> points) {
  return guarded([&] {
    for (const GridPoint& p : points) {
      DT::Vertex_handle v;
      if (!impl_->dt.is_vertex(to_point(p), v))
        return Status{StatusCode::kInvalidInput, "remove: a point is not a vertex"};
      impl_->dt.remove(v);
    }
    return Status::Ok();
  });
}

int IncrementalDelaunay::dimension() const { return impl_->dt.dimension(); }
size_t IncrementalDelaunay::number_of_vertices() const { return impl_->dt.number_of_vertices(); }
TetMesh IncrementalDelaunay::mesh() const { return export_mesh(impl_->dt); }

CavityFill cavity_fill(std::span<const GridPoint> link, std::span<const uint32_t> link_ids,
                       const GridPoint& apex) {
  CavityFill out;
  DT dt;
  DT::Cell_handle hint;
  for (size_t i = 0; i < link.size(); ++i) {
    auto v = dt.insert(to_point(link[i]), hint);
    v->info() = link_ids[i];
    hint = v->cell();
  }
  if (dt.dimension() < 3) return out;
  const Point q = to_point(apex);
  DT::Locate_type lt;
  int li, lj;
  const DT::Cell_handle start = dt.locate(q, lt, li, lj, hint);
  DTM_CHECK(lt != DT::VERTEX);
  std::vector<DT::Cell_handle> conflicts;
  dt.find_conflicts(q, start, CGAL::Emptyset_iterator(), std::back_inserter(conflicts));
  for (auto c = dt.all_cells_begin(); c != dt.all_cells_end(); ++c) c->info() = -1;
  for (DT::Cell_handle c : conflicts)
    if (!dt.is_infinite(c)) {
      c->info() = static_cast<int32_t>(out.cells.size());
      out.cells.push_back(
          {c->vertex(0)->info(), c->vertex(1)->info(), c->vertex(2)->info(), c->vertex(3)->info()});
    }
  out.neighbors.resize(out.cells.size());
  for (DT::Cell_handle c : conflicts)
    if (c->info() >= 0)
      for (int i = 0; i < 4; ++i) out.neighbors[c->info()][i] = c->neighbor(i)->info();
  return out;
}

}  // namespace dtm
