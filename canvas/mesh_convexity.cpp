// is_convex (surface_mesh.h). A closed, connected surface without self-intersections bounds one
// solid; where that solid is locally convex at every point it is convex (Tietze's theorem). Inside
// a face it always is; at an edge and at a vertex it is when every face around the vertex has the
// vertex's whole star on its inner side. So the surface is oriented outward by a flood fill over
// its edges, and every face around each vertex is tested against the vertices of that star.
#include <algorithm>
#include <array>
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

}  // namespace

bool is_convex(const SurfaceMesh& mesh, double voxel_size) {
  if (mesh.triangles.empty()) return false;
  std::vector<Triangle> triangles = consistently_oriented(mesh);
  if (triangles.empty()) return false;
  const Box box = bounds_of(mesh);
  if (signed_volume_6(mesh, triangles, 0.5 * (box.lo + box.hi)) < 0)
    for (Triangle& t : triangles) std::swap(t[1], t[2]);
  std::vector<std::vector<int>> around(mesh.vertices.size());  // the triangles at each vertex
  for (std::size_t t = 0; t < triangles.size(); ++t)
    for (const int v : triangles[t]) around[v].push_back(static_cast<int>(t));
  // A dent of a hundredth of a voxel changes no voxel much; coordinates written with 6 digits (or
  // stored as floats, binary STL) put the corners of a flat face that far off its plane.
  const double largest_coordinate =
      std::max(box.lo.cwiseAbs().maxCoeff(), box.hi.cwiseAbs().maxCoeff());
  const double tolerance = std::max(0.01 * voxel_size, 1e-6 * largest_coordinate);
  for (const std::vector<int>& star : around)
    for (const int face : star) {
      const Vec3& a = mesh.vertices[triangles[face][0]];
      const Vec3 normal = face_normal(mesh, triangles[face]);
      for (const int other : star)
        for (const int x : triangles[other])
          if (normal.dot(mesh.vertices[x] - a) > tolerance) return false;
    }
  return true;
}

}  // namespace rvor
