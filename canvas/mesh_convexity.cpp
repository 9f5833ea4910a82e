// is_convex (surface_mesh.h). A closed, connected surface without self-intersections bounds one
// solid, which is convex when every face's plane has all the surface's vertices on its inner
// side: each face then lies on the boundary of the vertices' hull. The surface is oriented outward
// by a flood fill over its edges, and every face is tested against all vertices at once (a tree
// of boxes). The test was local (each face against the star of each of its vertices: Tietze's
// theorem), but within a tolerance local convexity does not add up: a torus of 120k triangles
// bends less than a hundredth of a voxel at each edge and passed as convex.
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <cstdint>
#include <unordered_map>
#include <utility>
#include <vector>

#include <Eigen/Geometry>

#include "surface_mesh.h"

namespace rvor {
namespace {

using Triangle = std::array<int, 3>;

std::uint64_t edge_key(int a, int b) {
  const auto [lo, hi] = std::minmax(a, b);
  return (static_cast<std::uint64_t>(lo) << 32) | static_cast<std::uint32_t>(hi);
}

// The triangles along each edge; a closed surface has exactly two per edge.
std::unordered_map<std::uint64_t, std::vector<int>> edge_triangles(const SurfaceMesh& mesh) {
  std::unordered_map<std::uint64_t, std::vector<int>> edges;
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t)
    for (int e = 0; e < 3; ++e)
      edges[edge_key(mesh.triangles[t][e], mesh.triangles[t][(e + 1) % 3])].push_back(
          static_cast<int>(t));
  return edges;
}

bool runs_along(const Triangle& t, int a, int b) {
  for (int e = 0; e < 3; ++e)
    if (t[e] == a && t[(e + 1) % 3] == b) return true;
  return false;
}

// The triangles turned so that every edge runs both ways (a flood fill from triangle 0); empty
// when the surface has several components, an edge other than two triangles, or no orientation.
std::vector<Triangle> consistently_oriented(const SurfaceMesh& mesh) {
  const auto edges = edge_triangles(mesh);
  std::vector<Triangle> oriented = mesh.triangles;
  std::vector<bool> reached(oriented.size(), false);
  std::vector<int> stack{0};
  reached[0] = true;
  std::size_t reached_count = 1;
  while (!stack.empty()) {
    const int t = stack.back();
    stack.pop_back();
    for (int e = 0; e < 3; ++e) {
      const int a = oriented[t][e], b = oriented[t][(e + 1) % 3];
      const std::vector<int>& pair = edges.at(edge_key(a, b));
      if (pair.size() != 2) return {};
      const int u = pair[0] == t ? pair[1] : pair[0];
      if (!reached[u]) {
        if (runs_along(oriented[u], a, b)) std::swap(oriented[u][1], oriented[u][2]);
        reached[u] = true;
        ++reached_count;
        stack.push_back(u);
      } else if (runs_along(oriented[u], a, b)) {
        return {};  // not orientable
      }
    }
  }
  if (reached_count != oriented.size()) return {};
  return oriented;
}

// Six times the signed volume the triangles enclose (positive: normals point outward).
double signed_volume_6(const SurfaceMesh& mesh, const std::vector<Triangle>& triangles,
                       const Vec3& centre) {
  double volume = 0.0;
  for (const Triangle& t : triangles)
    volume += (mesh.vertices[t[0]] - centre)
                  .dot((mesh.vertices[t[1]] - centre).cross(mesh.vertices[t[2]] - centre));
  return volume;
}

// The unit outward normal of a triangle, or zero for a sliver whose plane its rounded corners do
// not define (its neighbours' planes are tested instead).
Vec3 face_normal(const SurfaceMesh& mesh, const Triangle& t) {
  const Vec3 u = mesh.vertices[t[1]] - mesh.vertices[t[0]];
  const Vec3 v = mesh.vertices[t[2]] - mesh.vertices[t[0]];
  const Vec3 cross = u.cross(v);
  const double longest = std::max({u.squaredNorm(), v.squaredNorm(), (v - u).squaredNorm()});
  return cross.norm() > 1e-10 * longest ? Vec3(cross.normalized()) : Vec3(Vec3::Zero());
}

// Points in a tree of boxes, to tell whether any lies above a plane without testing each where
// the boxes tell (every face against every vertex would be quadratic; a face of a convex surface
// opens the few boxes its plane cuts). A box is passed when the plane's
// function is at most the tolerance at its corners; that bound and a point's own value differ by
// rounding, far below the tolerance.
class PointTree {
 public:
  explicit PointTree(std::vector<Vec3> points) : points_(std::move(points)) {
    if (points_.empty()) return;
    nodes_.resize(1);
    build(0, 0, points_.size());
  }

  // Whether some point p has normal . (p - a) > tolerance.
  bool any_above(const Vec3& normal, const Vec3& a, double tolerance) const {
    if (nodes_.empty()) return false;
    const double offset = normal.dot(a);
    std::vector<std::size_t> stack{0};
    while (!stack.empty()) {
      const Node& node = nodes_[stack.back()];
      stack.pop_back();
      double bound = -offset;
      for (int axis = 0; axis < 3; ++axis)
        bound += std::max(normal[axis] * node.lo[axis], normal[axis] * node.hi[axis]);
      if (bound <= tolerance) continue;
      if (node.children == 0) {
        for (std::size_t p = node.begin; p < node.end; ++p)
          if (normal.dot(points_[p] - a) > tolerance) return true;
      } else {
        stack.push_back(node.children);
        stack.push_back(node.children + 1);
      }
    }
    return false;
  }

 private:
  static constexpr std::size_t kLeafSize = 8;
  struct Node {
    Vec3 lo, hi;
    std::size_t begin, end;
    std::size_t children = 0;  // the index of the first of two, 0 for a leaf
  };

  // Fills node `index` with points [begin, end), its two children next to each other.
  void build(std::size_t index, std::size_t begin, std::size_t end) {
    Vec3 lo = points_[begin], hi = points_[begin];
    for (std::size_t p = begin; p < end; ++p) {
      lo = lo.cwiseMin(points_[p]);
      hi = hi.cwiseMax(points_[p]);
    }
    nodes_[index] = {lo, hi, begin, end};
    if (end - begin <= kLeafSize) return;
    int axis = 0;
    (hi - lo).maxCoeff(&axis);
    const std::size_t middle = begin + (end - begin) / 2;
    std::nth_element(points_.begin() + static_cast<std::ptrdiff_t>(begin),
                     points_.begin() + static_cast<std::ptrdiff_t>(middle),
                     points_.begin() + static_cast<std::ptrdiff_t>(end),
                     [axis](const Vec3& p, const Vec3& q) { return p[axis] < q[axis]; });
    const std::size_t children = nodes_.size();
    nodes_.resize(children + 2);
    nodes_[index].children = children;
    build(children, begin, middle);
    build(children + 1, middle, end);
  }

  std::vector<Vec3> points_;
  std::vector<Node> nodes_;
};

}  // namespace

bool is_convex(const SurfaceMesh& mesh, double voxel_size) {
  if (mesh.triangles.empty()) return false;
  std::vector<Triangle> triangles = consistently_oriented(mesh);
  if (triangles.empty()) return false;
  const Box box = bounds_of(mesh);
  if (signed_volume_6(mesh, triangles, 0.5 * (box.lo + box.hi)) < 0)
    for (Triangle& t : triangles) std::swap(t[1], t[2]);
  // A dent of a hundredth of a voxel changes no voxel much; coordinates written with 6 digits (or
  // stored as floats, binary STL) put the corners of a flat face that far off its plane. That
  // allowance is held to a tenth of a voxel: unbounded, it grew with the distance from the origin
  // and passed a C-shaped prism 0.08 across at 1e5 (tolerance 0.1) as convex. A flat face rounded
  // further off is only called non-convex, which costs the exact start time, not correctness.
  const double largest_coordinate =
      std::max(box.lo.cwiseAbs().maxCoeff(), box.hi.cwiseAbs().maxCoeff());
  const double tolerance =
      std::max(0.01 * voxel_size, std::min(1e-6 * largest_coordinate, 0.1 * voxel_size));
  std::vector<bool> used(mesh.vertices.size(), false);
  for (const Triangle& t : triangles)
    for (const int v : t) used[v] = true;
  std::vector<Vec3> points;
  for (std::size_t v = 0; v < used.size(); ++v)
    if (used[v]) points.push_back(mesh.vertices[v]);
  const PointTree tree(std::move(points));
  // In parallel: a convex sphere of 327k triangles took 1.7 s on one core.
  std::atomic<bool> convex{true};
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, triangles.size()), [&](const auto& range) {
    for (std::size_t n = range.begin(); n != range.end() && convex.load(); ++n) {
      const Triangle& t = triangles[n];
      if (tree.any_above(face_normal(mesh, t), mesh.vertices[t[0]], tolerance)) convex = false;
    }
  });
  return convex;
}

}  // namespace rvor
