// The straight dual against CGAL's Delaunay triangulation of F * seeds for uniform anisotropic
// metrics (issue 4), at sizes the default test run affords: 2D with the reference propagator's
// labels, 3D (box and a closed .off mesh) with the exact labels of the metric. The pipeline with
// the propagator in 3D runs under the `heavy` label (test_dual_uniform_heavy.cpp).
#include <gtest/gtest.h>

#include "dual/uniform_case.h"

namespace rvor::test {
namespace {

// 2D: anisotropy 10 and 2.7, labels from the reference propagator.
TEST(StraightDualUniform, MatchesDelaunayOfMappedSeeds2D) {
  run_box_case({2, 512, Vec3(1.0, 10.0, 1.0), 11, true, 0.96});
  run_box_case({2, 384, Vec3(4.0, 1.5, 1.0), 12, true, 0.96});
}

// 3D at 96^3: exact labels of the uniform metric (the reference propagator takes ~30 s a case
// here; the pipeline with it runs under the `heavy` label).
TEST(StraightDualUniform, MatchesDelaunayOfMappedSeeds3D) {
  run_box_case({3, 96, Vec3(1.0, 3.0, 10.0), 21, false, 0.8});
  run_box_case({3, 96, Vec3(2.0, 1.0, 1.5), 22, false, 0.9});
}

TEST(StraightDualUniform, MatchesDelaunayOfMappedSeedsOnOffMesh) {
  run_mesh_case({3, 96, Vec3(1.0, 3.0, 10.0), 31, false, 0.65});
}

}  // namespace
}  // namespace rvor::test
