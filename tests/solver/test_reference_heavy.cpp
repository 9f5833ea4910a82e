// The 256^3 convergence study (label `heavy`: minutes and a few GB of memory).
#include "pullback_study.h"

namespace rvor::test {
namespace {

TEST(PullBackMetricHeavy, ConvergesAtFirstOrderUpTo256) {
  const std::vector<ErrorStats> errors = pullback_study(3, {64, 128, 256});
  EXPECT_LE(errors[1].max_relative, 0.02);
  EXPECT_LE(errors[2].max_relative, errors[1].max_relative);
}

TEST(PullBackMetricHeavy, ConvergesAtFirstOrderUpTo2048In2D) {
  const std::vector<ErrorStats> errors = pullback_study(2, {256, 512, 1024, 2048});
  EXPECT_LE(errors.back().max_relative, 0.01);
}

}  // namespace
}  // namespace rvor::test
