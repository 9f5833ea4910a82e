#include "dual/dual_fixtures.h"

#include "support/box_canvas.h"

#include <Eigen/Geometry>
#include <cmath>
#include <limits>
#include <random>
#include <stdexcept>

namespace rvor::test {

Mat3 random_uniform_sqrt_metric(int dimension, const Vec3& scales, std::uint64_t rng_seed) {
  std::mt19937_64 rng(rng_seed);
  std::normal_distribution<double> normal;
  Mat3 R = Mat3::Identity();
  if (dimension == 3) {
    Eigen::Quaterniond q(normal(rng), normal(rng), normal(rng), normal(rng));
    R = q.normalized().toRotationMatrix();
  } else {
    R.topLeftCorner<2, 2>() =
        Eigen::Rotation2Dd(std::uniform_real_distribution<double>(0, M_PI)(rng)).toRotationMatrix();
  }
  Vec3 s = scales;
  if (dimension == 2) s[2] = 1.0;
  return R * s.asDiagonal() * R.transpose();
}

double poisson_radius(int dimension, const Vec3& lo, const Vec3& hi, const Mat3& F,
                      std::size_t count) {
  const Vec3 e = hi - lo;
  const double volume = dimension == 3 ? e.prod() * F.determinant()
                                       : e.x() * e.y() * F.topLeftCorner<2, 2>().determinant();
  return 0.7 * std::pow(volume / static_cast<double>(count), 1.0 / dimension);
}

std::vector<Vec3> poisson_disk_seeds(int dimension, const Vec3& lo, const Vec3& hi, double margin,
                                     const Mat3& F, double radius, std::size_t count,
                                     std::uint64_t rng_seed,
                                     const std::function<bool(const Vec3&)>& accept) {
  std::mt19937_64 rng(rng_seed);
  std::vector<std::uniform_real_distribution<double>> axis;
  for (int a = 0; a < 3; ++a) axis.emplace_back(lo[a] + margin, hi[a] - margin);
  std::vector<Vec3> seeds, images;
  for (int dart = 0; dart < 1000000 && seeds.size() < count; ++dart) {
    const Vec3 p(axis[0](rng), axis[1](rng), dimension == 3 ? axis[2](rng) : 0.0);
    if (accept && !accept(p)) continue;
    const Vec3 image = F * p;
    bool free = true;
    for (const Vec3& q : images) free = free && (q - image).norm() >= radius;
    if (!free) continue;
    seeds.push_back(p);
    images.push_back(image);
  }
  if (seeds.size() < count) throw std::runtime_error("Poisson-disk sampling: radius too large");
  return seeds;
}

VoronoiField exact_uniform_field(const Canvas& canvas, const std::vector<Vec3>& seeds,
                                 const Mat3& F) {
  VoronoiField field = constant_field(canvas, std::numeric_limits<float>::infinity(), -1);
  std::vector<Vec3> images;
  for (const Vec3& s : seeds) images.push_back(F * s);
  for (std::size_t slot = 0; slot < canvas.slot_count(); ++slot) {
    if (!canvas.active[slot]) continue;
    const Vec3 p = F * canvas.world_of(slot);
    double best = std::numeric_limits<double>::infinity();
    for (std::size_t s = 0; s < images.size(); ++s) {
      const double d = (p - images[s]).norm();
      if (d < best) {
        best = d;
        field.label[slot] = static_cast<int32_t>(s);
      }
    }
    field.distance[slot] = static_cast<float>(best);
  }
  return field;
}

VoronoiField solve_reference(const Canvas& canvas, const std::vector<Vec3>& seeds) {
  VoronoiField field;
  make_reference_propagator()->solve(canvas, seeds, field);
  return field;
}

}  // namespace rvor::test
