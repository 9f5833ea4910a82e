// Exact geometric predicates on the straight dual (the only CGAL translation unit of the dual):
// orientations, and intersecting pairs of top simplices found by box intersection and decided
// by exact tests that ignore the contact along a shared face.
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/box_intersection_d.h>
#include <CGAL/intersections.h>

#include <algorithm>
#include <cstdint>

#include "dual/dual_internal.h"
#include "dual/parallel_for.h"

namespace rvor::dual {

namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using P2 = Kernel::Point_2;
using P3 = Kernel::Point_3;
using Box = CGAL::Box_intersection_d::Box_with_info_d<double, 3, std::size_t>;

P2 p2(const Vec3& v) {
  return P2(v.x(), v.y());
}
P3 p3(const Vec3& v) {
  return P3(v.x(), v.y(), v.z());
}

int sign_of(CGAL::Orientation o) {
  return o == CGAL::POSITIVE ? 1 : (o == CGAL::NEGATIVE ? -1 : 0);
}

// Up to four vertex ids (no heap allocation: this runs for millions of candidate pairs).
struct Vertices {
  std::array<int32_t, 4> id{};
  int count = 0;
  void push_back(int32_t v) { id[count++] = v; }
  std::size_t size() const { return static_cast<std::size_t>(count); }
  int32_t operator[](int i) const { return id[i]; }
  const int32_t* begin() const { return id.data(); }
  const int32_t* end() const { return id.data() + count; }
};

// The vertices of simplices a and b split into shared ones and the rest of each.
struct Split {
  Vertices shared, only_a, only_b;
};

Split split(const std::array<int32_t, 4>& a, const std::array<int32_t, 4>& b, int n) {
  Split s;
  for (int i = 0; i < n; ++i) {
    const bool in_b = std::find(b.begin(), b.begin() + n, a[i]) != b.begin() + n;
    (in_b ? s.shared : s.only_a).push_back(a[i]);
  }
  for (int i = 0; i < n; ++i)
    if (std::find(a.begin(), a.begin() + n, b[i]) == a.begin() + n) s.only_b.push_back(b[i]);
  return s;
}

class PairTest {
 public:
  explicit PairTest(const StraightDual& dual) : dual_(dual) {}

  bool intersect(std::size_t i, std::size_t j) const {
    const auto a = dual_.top_simplex(i), b = dual_.top_simplex(j);
    const Split s = split(a, b, dual_.dimension + 1);
    // Most candidate pairs are disjoint but for a shared vertex; a facet plane separating them
    // proves it with a few statically filtered orientations, where CGAL's general intersection
    // tests would run in interval arithmetic.
    if (s.shared.size() <= 1 &&
        (facet_separates(a, s.shared, s.only_b) || facet_separates(b, s.shared, s.only_a)))
      return false;
    return dual_.dimension == 3 ? intersect_3(a, b, s) : intersect_2(a, b, s);
  }

 private:
  const Vec3& x(int32_t v) const { return dual_.vertices[v]; }

  // Side (-1, 0, +1) of point p relative to the facet of top simplex s without vertex `skip`.
  int facet_side(const std::array<int32_t, 4>& s, int skip, const Vec3& p) const {
    std::array<int32_t, 3> f{};
    int m = 0;
    for (int v = 0; v <= dual_.dimension; ++v)
      if (v != skip) f[m++] = s[v];
    if (dual_.dimension == 2) return sign_of(CGAL::orientation(p2(x(f[0])), p2(x(f[1])), p2(p)));
    return sign_of(CGAL::orientation(p3(x(f[0])), p3(x(f[1])), p3(x(f[2])), p3(p)));
  }

  // Whether the plane of a facet of s holding all `shared` vertices has every vertex of `others`
  // (the other simplex's unshared ones) strictly on the side away from s: the two simplices then
  // meet at most in their common face.
  bool facet_separates(const std::array<int32_t, 4>& s, const Vertices& shared,
                       const Vertices& others) const {
    for (int skip = 0; skip <= dual_.dimension; ++skip) {
      if (std::find(shared.begin(), shared.end(), s[skip]) != shared.end()) continue;
      const int inside = facet_side(s, skip, x(s[skip]));
      if (inside == 0) continue;
      bool separated = true;
      for (int32_t v : others)
        if (facet_side(s, skip, x(v)) != -inside) {
          separated = false;
          break;
        }
      if (separated) return true;
    }
    return false;
  }
  Kernel::Triangle_2 triangle_2(const std::array<int32_t, 4>& t) const {
    return {p2(x(t[0])), p2(x(t[1])), p2(x(t[2]))};
  }
  Kernel::Tetrahedron_3 tetrahedron(const std::array<int32_t, 4>& t) const {
    return {p3(x(t[0])), p3(x(t[1])), p3(x(t[2])), p3(x(t[3]))};
  }

  bool intersect_2(const std::array<int32_t, 4>& a, const std::array<int32_t, 4>& b,
                   const Split& s) const {
    switch (s.shared.size()) {
      case 0:
        return CGAL::do_intersect(triangle_2(a), triangle_2(b));
      case 1: {  // overlapping near the shared vertex <=> an opposite edge meets the other triangle
        const Kernel::Segment_2 ea(p2(x(s.only_a[0])), p2(x(s.only_a[1])));
        const Kernel::Segment_2 eb(p2(x(s.only_b[0])), p2(x(s.only_b[1])));
        return CGAL::do_intersect(ea, triangle_2(b)) || CGAL::do_intersect(eb, triangle_2(a));
      }
      case 2:  // a shared edge: the opposite vertices must lie on opposite sides
        return CGAL::orientation(p2(x(s.shared[0])), p2(x(s.shared[1])), p2(x(s.only_a[0]))) ==
               CGAL::orientation(p2(x(s.shared[0])), p2(x(s.shared[1])), p2(x(s.only_b[0])));
      default:
        return true;  // the same triangle twice
    }
  }

  bool intersect_3(const std::array<int32_t, 4>& a, const std::array<int32_t, 4>& b,
                   const Split& s) const {
    switch (s.shared.size()) {
      case 0:
        return CGAL::do_intersect(tetrahedron(a), tetrahedron(b));
      case 1: {  // the cones at the shared vertex overlap <=> an opposite face meets the other tet
        const Kernel::Triangle_3 fa(p3(x(s.only_a[0])), p3(x(s.only_a[1])), p3(x(s.only_a[2])));
        const Kernel::Triangle_3 fb(p3(x(s.only_b[0])), p3(x(s.only_b[1])), p3(x(s.only_b[2])));
        return CGAL::do_intersect(fa, tetrahedron(b)) || CGAL::do_intersect(fb, tetrahedron(a));
      }
      case 2:
        return wedges_overlap(s);
      case 3: {  // a shared facet: the opposite vertices must lie on opposite sides
        const P3 u = p3(x(s.shared[0])), v = p3(x(s.shared[1])), w = p3(x(s.shared[2]));
        return CGAL::orientation(u, v, w, p3(x(s.only_a[0]))) ==
               CGAL::orientation(u, v, w, p3(x(s.only_b[0])));
      }
      default:
        return true;
    }
  }

  // Two tetrahedra sharing the edge uv overlap iff their dihedral wedges about uv do: each wedge
  // is convex, so otherwise a plane through uv separates them.
  bool wedges_overlap(const Split& s) const {
    const P3 u = p3(x(s.shared[0])), v = p3(x(s.shared[1]));
    const P3 a1 = p3(x(s.only_a[0])), a2 = p3(x(s.only_a[1]));
    const P3 b1 = p3(x(s.only_b[0])), b2 = p3(x(s.only_b[1]));
    auto turn = [&](const P3& p, const P3& q) { return sign_of(CGAL::orientation(u, v, p, q)); };
    auto inside = [&](const P3& r, const P3& p, const P3& q) {
      const int w = turn(p, q);
      return w != 0 && turn(p, r) == w && turn(r, q) == w;
    };
    auto same_ray = [&](const P3& p, const P3& q) {
      return turn(p, q) == 0 && CGAL::coplanar_orientation(u, v, p, q) == CGAL::POSITIVE;
    };
    if (inside(b1, a1, a2) || inside(b2, a1, a2) || inside(a1, b1, b2) || inside(a2, b1, b2))
      return true;
    return (same_ray(a1, b1) && same_ray(a2, b2)) || (same_ray(a1, b2) && same_ray(a2, b1));
  }

  const StraightDual& dual_;
};

std::vector<Box> element_boxes(const StraightDual& dual, const std::vector<int>& orientation) {
  std::vector<Box> boxes;
  for (std::size_t t = 0; t < dual.top_count(); ++t) {
    if (orientation[t] == 0) continue;
    const auto s = dual.top_simplex(t);
    CGAL::Bbox_3 box;
    for (int v = 0; v <= dual.dimension; ++v) box += p3(dual.vertices[s[v]]).bbox();
    boxes.emplace_back(box, t);
  }
  return boxes;
}

using Pairs = std::vector<std::array<std::size_t, 2>>;

// Appends the pair of elements (smaller index first).
struct PairSink {
  Pairs& out;
  void operator()(const Box& a, const Box& b) const {
    out.push_back({std::min(a.info(), b.info()), std::max(a.info(), b.info())});
  }
};

// The pairs of elements whose (closed) boxes overlap, in no particular order. Large inputs are cut
// at the median x of the box centres into boxes left of the cut, right of it, and straddling it;
// left/right pairs cannot overlap, so two threads find left+straddling pairs and right+right,
// right+straddling ones.
Pairs overlapping_boxes(std::vector<Box> boxes) {
  Pairs pairs;
  if (boxes.size() < 4096) {
    CGAL::box_self_intersection_d(boxes.begin(), boxes.end(), PairSink{pairs});
    return pairs;
  }
  std::vector<double> centres;
  for (const Box& b : boxes) centres.push_back(0.5 * (b.min_coord(0) + b.max_coord(0)));
  std::nth_element(centres.begin(), centres.begin() + centres.size() / 2, centres.end());
  const double cut = centres[centres.size() / 2];
  std::vector<Box> left_and_straddling, right, straddling;
  for (const Box& b : boxes) {
    if (b.min_coord(0) > cut)
      right.push_back(b);
    else
      left_and_straddling.push_back(b);
    if (b.min_coord(0) <= cut && b.max_coord(0) >= cut) straddling.push_back(b);
  }
  std::array<Pairs, 2> found;
  detail::parallel_for(2, 1, [&](std::size_t part) {
    PairSink sink{found[part]};
    if (part == 0) {
      CGAL::box_self_intersection_d(left_and_straddling.begin(), left_and_straddling.end(), sink);
      return;
    }
    CGAL::box_self_intersection_d(right.begin(), right.end(), sink);
    CGAL::box_intersection_d(right.begin(), right.end(), straddling.begin(), straddling.end(),
                             sink);
  });
  pairs = std::move(found[0]);
  pairs.insert(pairs.end(), found[1].begin(), found[1].end());
  return pairs;
}

}  // namespace

int orientation_sign(const StraightDual& dual, const std::array<int32_t, 4>& s) {
  const auto& x = dual.vertices;
  return dual.dimension == 3
             ? sign_of(CGAL::orientation(p3(x[s[0]]), p3(x[s[1]]), p3(x[s[2]]), p3(x[s[3]])))
             : sign_of(CGAL::orientation(p2(x[s[0]]), p2(x[s[1]]), p2(x[s[2]])));
}

std::vector<int> orientation_signs(const StraightDual& dual) {
  std::vector<int> signs(dual.top_count());
  for (std::size_t t = 0; t < dual.top_count(); ++t)
    signs[t] = orientation_sign(dual, dual.top_simplex(t));
  return signs;
}

std::vector<std::array<std::size_t, 2>> intersecting_pairs(const StraightDual& dual,
                                                           const std::vector<int>& orientation) {
  const std::vector<std::array<std::size_t, 2>> candidates =
      overlapping_boxes(element_boxes(dual, orientation));
  // The exact tests dominate the dual's time (anisotropic elements have large, overlapping
  // boxes): run them on all cores.
  std::vector<uint8_t> intersects(candidates.size(), 0);
  const PairTest test(dual);
  detail::parallel_for(candidates.size(), 256, [&](std::size_t i) {
    intersects[i] = test.intersect(candidates[i][0], candidates[i][1]) ? 1 : 0;
  });
  std::vector<std::array<std::size_t, 2>> pairs;
  for (std::size_t i = 0; i < candidates.size(); ++i)
    if (intersects[i]) pairs.push_back(candidates[i]);
  std::sort(pairs.begin(), pairs.end());
  return pairs;
}

}  // namespace rvor::dual

namespace rvor {

int seeds_affine_dimension(const std::vector<Vec3>& seeds, int dimension) {
  using Point = CGAL::Exact_predicates_inexact_constructions_kernel::Point_3;
  const auto point = [&](std::size_t i) {
    return Point(seeds[i].x(), seeds[i].y(), dimension == 2 ? 0.0 : seeds[i].z());
  };
  if (seeds.empty()) return -1;
  // The first seed off the hull so far raises its dimension; the rest are tested against it.
  std::size_t i = 1;
  const Point a = point(0);
  while (i < seeds.size() && point(i) == a) ++i;
  if (i == seeds.size()) return 0;
  const Point b = point(i);
  while (i < seeds.size() && CGAL::collinear(a, b, point(i))) ++i;
  if (i == seeds.size()) return 1;
  const Point c = point(i);
  while (i < seeds.size() && CGAL::coplanar(a, b, c, point(i))) ++i;
  return i == seeds.size() ? 2 : 3;
}

}  // namespace rvor
