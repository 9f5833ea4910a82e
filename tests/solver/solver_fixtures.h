#pragma once
// Shared helpers of the solver tests: metrics with exact geodesics, error statistics against an
// exact distance, and solving with the double-precision reference.
#include <cmath>
#include <cstdio>
#include <functional>
#include <string>
#include <vector>

#include "reference_solver.h"
#include "rvor/canvas.h"
#include "support/box_canvas.h"

namespace rvor::test {

// Uniform metric whose F = G^{1/2} has eigenvalue `strong` along `axis` and 1 across it.
inline Mat3 uniform_anisotropic_metric(const Vec3& axis, double strong) {
  const Vec3 a = axis.normalized();
  return Mat3::Identity() + (strong * strong - 1) * a * a.transpose();
}

// A smooth diffeomorphism of R^d, phi(x) = x + a (sin(w y), sin(w z), sin(w x)) / w (2D: the z
// terms vanish: phi(x) = x + a (sin(w y), sin(w x)) / w). The perturbation is a-Lipschitz with
// a < 1, so phi is a diffeomorphism; G = J^T J pulls the Euclidean metric back.
struct PullBack {
  int dimension = 3;
  double amplitude = 0.4;
  double frequency = 3.0;

  Vec3 phi(const Vec3& x) const {
    const double a = amplitude, w = frequency;
    if (dimension == 2)
      return {x.x() + a * std::sin(w * x.y()) / w, x.y() + a * std::sin(w * x.x()) / w, 0};
    return {x.x() + a * std::sin(w * x.y()) / w, x.y() + a * std::sin(w * x.z()) / w,
            x.z() + a * std::sin(w * x.x()) / w};
  }
  Mat3 jacobian(const Vec3& x) const {
    const double a = amplitude, w = frequency;
    Mat3 J = Mat3::Identity();
    J(0, 1) = a * std::cos(w * x.y());
    if (dimension == 2) {
      J(1, 0) = a * std::cos(w * x.x());
    } else {
      J(1, 2) = a * std::cos(w * x.z());
      J(2, 0) = a * std::cos(w * x.x());
    }
    return J;
  }
  Mat3 metric(const Vec3& x) const {
    const Mat3 J = jacobian(x);
    Mat3 G = J.transpose() * J;
    if (dimension == 2) {
      G.row(2).setZero();
      G.col(2).setZero();
      G(2, 2) = 1;
    }
    return G;
  }
  double distance(const Vec3& p, const Vec3& q) const { return (phi(p) - phi(q)).norm(); }
};

// Box canvas [-1,1]^d restricted to Omega = phi^-1(ball of radius `radius` around the origin), so
// that phi(Omega) is convex and geodesics are the pull-backs of straight segments.
inline Canvas make_pullback_canvas(const PullBack& pull, int resolution, double radius) {
  const Vec3 lo(-1, -1, -1), hi(1, 1, 1);
  Canvas canvas = make_box_canvas(pull.dimension, lo, hi, resolution,
                                  [&pull](const Vec3& x) { return pull.metric(x); });
  for (std::size_t slot = 0; slot < canvas.slot_count(); ++slot)
    if (canvas.active[slot] && pull.phi(canvas.world_of(slot)).norm() > radius)
      canvas.active[slot] = 0;
  canvas.finalize();
  return canvas;
}

// The centre of the voxel containing `near`: a seed exactly on a voxel centre.
inline Vec3 voxel_centre_near(const Canvas& canvas, const Vec3& near) {
  return canvas.world_of(canvas.voxel_containing(near));
}

struct ErrorStats {
  double max_relative = 0;
  double mean_relative = 0;
  std::size_t samples = 0;
  std::size_t unreached = 0;
};

// Relative error of `distance` against `exact(x)` at every active voxel where exact >= min_exact.
inline ErrorStats relative_errors(const Canvas& canvas, const std::vector<double>& distance,
                                  const std::function<double(const Vec3&)>& exact,
                                  double min_exact) {
  ErrorStats stats;
  double sum = 0;
  for (std::size_t slot = 0; slot < canvas.slot_count(); ++slot) {
    if (!canvas.active[slot]) continue;
    const double e = exact(canvas.world_of(slot));
    if (e < min_exact) continue;
    if (!std::isfinite(distance[slot])) {
      ++stats.unreached;
      continue;
    }
    const double relative = std::abs(distance[slot] - e) / e;
    stats.max_relative = std::max(stats.max_relative, relative);
    sum += relative;
    ++stats.samples;
  }
  stats.mean_relative = stats.samples ? sum / stats.samples : 0;
  return stats;
}

inline detail::ExactField solve_exact(const Canvas& canvas, const std::vector<Vec3>& seeds,
                                      PropagationStats* stats = nullptr) {
  detail::ReferenceSolver solver(canvas);
  detail::ExactField field;
  const PropagationStats s = solver.solve(canvas, seeds, field);
  if (stats) *stats = s;
  return field;
}

inline void report(const std::string& what, const ErrorStats& e, const PropagationStats& s) {
  std::printf(
      "[ measured ] %-40s max %.4f%%  mean %.5f%%  (%zu voxels, %.2f s, %llu pops, %llu solves)\n",
      what.c_str(), 100 * e.max_relative, 100 * e.mean_relative, e.samples, s.seconds,
      static_cast<unsigned long long>(s.iterations),
      static_cast<unsigned long long>(s.voxel_updates));
}

}  // namespace rvor::test
