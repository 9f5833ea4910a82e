// inside_runs (surface_mesh.h): the voxel centres inside a closed mesh, by the parity of the
// surface crossings along rays in +x. Exact orientation predicates (CGAL) with a symbolic
// perturbation of the rays decide every ray that passes through an edge or a vertex the same way
// from all the triangles there, so each ray crosses a closed surface an even number of times.
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Exact_rational.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <utility>
#include <vector>

#include "surface_mesh.h"

namespace rvor {

namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point2 = Kernel::Point_2;
constexpr int kSlab = 8;  // k layers per task: one OpenVDB leaf deep

// A projected vertex: (y, z) of its index coordinates.
struct Projected {
  Point2 yz;
  double x;
};

int sign_of(double value) {
  return (value > 0) - (value < 0);
}

// The side of the ray (q + (eps, eps^2) in y, z, eps -> 0) from the edge u -> v: +1 left, -1
// right, never 0. Swapping u and v flips it, so the two triangles of an edge agree.
int side(const Point2& u, const Point2& v, const Point2& q) {
  const CGAL::Orientation o = CGAL::orientation(u, v, q);
  if (o != CGAL::COLLINEAR) return o == CGAL::LEFT_TURN ? 1 : -1;
  // det(v - u, q + delta - u) = det(v - u, q - u) + (v_y - u_y) eps^2 - (v_z - u_z) eps.
  if (v.y() != u.y()) return -sign_of(v.y() - u.y());
  return sign_of(v.x() - u.x());
}

// Twice the signed area of the (y, z) triangle u v w, in doubles (for interpolation only).
double area2(const Point2& u, const Point2& v, const Point2& w) {
  return (v.x() - u.x()) * (w.y() - u.y()) - (v.y() - u.y()) * (w.x() - u.x());
}

class SlabCrossings {
 public:
  SlabCrossings(int k0, int k1, int rows_j) : k0_(k0), k1_(k1), rows_j_(rows_j) {
    crossings_.resize(static_cast<std::size_t>(rows_j) * static_cast<std::size_t>(k1 - k0));
  }

  // The x of the triangle's crossings with the slab's rays through voxel centres (j, k).
  void add(const Projected& a, const Projected& b, const Projected& c) {
    const CGAL::Orientation turn = CGAL::orientation(a.yz, b.yz, c.yz);
    if (turn == CGAL::COLLINEAR) return;  // edge-on: a perturbed ray never lies inside it
    const int expected = turn == CGAL::LEFT_TURN ? 1 : -1;
    const double area = area2(a.yz, b.yz, c.yz);
    const int j0 =
        std::max(0, static_cast<int>(std::ceil(std::min({a.yz.x(), b.yz.x(), c.yz.x()}))));
    const int j1 = std::min(rows_j_ - 1,
                            static_cast<int>(std::floor(std::max({a.yz.x(), b.yz.x(), c.yz.x()}))));
    const int k0 =
        std::max(k0_, static_cast<int>(std::ceil(std::min({a.yz.y(), b.yz.y(), c.yz.y()}))));
    const int k1 =
        std::min(k1_ - 1, static_cast<int>(std::floor(std::max({a.yz.y(), b.yz.y(), c.yz.y()}))));
    for (int k = k0; k <= k1; ++k) {
      const auto [row_j0, row_j1] = row_span(a.yz, b.yz, c.yz, k);
      for (int j = std::max(j0, row_j0); j <= std::min(j1, row_j1); ++j) {
        const Point2 q(j, k);
        if (side(a.yz, b.yz, q) != expected || side(b.yz, c.yz, q) != expected ||
            side(c.yz, a.yz, q) != expected)
          continue;
        row(j, k).push_back(crossing_x(a, b, c, q, area));
      }
    }
  }

  // The j's of row k that may lie in the (y, z) triangle u v w: between its edges' crossings
  // with z = k, widened by a voxel against their rounding (the exact side tests decide). The whole
  // bounding box was tested before: a fan of 200k slivers across a cylinder's end took 12 s at
  // 512^3 for an area of a few thousand rows.
  static std::pair<int, int> row_span(const Point2& u, const Point2& v, const Point2& w, int k) {
    double lo = HUGE_VAL, hi = -HUGE_VAL;
    for (const auto& [p, q] : {std::pair{u, v}, std::pair{v, w}, std::pair{w, u}}) {
      if (std::min(p.y(), q.y()) > k || std::max(p.y(), q.y()) < k) continue;
      if (p.y() == q.y()) {  // along the row
        lo = std::min({lo, p.x(), q.x()});
        hi = std::max({hi, p.x(), q.x()});
        continue;
      }
      const double y = p.x() + (k - p.y()) / (q.y() - p.y()) * (q.x() - p.x());
      lo = std::min(lo, y);
      hi = std::max(hi, y);
    }
    if (!(lo <= hi)) return {0, -1};
    return {static_cast<int>(std::max(-1e9, std::floor(lo) - 1)),
            static_cast<int>(std::min(1e9, std::ceil(hi) + 1))};
  }

  // Where the ray through q meets the triangle, which holds it: barycentric interpolation of the
  // x's, in doubles unless the (y, z) area is small against its rounding (a triangle nearly
  // edge-on to x, whose double area can be 0 or of the wrong sign: then exactly). Kept within the
  // triangle's x range either way.
  static double crossing_x(const Projected& a, const Projected& b, const Projected& c,
                           const Point2& q, double area) {
    const double magnitude = std::abs((b.yz.x() - a.yz.x()) * (c.yz.y() - a.yz.y())) +
                             std::abs((b.yz.y() - a.yz.y()) * (c.yz.x() - a.yz.x()));
    double x = 0;
    if (std::abs(area) > 1e-10 * magnitude) {
      const double la = area2(b.yz, c.yz, q) / area, lb = area2(c.yz, a.yz, q) / area;
      x = la * a.x + lb * b.x + (1.0 - la - lb) * c.x;
    } else {
      using Q = CGAL::Exact_rational;
      // The return type spelled out: GMP's expression templates would refer to dead temporaries.
      const auto exact_area2 = [](const Point2& u, const Point2& v, const Point2& w) -> Q {
        return (Q(v.x()) - Q(u.x())) * (Q(w.y()) - Q(u.y())) -
               (Q(v.y()) - Q(u.y())) * (Q(w.x()) - Q(u.x()));
      };
      const Q whole = exact_area2(a.yz, b.yz, c.yz);
      x = CGAL::to_double(
          Q((exact_area2(b.yz, c.yz, q) * Q(a.x) + exact_area2(c.yz, a.yz, q) * Q(b.x) +
             exact_area2(a.yz, b.yz, q) * Q(c.x)) /
            whole));
    }
    return std::clamp(x, std::min({a.x, b.x, c.x}), std::max({a.x, b.x, c.x}));
  }

  // Pairs each row's sorted crossings: voxels between the first and the second are inside, and
  // so on (a ray that met an odd number, which a closed surface does not give, drops its last).
  void runs(int dims_x, std::vector<VoxelRun>& out) {
    for (int k = k0_; k < k1_; ++k)
      for (int j = 0; j < rows_j_; ++j) {
        std::vector<double>& xs = row(j, k);
        std::sort(xs.begin(), xs.end());
        for (std::size_t n = 0; n + 1 < xs.size(); n += 2) {
          const int begin = std::max(0, static_cast<int>(std::floor(xs[n])) + 1);
          const int end = std::min(dims_x, static_cast<int>(std::ceil(xs[n + 1])));
          if (begin < end) out.push_back({j, k, begin, end});
        }
      }
  }

 private:
  std::vector<double>& row(int j, int k) {
    return crossings_[static_cast<std::size_t>(k - k0_) * rows_j_ + j];
  }

  int k0_, k1_, rows_j_;
  std::vector<std::vector<double>> crossings_;
};

}  // namespace

std::vector<VoxelRun> inside_runs(const SurfaceMesh& mesh, const Vec3& origin, double h,
                                  const std::array<int, 3>& dims) {
  std::vector<Projected> vertices;
  vertices.reserve(mesh.vertices.size());
  for (const Vec3& v : mesh.vertices) {
    const Vec3 index = (v - origin) / h;  // in double: world coordinates far from 0 keep their bits
    vertices.push_back({Point2(index.y(), index.z()), index.x()});
  }
  const int slabs = (dims[2] + kSlab - 1) / kSlab;
  std::vector<std::vector<int>> slab_triangles(static_cast<std::size_t>(slabs));
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    double lo = HUGE_VAL, hi = -HUGE_VAL;
    for (int c = 0; c < 3; ++c) {
      lo = std::min(lo, vertices[mesh.triangles[t][c]].yz.y());
      hi = std::max(hi, vertices[mesh.triangles[t][c]].yz.y());
    }
    const int k0 = std::max(0, static_cast<int>(std::ceil(lo)));
    const int k1 = std::min(dims[2] - 1, static_cast<int>(std::floor(hi)));
    for (int s = k0 / kSlab; k0 <= k1 && s <= k1 / kSlab; ++s)
      slab_triangles[s].push_back(static_cast<int>(t));
  }
  std::vector<std::vector<VoxelRun>> slab_runs(static_cast<std::size_t>(slabs));
  tbb::parallel_for(tbb::blocked_range<int>(0, slabs), [&](const tbb::blocked_range<int>& range) {
    for (int s = range.begin(); s != range.end(); ++s) {
      SlabCrossings crossings(s * kSlab, std::min(dims[2], (s + 1) * kSlab), dims[1]);
      for (const int t : slab_triangles[s]) {
        const auto& triangle = mesh.triangles[static_cast<std::size_t>(t)];
        crossings.add(vertices[triangle[0]], vertices[triangle[1]], vertices[triangle[2]]);
      }
      crossings.runs(dims[0], slab_runs[s]);
    }
  });
  std::vector<VoxelRun> runs;
  for (const std::vector<VoxelRun>& part : slab_runs)
    runs.insert(runs.end(), part.begin(), part.end());
  return runs;
}

}  // namespace rvor
