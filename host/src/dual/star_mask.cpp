// Rasterisation of a seed's star into a voxel mask (star_mask.h).
#include "star_mask.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>

namespace rvor::detail {

namespace {

struct HalfSpace {
  Vec3 normal;  // unit, pointing into the simplex
  double offset;
};

double distance_to_segment(const Vec3& p, const Vec3& a, const Vec3& b) {
  const Vec3 ab = b - a;
  const double length2 = ab.squaredNorm();
  const double t = length2 > 0.0 ? std::clamp((p - a).dot(ab) / length2, 0.0, 1.0) : 0.0;
  return (p - (a + t * ab)).norm();
}

// The inward unit normal of the facet opposite vertex `i`; false when the simplex is flat there.
bool facet_half_space(const std::vector<Vec3>& v, int dimension, std::size_t i, HalfSpace& out) {
  std::vector<Vec3> facet;
  for (std::size_t j = 0; j < v.size(); ++j)
    if (j != i) facet.push_back(v[j]);
  Vec3 n;
  if (dimension == 3) {
    n = (facet[1] - facet[0]).cross(facet[2] - facet[0]);
  } else {
    const Vec3 e = facet[1] - facet[0];
    n = Vec3(-e.y(), e.x(), 0.0);
  }
  const double norm = n.norm();
  if (!(norm > 1e-9)) return false;
  n /= norm;
  const double height = n.dot(v[i] - facet[0]);
  if (std::abs(height) < 1e-6) return false;
  if (height < 0) n = -n;
  out = {n, n.dot(facet[0])};
  return true;
}

// Calls f(x, index) for each voxel of the box within the simplex's bounding box grown by m.
template <typename F>
void for_each_voxel_near(const std::array<int, 3>& lo, const std::array<int, 3>& dims,
                         const StarSimplex& s, F&& f) {
  std::array<int, 3> from{}, to{};
  for (int a = 0; a < 3; ++a) {
    double vmin = s.vertices[0][a], vmax = vmin;
    for (const Vec3& v : s.vertices) vmin = std::min(vmin, v[a]), vmax = std::max(vmax, v[a]);
    from[a] = std::max(lo[a], static_cast<int>(std::floor(vmin - s.margin)));
    to[a] = std::min(lo[a] + dims[a] - 1, static_cast<int>(std::ceil(vmax + s.margin)));
  }
  for (int k = from[2]; k <= to[2]; ++k)
    for (int j = from[1]; j <= to[1]; ++j)
      for (int i = from[0]; i <= to[0]; ++i)
        f(Vec3(i, j, k), static_cast<std::size_t>(i - lo[0]) +
                             static_cast<std::size_t>(dims[0]) *
                                 (static_cast<std::size_t>(j - lo[1]) +
                                  static_cast<std::size_t>(dims[1]) * (k - lo[2])));
}

void mark_half_spaces(const std::array<int, 3>& lo, const std::array<int, 3>& dims,
                      const StarSimplex& s, const std::vector<HalfSpace>& planes,
                      std::vector<uint8_t>& mask) {
  for_each_voxel_near(lo, dims, s, [&](const Vec3& x, std::size_t index) {
    for (const HalfSpace& h : planes)
      if (h.normal.dot(x) < h.offset - s.margin) return;
    mask[index] = 1;
  });
}

void mark_capsules(const std::array<int, 3>& lo, const std::array<int, 3>& dims,
                   const StarSimplex& s, std::vector<uint8_t>& mask) {
  for_each_voxel_near(lo, dims, s, [&](const Vec3& x, std::size_t index) {
    for (std::size_t a = 0; a < s.vertices.size(); ++a)
      for (std::size_t b = a + 1; b < s.vertices.size(); ++b)
        if (distance_to_segment(x, s.vertices[a], s.vertices[b]) <= s.margin) {
          mask[index] = 1;
          return;
        }
  });
}

}  // namespace

std::vector<uint8_t> star_mask(const std::array<int, 3>& lo, const std::array<int, 3>& dims,
                               int dimension, const std::vector<StarSimplex>& simplices) {
  std::vector<uint8_t> mask(static_cast<std::size_t>(dims[0]) * dims[1] * dims[2], 0);
  for (const StarSimplex& s : simplices) {
    std::vector<HalfSpace> planes;
    bool full = static_cast<int>(s.vertices.size()) == dimension + 1;
    for (std::size_t i = 0; full && i < s.vertices.size(); ++i) {
      HalfSpace h{Vec3::Zero(), 0.0};
      full = facet_half_space(s.vertices, dimension, i, h);
      planes.push_back(h);
    }
    if (full)
      mark_half_spaces(lo, dims, s, planes, mask);
    else
      mark_capsules(lo, dims, s, mask);
  }
  return mask;
}

}  // namespace rvor::detail
