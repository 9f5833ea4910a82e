// A non-uniform metric with exact geodesics (pull-back of the Euclidean metric by a smooth
// diffeomorphism): first-order convergence of the factored scheme.
#include "pullback_study.h"

namespace rvor::test {
namespace {

TEST(PullBackMetric, ConvergesAtFirstOrder3D) {
  const std::vector<ErrorStats> errors = pullback_study(3, {64, 128});
  EXPECT_LE(errors.back().max_relative, 0.02);
}

TEST(PullBackMetric, ConvergesAtFirstOrder2D) {
  const std::vector<ErrorStats> errors = pullback_study(2, {128, 256, 512});
  EXPECT_LE(errors.back().max_relative, 0.02);
}

}  // namespace
}  // namespace rvor::test
