#pragma once
// Inputs for the dual tests: uniform anisotropic metrics, Poisson-disk seeds in the metric, and
// the labeled canvas from the reference propagator.
#include <cstdint>
#include <functional>
#include <vector>

#include "rvor/canvas.h"
#include "rvor/propagation.h"

namespace rvor::test {

// F = R diag(scales) R^T for a random rotation R (deterministic in rng_seed); G = F^2.
// dimension 2: rotation in the xy plane, scales[2] ignored (F_zz = 1).
Mat3 random_uniform_sqrt_metric(int dimension, const Vec3& scales, std::uint64_t rng_seed);

// Dart throwing in F-space with rejection: points of the box [lo, hi] (z ignored in 2D) whose
// F-images are at least `radius` apart, until `count` are accepted; throws if that takes more
// than 10^6 darts. Seeds are kept away from the box faces by `margin` (world units), and darts
// that `accept` refuses (e.g. outside a mesh domain) are thrown away.
std::vector<Vec3> poisson_disk_seeds(int dimension, const Vec3& lo, const Vec3& hi, double margin,
                                     const Mat3& F, double radius, std::size_t count,
                                     std::uint64_t rng_seed,
                                     const std::function<bool(const Vec3&)>& accept = {});

// A radius that lets `count` darts fit easily: 0.7 (vol_F / count)^(1/d).
double poisson_radius(int dimension, const Vec3& lo, const Vec3& hi, const Mat3& F,
                      std::size_t count);

// The exact labeled canvas of a uniform metric: nearest seed in |F (x - s)| (ties: smallest label).
VoronoiField exact_uniform_field(const Canvas& canvas, const std::vector<Vec3>& seeds,
                                 const Mat3& F);

VoronoiField solve_reference(const Canvas& canvas, const std::vector<Vec3>& seeds);

}  // namespace rvor::test
