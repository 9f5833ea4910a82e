// require_no_self_intersection (surface_mesh.h): the one translation unit of the canvas libraries
// with CGAL's polygon mesh processing, which takes long to compile.
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_mesh_processing/orient_polygon_soup.h>
#include <CGAL/Polygon_mesh_processing/polygon_soup_to_polygon_mesh.h>
#include <CGAL/Polygon_mesh_processing/self_intersections.h>
#include <CGAL/Surface_mesh.h>

#include <algorithm>
#include <array>
#include <iterator>
#include <utility>
#include <vector>

#include "rvor/error.h"
#include "surface_mesh.h"

namespace rvor {

namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point = Kernel::Point_3;
using CgalMesh = CGAL::Surface_mesh<Point>;
using Face = CgalMesh::Face_index;
namespace pmp = CGAL::Polygon_mesh_processing;

// The mesh as CGAL's halfedge structure, face i being triangle i. Orienting the soup first makes
// any closed mesh acceptable whatever the orientation of its triangles (the canvas does not need
// one), and splits a vertex where separate sheets meet, so that they show up as touching below.
CgalMesh cgal_mesh(const SurfaceMesh& mesh, const std::string& path) {
  std::vector<Point> points;
  points.reserve(mesh.vertices.size());
  for (const Vec3& v : mesh.vertices) points.emplace_back(v.x(), v.y(), v.z());
  std::vector<std::array<std::size_t, 3>> triangles;
  triangles.reserve(mesh.triangles.size());
  for (const auto& t : mesh.triangles)
    triangles.push_back({static_cast<std::size_t>(t[0]), static_cast<std::size_t>(t[1]),
                         static_cast<std::size_t>(t[2])});
  // What orienting cannot mend (a triangle that repeats a vertex, a one-sided surface) is no
  // boundary of a volume either; polygon_soup_to_polygon_mesh requires it mended.
  if (!pmp::is_polygon_soup_a_polygon_mesh(triangles) &&
      (pmp::orient_polygon_soup(points, triangles),  // keeps the triangles in order
       !pmp::is_polygon_soup_a_polygon_mesh(triangles)))
    throw Error("mesh " + path +
                " is not the boundary of a volume: its triangles cannot be oriented consistently "
                "(a one-sided surface, or a triangle that repeats a vertex)");
  CgalMesh out;
  pmp::polygon_soup_to_polygon_mesh(points, triangles, out);
  return out;
}

std::string triangle_text(const SurfaceMesh& mesh, std::size_t t) {
  const auto& v = mesh.triangles[t];
  return "triangle " + std::to_string(t) +
         " (0-based, polygons counted as the triangles they are cut into; " + "centred at " +
         point_text((mesh.vertices[v[0]] + mesh.vertices[v[1]] + mesh.vertices[v[2]]) / 3.0) + ")";
}

}  // namespace

void require_no_self_intersection(const SurfaceMesh& mesh, const std::string& path) {
  const CgalMesh cgal = cgal_mesh(mesh, path);
  // The first pair only: a flat mesh folded onto itself has a number of crossing pairs quadratic
  // in its size.
  std::vector<std::pair<Face, Face>> found;
  pmp::self_intersections(cgal, std::back_inserter(found), CGAL::parameters::maximum_number(1));
  if (found.empty()) return;
  const std::size_t a = std::min<std::size_t>(found.front().first, found.front().second);
  const std::size_t b = std::max<std::size_t>(found.front().first, found.front().second);
  if (a == b)  // CGAL reports a degenerate triangle as crossing itself
    throw Error("mesh " + path + " has a degenerate " + triangle_text(mesh, a) +
                ": its three vertices lie on a line, as where a T-junction was closed with a "
                "sliver; rvor needs a conforming surface: split the faces at such a vertex "
                "instead");
  throw Error("mesh " + path + " intersects itself: " + triangle_text(mesh, a) + " and triangle " +
              std::to_string(b) +
              " cross or touch other than along an edge they share or at a vertex of one sheet "
              "of the surface; a mesh domain must be a closed surface that bounds a volume "
              "without touching itself");
}

}  // namespace rvor
