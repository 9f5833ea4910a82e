// When a solve steps its front (host/src/opencl/front_step.h): the automatic rule and the voxel
// length the step is measured in. No OpenCL device needed.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "front_step.h"
#include "support/box_canvas.h"

namespace rvor {
namespace {

using opencl::front_step_voxels;

TEST(FrontStep, AnExplicitStepIsTakenAsGiven) {
  EXPECT_EQ(front_step_voxels(0.0, 2, 1 << 20, 1, false), 0.0);
  EXPECT_EQ(front_step_voxels(5.0, 3, 1000, 1000, true), 5.0);
}

TEST(FrontStep, AutomaticStepsLargeCellsOfNonAxisStencils) {
  // 1024^2 with 10 seeds: cells ~324 voxels across; 256^3 with 1000 seeds: ~26.
  EXPECT_EQ(front_step_voxels(-1.0, 2, 1024 * 1024, 10, false), 3.0);
  EXPECT_EQ(front_step_voxels(-1.0, 3, 128 * 128 * 128, 10, false), 3.0);
  EXPECT_EQ(front_step_voxels(-1.0, 3, 256 * 256 * 256, 1000, false), 0.0);
  EXPECT_EQ(front_step_voxels(-1.0, 2, 1024 * 1024, 1000, false), 0.0);
}

TEST(FrontStep, AutomaticNeverStepsAxisStencils) {
  EXPECT_EQ(front_step_voxels(-1.0, 2, 1024 * 1024, 1, true), 0.0);
  EXPECT_EQ(front_step_voxels(-1.0, 3, 256 * 256 * 256, 1, true), 0.0);
}

TEST(FrontStep, VoxelLengthIsTheShortestAxisStepOfTheSeedsMetric) {
  // G = diag(4, 9, 16): the shortest axis step is h sqrt(4) = 2h.
  const Canvas canvas = test::make_box_canvas(3, Vec3(0, 0, 0), Vec3(1, 1, 1), 16, [](const Vec3&) {
    Mat3 g = Mat3::Zero();
    g.diagonal() = Vec3(4, 9, 16);
    return g;
  });
  const double length = opencl::voxel_length(canvas, {Vec3(0.5, 0.5, 0.5), Vec3(0.2, 0.3, 0.4)});
  EXPECT_NEAR(length, 2.0 * canvas.voxel_size, 1e-12);
}

}  // namespace
}  // namespace rvor
