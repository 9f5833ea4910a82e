// The issue-4 straight-dual checks through the whole pipeline in 3D: labels from the reference
// propagator (about 30 s a case on two cores), on the box and on the .off mesh domain, and the raw
// nerve at twice the default resolution. ctest -L heavy (scripts/test.sh --heavy).
#include <gtest/gtest.h>

#include "dual/uniform_case.h"

namespace rvor::test {
namespace {

TEST(StraightDualUniformHeavy, SolverLabels3D) {
  run_box_case({3, 96, Vec3(1.0, 3.0, 10.0), 21, true, 0.75});
  run_box_case({3, 96, Vec3(2.0, 1.0, 1.5), 22, true, 0.88});
}

TEST(StraightDualUniformHeavy, SolverLabelsOnOffMesh) {
  run_mesh_case({3, 96, Vec3(1.0, 3.0, 10.0), 31, true, 0.6});
}

// The raw nerve converges with the resolution (about linearly: its errors are configurations
// closer to cospherical than a voxel).
TEST(StraightDualUniformHeavy, RawNerveAtTwiceTheResolution) {
  run_box_case({3, 192, Vec3(1.0, 3.0, 10.0), 21, false, 0.9});
}

}  // namespace
}  // namespace rvor::test
