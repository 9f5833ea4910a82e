// The curved dual with local fields on larger cases (ctest -L heavy: about 3 minutes on 2 cores):
// 500 seeds at 96^3 and 200 seeds at 256^2 in uniform anisotropic metrics. Every edge (Gabriel or
// not) must follow its straight segment within 2 voxels and measure |F (a - b)| within 2%, every
// face vertex lie within 2 voxels of its flat triangle; the run time of the local fields is
// printed.
#include <gtest/gtest.h>

#include "dual/curved_case.h"

namespace rvor {
namespace {

TEST(CurvedDualHeavy, Uniform3D500SeedsAt96) {
  const test::CurvedMeasures m = test::run_case({3, 96, 500, 61});
  EXPECT_EQ(m.unreached, 0u);
  EXPECT_EQ(m.unreached_faces, 0u);
}

TEST(CurvedDualHeavy, Uniform2D200SeedsAt256) {
  const test::CurvedMeasures m = test::run_case({2, 256, 200, 62});
  EXPECT_EQ(m.unreached, 0u);
  EXPECT_EQ(m.unreached_faces, 0u);
}

}  // namespace
}  // namespace rvor
