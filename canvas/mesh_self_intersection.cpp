// require_no_self_intersection (surface_mesh.h): the one translation unit of the canvas libraries
// with CGAL's polygon mesh processing, which takes long to compile.
//
// CGAL's Polygon_mesh_processing::self_intersections tests every pair of triangles whose bounding
// boxes overlap. Around a vertex of high degree (a cone's apex, a fan-cut polygon) every pair of
// its triangles overlaps there, and so do the boxes of long triangles across a flat fan: N^2/2
// exact tests, 14 s for a double cone of 10k rim vertices (20k triangles), over a minute for 20k.
// The test below needs no pair that shares a vertex: two triangles that meet other than along what
// they share have an edge of one meeting the other where they share no vertex (see
// require_no_self_intersection). It looks for such an edge and triangle in the cells of a bisection
// of space, each holding the edges and triangles that meet it; a cell whose elements all share one
// vertex holds no such pair and is not split, which keeps a fan's cells few.
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_mesh_processing/orient_polygon_soup.h>
#include <CGAL/Polygon_mesh_processing/polygon_soup_to_polygon_mesh.h>
#include <CGAL/intersections.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <optional>
#include <utility>
#include <vector>

#include "rvor/error.h"
#include "surface_mesh.h"

namespace rvor {

namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point = Kernel::Point_3;
using Segment = Kernel::Segment_3;
using Triangle = Kernel::Triangle_3;
using Corners = std::array<std::size_t, 3>;
namespace pmp = CGAL::Polygon_mesh_processing;

// The triangles as CGAL's polygon soup, triangle i being triangle i. Orienting the soup makes any
// closed mesh acceptable whatever the orientation of its triangles (the canvas does not need
// one), and splits a vertex where separate sheets meet, so that they show up as touching below.
void orient(std::vector<Point>& points, std::vector<Corners>& triangles, const std::string& path) {
  // What orienting cannot mend (a triangle that repeats a vertex, a one-sided surface) is no
  // boundary of a volume either.
  if (!pmp::is_polygon_soup_a_polygon_mesh(triangles) &&
      (pmp::orient_polygon_soup(points, triangles),  // keeps the triangles in order
       !pmp::is_polygon_soup_a_polygon_mesh(triangles)))
    throw Error("mesh " + path +
                " is not the boundary of a volume: its triangles cannot be oriented consistently "
                "(a one-sided surface, or a triangle that repeats a vertex)");
}

std::string triangle_text(const SurfaceMesh& mesh, std::size_t t) {
  const auto& v = mesh.triangles[t];
  return "triangle " + std::to_string(t) +
         " (0-based, polygons counted as the triangles they are cut into; " + "centred at " +
         point_text((mesh.vertices[v[0]] + mesh.vertices[v[1]] + mesh.vertices[v[2]]) / 3.0) + ")";
}

using TrianglePair = std::pair<std::size_t, std::size_t>;

struct Edge {
  std::size_t a, b;
  std::size_t triangle;  // one triangle along it
};

// Looks for an edge and a triangle without a common vertex that meet (exact predicates).
class EdgeTriangleSearch {
 public:
  EdgeTriangleSearch(const std::vector<Point>& points, const std::vector<Corners>& triangles,
                     const std::vector<Edge>& edges)
      : points_(points), triangles_(triangles), edges_(edges) {
    for (const Edge& e : edges_) edge_boxes_.push_back(segment(e).bbox());
    for (const Corners& t : triangles_) triangle_boxes_.push_back(triangle(t).bbox());
  }

  std::optional<TrianglePair> find() {
    std::vector<std::size_t> edges(edges_.size()), triangles(triangles_.size());
    for (std::size_t e = 0; e < edges.size(); ++e) edges[e] = e;
    for (std::size_t t = 0; t < triangles.size(); ++t) triangles[t] = t;
    CGAL::Bbox_3 box;
    for (const CGAL::Bbox_3& b : triangle_boxes_) box += b;
    // Widened by odd fractions of its size, so that the cuts miss the planes that meshes drawn
    // on a grid tend to have elements in: a cut through the plane of a flat fan sends the tests
    // of all its triangles to exact arithmetic (the 100k double cone: 8.3 s before, 7.1 s after).
    const double size =
        std::max({box.xmax() - box.xmin(), box.ymax() - box.ymin(), box.zmax() - box.zmin()});
    double lo[3], hi[3];
    for (int a = 0; a < 3; ++a) {
      lo[a] = box.min(a) - 0.0123 * size;
      hi[a] = box.max(a) + 0.0371 * size;
    }
    box = CGAL::Bbox_3(lo[0], lo[1], lo[2], hi[0], hi[1], hi[2]);
    search(box, edges, triangles, 0);
    return found_;
  }

 private:
  // Deeper than this (a box of 2^-30 of the mesh's extent across) a cell's pairs are tested one
  // by one.
  static constexpr int kMaxDepth = 90;

  Segment segment(const Edge& e) const { return {points_[e.a], points_[e.b]}; }
  Triangle triangle(const Corners& t) const {
    return {points_[t[0]], points_[t[1]], points_[t[2]]};
  }
  static bool contains(const CGAL::Bbox_3& outer, const CGAL::Bbox_3& inner) {
    for (int a = 0; a < 3; ++a)
      if (inner.min(a) < outer.min(a) || inner.max(a) > outer.max(a)) return false;
    return true;
  }
  bool edge_meets(std::size_t e, const CGAL::Bbox_3& box) const {
    const CGAL::Bbox_3& own = edge_boxes_[e];
    if (!CGAL::do_overlap(own, box)) return false;
    return contains(box, own) || CGAL::do_intersect(segment(edges_[e]), box);
  }
  bool triangle_meets(std::size_t t, const CGAL::Bbox_3& box) const {
    const CGAL::Bbox_3& own = triangle_boxes_[t];
    if (!CGAL::do_overlap(own, box)) return false;
    return contains(box, own) || CGAL::do_intersect(triangle(triangles_[t]), box);
  }
  bool shares_vertex(const Edge& e, const Corners& t) const {
    return std::find(t.begin(), t.end(), e.a) != t.end() ||
           std::find(t.begin(), t.end(), e.b) != t.end();
  }

  // Whether one vertex is common to all the cell's elements: then no edge and triangle in it lack
  // a common vertex. Around a vertex of high degree, cells hold its triangles and edges only.
  bool one_vertex_in_all(const std::vector<std::size_t>& edges,
                         const std::vector<std::size_t>& triangles) const {
    for (const std::size_t v : {edges_[edges.front()].a, edges_[edges.front()].b}) {
      bool in_all = true;
      for (std::size_t i = 0; in_all && i < edges.size(); ++i)
        in_all = edges_[edges[i]].a == v || edges_[edges[i]].b == v;
      for (std::size_t i = 0; in_all && i < triangles.size(); ++i) {
        const Corners& t = triangles_[triangles[i]];
        in_all = t[0] == v || t[1] == v || t[2] == v;
      }
      if (in_all) return true;
    }
    return false;
  }

  void test_pairs(const std::vector<std::size_t>& edges,
                  const std::vector<std::size_t>& triangles) {
    for (const std::size_t e : edges)
      for (const std::size_t t : triangles)
        if (!shares_vertex(edges_[e], triangles_[t]) &&
            CGAL::do_overlap(edge_boxes_[e], triangle_boxes_[t]) &&
            CGAL::do_intersect(segment(edges_[e]), triangle(triangles_[t]))) {
          found_ = std::minmax(edges_[e].triangle, t);
          return;
        }
  }

  // Tests the pairs whose boxes, cut to the cell, overlap, found by sorting them along one axis;
  // false, testing none, when that would look at too many pairs (then the cell is split). Cells
  // do not part long elements side by side (the walls of a prism of 40k sides, 1 by 1/40k
  // triangles) but their boxes do.
  bool sweep_pairs(const CGAL::Bbox_3& cell, const std::vector<std::size_t>& edges,
                   const std::vector<std::size_t>& triangles) {
    struct Item {
      CGAL::Bbox_3 box;
      std::size_t id;
      bool edge;
    };
    std::vector<Item> items;
    items.reserve(edges.size() + triangles.size());
    const auto cut = [&](const CGAL::Bbox_3& b) {
      return CGAL::Bbox_3(std::max(b.xmin(), cell.xmin()), std::max(b.ymin(), cell.ymin()),
                          std::max(b.zmin(), cell.zmin()), std::min(b.xmax(), cell.xmax()),
                          std::min(b.ymax(), cell.ymax()), std::min(b.zmax(), cell.zmax()));
    };
    for (const std::size_t e : edges) items.push_back({cut(edge_boxes_[e]), e, true});
    for (const std::size_t t : triangles) items.push_back({cut(triangle_boxes_[t]), t, false});
    // Along the axis where the boxes are shortest for the cell's size: the fewest overlaps.
    int axis = 0;
    double fewest = HUGE_VAL;
    for (int a = 0; a < 3; ++a) {
      double length = 0;
      for (const Item& item : items) length += item.box.max(a) - item.box.min(a);
      const double share = length / (cell.max(a) - cell.min(a));
      if (share < fewest) fewest = share, axis = a;
    }
    // Boxes spread evenly would overlap in about items * share pairs: far more, and the sort is
    // not worth trying (a fan's cells, until small).
    const std::size_t budget = 8 * items.size() + 1024;
    if (static_cast<double>(items.size()) * fewest > 4.0 * static_cast<double>(budget))
      return false;
    std::sort(items.begin(), items.end(),
              [axis](const Item& x, const Item& y) { return x.box.min(axis) < y.box.min(axis); });
    std::size_t looked = 0;
    std::vector<std::pair<std::size_t, std::size_t>> candidates;  // edge, triangle
    for (std::size_t i = 0; i < items.size(); ++i)
      for (std::size_t j = i + 1;
           j < items.size() && items[j].box.min(axis) <= items[i].box.max(axis); ++j) {
        if (++looked > budget) return false;
        if (items[i].edge == items[j].edge || !CGAL::do_overlap(items[i].box, items[j].box))
          continue;
        const std::size_t e = items[i].edge ? items[i].id : items[j].id;
        const std::size_t t = items[i].edge ? items[j].id : items[i].id;
        if (!shares_vertex(edges_[e], triangles_[t])) candidates.emplace_back(e, t);
      }
    for (const auto& [e, t] : candidates)
      if (CGAL::do_intersect(segment(edges_[e]), triangle(triangles_[t]))) {
        found_ = std::minmax(edges_[e].triangle, t);
        break;
      }
    return true;
  }

  void search(const CGAL::Bbox_3& box, const std::vector<std::size_t>& edges,
              const std::vector<std::size_t>& triangles, int depth) {
    if (edges.empty() || triangles.empty() || one_vertex_in_all(edges, triangles)) return;
    int axis = 0;
    for (int a = 1; a < 3; ++a)
      if (box.max(a) - box.min(a) > box.max(axis) - box.min(axis)) axis = a;
    const double middle = 0.5 * (box.min(axis) + box.max(axis));
    if (sweep_pairs(box, edges, triangles)) return;
    if (depth >= kMaxDepth || !(box.min(axis) < middle && middle < box.max(axis)))
      return test_pairs(edges, triangles);
    for (int half = 0; half < 2 && !found_; ++half) {
      double lo[3] = {box.xmin(), box.ymin(), box.zmin()};
      double hi[3] = {box.xmax(), box.ymax(), box.zmax()};
      (half == 0 ? hi : lo)[axis] = middle;  // closed halves: what lies on the cut is in both
      const CGAL::Bbox_3 part(lo[0], lo[1], lo[2], hi[0], hi[1], hi[2]);
      std::vector<std::size_t> part_edges, part_triangles;
      // An element that meets the cell on one side of the cut only meets that half: the exact
      // test is left to those that straddle the cut.
      const auto on_side = [&](const CGAL::Bbox_3& own) {
        return half == 0 ? own.max(axis) < middle : own.min(axis) > middle;
      };
      const auto off_side = [&](const CGAL::Bbox_3& own) {
        return half == 0 ? own.min(axis) > middle : own.max(axis) < middle;
      };
      for (const std::size_t e : edges)
        if (!off_side(edge_boxes_[e]) && (on_side(edge_boxes_[e]) || edge_meets(e, part)))
          part_edges.push_back(e);
      for (const std::size_t t : triangles)
        if (!off_side(triangle_boxes_[t]) &&
            (on_side(triangle_boxes_[t]) || triangle_meets(t, part)))
          part_triangles.push_back(t);
      search(part, part_edges, part_triangles, depth + 1);
    }
  }

  const std::vector<Point>& points_;
  const std::vector<Corners>& triangles_;
  const std::vector<Edge>& edges_;
  std::vector<CGAL::Bbox_3> edge_boxes_, triangle_boxes_;
  std::optional<TrianglePair> found_;
};

std::uint64_t edge_key(std::size_t a, std::size_t b) {
  return (static_cast<std::uint64_t>(std::min(a, b)) << 32) | std::max(a, b);
}

std::size_t third_corner(const Corners& t, std::size_t a, std::size_t b) {
  for (const std::size_t v : t)
    if (v != a && v != b) return v;
  return t[0];
}

// The first pair of triangles that meet other than along the vertices and edges they share: two
// triangles that share an edge meet beyond it only when folded onto each other in one plane; two
// that share all three corners coincide; for the others see the file's comment.
std::optional<TrianglePair> crossing_pair(const std::vector<Point>& points,
                                          const std::vector<Corners>& triangles) {
  std::vector<std::pair<Corners, std::size_t>> sorted;
  std::vector<std::pair<std::uint64_t, std::size_t>> edge_uses;
  for (std::size_t t = 0; t < triangles.size(); ++t) {
    Corners c = triangles[t];
    std::sort(c.begin(), c.end());
    sorted.emplace_back(c, t);
    for (int e = 0; e < 3; ++e) edge_uses.emplace_back(edge_key(c[e], c[(e + 1) % 3]), t);
  }
  std::sort(sorted.begin(), sorted.end());
  for (std::size_t i = 1; i < sorted.size(); ++i)
    if (sorted[i].first == sorted[i - 1].first)
      return std::minmax(sorted[i - 1].second, sorted[i].second);
  std::sort(edge_uses.begin(), edge_uses.end());
  std::vector<Edge> edges;
  for (std::size_t i = 0; i < edge_uses.size();) {
    std::size_t end = i + 1;
    while (end < edge_uses.size() && edge_uses[end].first == edge_uses[i].first) ++end;
    const std::size_t a = edge_uses[i].first >> 32, b = edge_uses[i].first & 0xffffffffu;
    edges.push_back({a, b, edge_uses[i].second});
    for (std::size_t m = i; m < end; ++m)
      for (std::size_t n = m + 1; n < end; ++n) {
        const std::size_t s = edge_uses[m].second, t = edge_uses[n].second;
        const Point &p = points[a], &q = points[b], &r = points[third_corner(triangles[s], a, b)],
                    &o = points[third_corner(triangles[t], a, b)];
        if (CGAL::coplanar(p, q, r, o) && CGAL::coplanar_orientation(p, q, r, o) == CGAL::POSITIVE)
          return std::minmax(s, t);
      }
    i = end;
  }
  return EdgeTriangleSearch(points, triangles, edges).find();
}

}  // namespace

// Two triangles that meet other than along the vertices and edges they share, and share at most
// one vertex, have an edge of one meeting the other where they share no vertex: their meeting is
// convex; when they share no vertex, an end of it lies on an edge of one of them; when they share
// a vertex v, it is a set around v whose far end lies on the edge of one of them opposite v (a
// ray from v leaves a triangle through that edge). Conversely such an edge and triangle make the
// triangles along the edge meet the other beyond what they share.
void require_no_self_intersection(const SurfaceMesh& mesh, const std::string& path) {
  std::vector<Point> points;
  points.reserve(mesh.vertices.size());
  for (const Vec3& v : mesh.vertices) points.emplace_back(v.x(), v.y(), v.z());
  std::vector<Corners> triangles;
  triangles.reserve(mesh.triangles.size());
  for (const auto& t : mesh.triangles)
    triangles.push_back({static_cast<std::size_t>(t[0]), static_cast<std::size_t>(t[1]),
                         static_cast<std::size_t>(t[2])});
  orient(points, triangles, path);
  // A degenerate triangle first: the edge and triangle argument needs triangles with an area.
  for (std::size_t t = 0; t < triangles.size(); ++t)
    if (CGAL::collinear(points[triangles[t][0]], points[triangles[t][1]], points[triangles[t][2]]))
      throw Error("mesh " + path + " has a degenerate " + triangle_text(mesh, t) +
                  ": its three vertices lie on a line, as where a T-junction was closed with a "
                  "sliver; rvor needs a conforming surface: split the faces at such a vertex "
                  "instead");
  const std::optional<TrianglePair> pair = crossing_pair(points, triangles);
  if (!pair) return;
  throw Error("mesh " + path + " intersects itself: " + triangle_text(mesh, pair->first) +
              " and triangle " + std::to_string(pair->second) +
              " cross or touch other than along an edge they share or at a vertex of one sheet "
              "of the surface; a mesh domain must be a closed surface that bounds a volume "
              "without touching itself");
}

}  // namespace rvor
