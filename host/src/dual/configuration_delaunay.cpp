// The Delaunay triangulation of a near-degenerate configuration (local_delaunay.cpp), with CGAL:
// its exact predicates and symbolic perturbation choose one triangulation of cospherical seeds,
// where an empty-sphere test in floating point kept every simplex of them (overlapping).
#include <CGAL/Delaunay_triangulation_2.h>
#include <CGAL/Delaunay_triangulation_3.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Triangulation_vertex_base_with_info_2.h>
#include <CGAL/Triangulation_vertex_base_with_info_3.h>
#include <algorithm>
#include <utility>

#include "dual/dual_internal.h"

namespace rvor::dual {

namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;

using Tds2 = CGAL::Triangulation_data_structure_2<
    CGAL::Triangulation_vertex_base_with_info_2<int32_t, Kernel>,
    CGAL::Triangulation_face_base_2<Kernel>>;
using Delaunay2 = CGAL::Delaunay_triangulation_2<Kernel, Tds2>;

using Tds3 = CGAL::Triangulation_data_structure_3<
    CGAL::Triangulation_vertex_base_with_info_3<int32_t, Kernel>,
    CGAL::Delaunay_triangulation_cell_base_3<Kernel>>;
using Delaunay3 = CGAL::Delaunay_triangulation_3<Kernel, Tds3>;

template <typename Triangulation, typename Point, typename Make>
Triangulation triangulate(const std::vector<Vec3>& points, Make make) {
  std::vector<std::pair<Point, int32_t>> indexed;
  for (std::size_t i = 0; i < points.size(); ++i)
    indexed.emplace_back(make(points[i]), static_cast<int32_t>(i));
  return Triangulation(indexed.begin(), indexed.end());
}

}  // namespace

std::vector<std::array<int32_t, 4>> delaunay_of(const std::vector<Vec3>& points, int dimension) {
  std::vector<std::array<int32_t, 4>> simplices;
  if (dimension == 2) {
    const Delaunay2 dt = triangulate<Delaunay2, Kernel::Point_2>(
        points, [](const Vec3& p) { return Kernel::Point_2(p.x(), p.y()); });
    if (dt.dimension() < 2) return simplices;
    for (auto face = dt.finite_faces_begin(); face != dt.finite_faces_end(); ++face) {
      std::array<int32_t, 4> s{face->vertex(0)->info(), face->vertex(1)->info(),
                               face->vertex(2)->info(), -1};
      std::sort(s.begin(), s.begin() + 3);
      simplices.push_back(s);
    }
    return simplices;
  }
  const Delaunay3 dt = triangulate<Delaunay3, Kernel::Point_3>(
      points, [](const Vec3& p) { return Kernel::Point_3(p.x(), p.y(), p.z()); });
  if (dt.dimension() < 3) return simplices;
  for (auto cell = dt.finite_cells_begin(); cell != dt.finite_cells_end(); ++cell) {
    std::array<int32_t, 4> s{cell->vertex(0)->info(), cell->vertex(1)->info(),
                             cell->vertex(2)->info(), cell->vertex(3)->info()};
    std::sort(s.begin(), s.end());
    simplices.push_back(s);
  }
  return simplices;
}

}  // namespace rvor::dual
