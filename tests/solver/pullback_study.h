#pragma once
// Convergence study on a pulled-back Euclidean metric (exact geodesics known): shared by the
// default test (64, 128) and the heavy one (64, 128, 256).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "solver_fixtures.h"

namespace rvor::test {

constexpr double kPullBackRadius = 0.75;  // Omega = phi^-1(ball of this radius), inside [-1,1]^d

inline ErrorStats pullback_errors(int dimension, int resolution) {
  PullBack pull;
  pull.dimension = dimension;
  const Canvas canvas = make_pullback_canvas(pull, resolution, kPullBackRadius);
  const Vec3 seed = voxel_centre_near(canvas, Vec3(0.1, -0.05, dimension == 3 ? 0.02 : 0));
  PropagationStats stats;
  const detail::ExactField field = solve_exact(canvas, {seed}, &stats);
  const ErrorStats errors = relative_errors(
      canvas, field.distance, [&](const Vec3& x) { return pull.distance(x, seed); }, 0.1);
  report(std::to_string(dimension) + "D pull-back " + std::to_string(resolution), errors, stats);
  EXPECT_EQ(errors.unreached, 0u);
  return errors;
}

// Errors at each resolution (each twice the previous one) and the observed orders between them.
inline std::vector<ErrorStats> pullback_study(int dimension, const std::vector<int>& resolutions) {
  std::vector<ErrorStats> errors;
  for (int r : resolutions) errors.push_back(pullback_errors(dimension, r));
  for (std::size_t n = 1; n < errors.size(); ++n) {
    const double order = std::log2(errors[n - 1].mean_relative / errors[n].mean_relative);
    const double max_order = std::log2(errors[n - 1].max_relative / errors[n].max_relative);
    std::printf(
        "[ measured ] %dD pull-back %d -> %d: observed order of the mean error %.2f (max: %.2f)\n",
        dimension, resolutions[n - 1], resolutions[n], order, max_order);
    EXPECT_GE(order, 0.8);
  }
  return errors;
}

}  // namespace rvor::test
