// Canvas::content_hash: what lets a propagator keep the canvas it derived stencils from (the
// OpenCL engine, the canvas on the device) only while the canvas is the same.
#include <gtest/gtest.h>

#include "rvor/canvas.h"
#include "support/box_canvas.h"

namespace rvor {
namespace {

const Vec3 kLo(-1, -1, -1), kHi(1, 1, 1);

Canvas uniform_square(const Mat3& G) {
  return test::make_uniform_box_canvas(2, kLo, kHi, 64, G);
}

TEST(CanvasContentHash, EqualCanvasesHashTheSame) {
  const Canvas a = uniform_square(Mat3::Identity()), b = uniform_square(Mat3::Identity());
  ASSERT_TRUE(a.content_hash().has_value());
  EXPECT_EQ(a.content_hash(), b.content_hash());
}

TEST(CanvasContentHash, OneFloatOfOneSlotChangesIt) {
  const Canvas original = uniform_square(Mat3::Identity());
  for (std::size_t slot : {std::size_t{0}, std::size_t{777}, original.slot_count() - 1})
    for (int component = 0; component < 6; ++component) {
      Canvas changed = original;
      changed.metric[6 * slot + component] += 0.5f;
      changed.finalize();
      EXPECT_NE(changed.content_hash(), original.content_hash())
          << "slot " << slot << ", component " << component;
    }
}

TEST(CanvasContentHash, ActivityAndGeometryChangeIt) {
  const Canvas original = uniform_square(Mat3::Identity());
  Canvas holed = original;
  holed.active[1234] = 0;
  holed.finalize();
  EXPECT_NE(holed.content_hash(), original.content_hash());
  Canvas shifted = original;
  shifted.origin.x() += shifted.voxel_size;
  shifted.finalize();
  EXPECT_NE(shifted.content_hash(), original.content_hash());
  Canvas finer = original;
  finer.voxel_size *= 0.5;
  finer.finalize();
  EXPECT_NE(finer.content_hash(), original.content_hash());
}

// A canvas being changed has no hash, so that no propagator takes it for one it has seen.
TEST(CanvasContentHash, NoneUntilFinalizeRuns) {
  Canvas canvas = uniform_square(Mat3::Identity());
  canvas.set_active(40, 2.0 * Mat3::Identity());
  EXPECT_FALSE(canvas.content_hash().has_value());
  canvas.finalize();
  EXPECT_TRUE(canvas.content_hash().has_value());
  canvas.allocate(2, 0.5, Vec3::Zero(), {8, 8, 1}, {VoxelIndex{0, 0, 0}});
  EXPECT_FALSE(canvas.content_hash().has_value());
}

}  // namespace
}  // namespace rvor
