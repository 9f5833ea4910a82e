// add_polygon (surface_mesh.h): ear clipping in the polygon's plane.
#include <algorithm>
#include <cmath>
#include <vector>

#include <Eigen/Geometry>

#include "surface_mesh.h"

namespace rvor {

namespace {

using Point2 = Eigen::Vector2d;

double cross(const Point2& a, const Point2& b, const Point2& c) {
  return (b - a).x() * (c - a).y() - (b - a).y() * (c - a).x();
}

// The side of c from the line a -> b: +1 left, -1 right, 0 on it to within rounding (a corner on
// a side must count as on it, or an ear would leave it as a T-junction).
int side(const Point2& a, const Point2& b, const Point2& c) {
  const double value = cross(a, b, c);
  const double rounding = 1e-12 * (b - a).norm() * (c - a).norm();
  return value > rounding ? 1 : value < -rounding ? -1 : 0;
}

// The polygon in its plane: the axis of largest normal component dropped, the other two ordered
// so that the polygon turns counterclockwise (Newell's normal: any planar polygon, convex or not).
std::vector<Point2> planar(const SurfaceMesh& mesh, const std::vector<int>& polygon) {
  // Relative to the first corner: far from the origin, the products of absolute coordinates
  // would drown a small polygon's normal in rounding.
  const Vec3& origin = mesh.vertices[polygon[0]];
  Vec3 normal = Vec3::Zero();
  for (std::size_t n = 0; n < polygon.size(); ++n)
    normal += (mesh.vertices[polygon[n]] - origin)
                  .cross(mesh.vertices[polygon[(n + 1) % polygon.size()]] - origin);
  int drop = 0;
  normal.cwiseAbs().maxCoeff(&drop);
  const int u = (drop + 1) % 3, v = (drop + 2) % 3;
  const bool flip = normal[drop] < 0;
  std::vector<Point2> points;
  for (const int index : polygon) {
    const Vec3 p = mesh.vertices[index] - origin;  // small numbers for the side tests
    points.emplace_back(flip ? p[v] : p[u], flip ? p[u] : p[v]);
  }
  return points;
}

// Whether corner n of the remaining polygon is an ear: convex with a non-zero area, and no other
// remaining vertex inside it or on its sides.
bool is_ear(const std::vector<Point2>& p, const std::vector<std::size_t>& left, std::size_t n) {
  const std::size_t count = left.size();
  const Point2 &a = p[left[(n + count - 1) % count]], &b = p[left[n]],
               &c = p[left[(n + 1) % count]];
  if (side(a, b, c) <= 0) return false;
  for (std::size_t m = 0; m < count; ++m) {
    const Point2& q = p[left[m]];
    if (q == a || q == b || q == c) continue;
    if (side(a, b, q) >= 0 && side(b, c, q) >= 0 && side(c, a, q) >= 0) return false;
  }
  return true;
}

void push_triangle(SurfaceMesh& mesh, int a, int b, int c) {
  if (a != b && b != c && a != c) mesh.triangles.push_back({a, b, c});
}

// The triangles that the ear clipping below cuts a convex polygon into, without its search for
// ears, which tests every corner left against each ear: 9 s for a face of 40k corners. In a
// convex polygon every corner is an ear, so the clipping takes the first candidate each time: it
// removes every other corner, round and round. False, adding nothing, unless every corner turns
// left and the outline turns once around.
bool clip_convex(SurfaceMesh& mesh, const std::vector<int>& polygon,
                 const std::vector<Point2>& points) {
  const std::size_t count = points.size();
  double turned = 0;
  for (std::size_t n = 0; n < count; ++n) {
    const Point2 &a = points[(n + count - 1) % count], &b = points[n], &c = points[(n + 1) % count];
    if (side(a, b, c) <= 0) return false;
    turned += std::atan2(cross(a, b, c), (b - a).dot(c - b));
  }
  constexpr double kTwoPi = 6.283185307179586;
  if (std::abs(turned - kTwoPi) > 1.0) return false;  // a star polygon turns 4 pi or more
  std::vector<std::size_t> next(count);
  for (std::size_t n = 0; n < count; ++n) next[n] = (n + 1) % count;
  std::vector<std::size_t> previous(count);
  for (std::size_t n = 0; n < count; ++n) previous[n] = (n + count - 1) % count;
  std::size_t ear = 0;
  for (std::size_t left = count; left > 3; --left) {
    push_triangle(mesh, polygon[previous[ear]], polygon[ear], polygon[next[ear]]);
    next[previous[ear]] = next[ear];
    previous[next[ear]] = previous[ear];
    ear = next[next[ear]];  // the search starts one past the corner after the ear
  }
  // The last three in the order they had in the polygon, as the clipping leaves them.
  std::size_t first = ear;
  if (previous[ear] < first) first = previous[ear];
  if (next[ear] < first) first = next[ear];
  push_triangle(mesh, polygon[first], polygon[next[first]], polygon[next[next[first]]]);
  return true;
}

}  // namespace

void add_polygon(SurfaceMesh& mesh, const std::vector<int>& corners) {
  std::vector<int> polygon;  // without repeated consecutive corners
  for (const int v : corners)
    if (polygon.empty() || polygon.back() != v) polygon.push_back(v);
  while (polygon.size() > 1 && polygon.front() == polygon.back()) polygon.pop_back();
  if (polygon.size() == 3) return push_triangle(mesh, polygon[0], polygon[1], polygon[2]);
  if (polygon.size() < 3) return;
  const std::vector<Point2> points = planar(mesh, polygon);
  if (clip_convex(mesh, polygon, points)) return;
  std::vector<std::size_t> left(polygon.size());
  for (std::size_t n = 0; n < left.size(); ++n) left[n] = n;
  // The search for the next ear starts past the last one, so that a convex polygon is cut into
  // a strip rather than a fan: a fan's centre would be shared by every triangle, which CGAL's
  // self-intersection test paid for quadratically (and a fan's triangles are long and thin).
  std::size_t start = 0;
  while (left.size() > 3) {
    const std::size_t count = left.size();
    std::size_t tried = 0, ear = start % count;
    for (; tried < count && !is_ear(points, left, ear); ++tried) ear = (ear + 1) % count;
    if (tried == count) break;  // not a simple planar polygon: the fan below, as before
    push_triangle(mesh, polygon[left[(ear + count - 1) % count]], polygon[left[ear]],
                  polygon[left[(ear + 1) % count]]);
    left.erase(left.begin() + static_cast<std::ptrdiff_t>(ear));
    start = ear + 1;
  }
  // The last three corners (or a fan of what is left when no ear was found). A last triangle of
  // zero area (collinear corners) is dropped: it bounds nothing.
  if (left.size() == 3 && side(points[left[0]], points[left[1]], points[left[2]]) == 0) return;
  for (std::size_t n = 1; n + 1 < left.size(); ++n)
    push_triangle(mesh, polygon[left[0]], polygon[left[n]], polygon[left[n + 1]]);
}

}  // namespace rvor
