// Canvas::content_hash: what lets a propagator keep the canvas it derived stencils from (the
// OpenCL engine, the canvas on the device) only while the canvas is the same.
#include <string>

#include <gtest/gtest.h>

#include "rvor/canvas.h"
#include "rvor/error.h"
#include "support/box_canvas.h"
#include "support/error_of.h"

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

// On a 3D canvas, where every component is the metric's (a 2D canvas's z row is fixed: below).
TEST(CanvasContentHash, OneFloatOfOneSlotChangesIt) {
  const Canvas original = test::make_uniform_box_canvas(3, kLo, kHi, 16, Mat3::Identity());
  for (std::size_t slot : {std::size_t{0}, std::size_t{777}, original.slot_count() - 1})
    for (int component = 0; component < 6; ++component) {
      Canvas changed = original;
      changed.mutable_metric(slot)[component] += 0.5f;
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

// finalize() checks what the solvers index by without checking, and a 2D canvas's z row: a canvas
// changed by hand crashed the reference (a brick table naming a brick that is not there), read
// out of bounds, or left the engines disagreeing (a 2D canvas's m33 changed: 5.8% in the
// reference, nothing in the kernels).
TEST(CanvasConsistency, FinalizeRefusesCorruptedBricks) {
  const Canvas original = uniform_square(Mat3::Identity());
  const auto expect_refused = [](Canvas canvas, const std::string& fragment) {
    try {
      canvas.finalize();
      ADD_FAILURE() << "finalize() accepted a canvas with " << fragment;
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find(fragment), std::string::npos) << e.what();
    }
  };
  Canvas beyond = original;
  beyond.brick_table[0] = 999;
  expect_refused(beyond, "holds brick 999");
  Canvas negative = original;
  negative.brick_table[0] = -5;
  expect_refused(negative, "holds brick -5");
  Canvas short_table = original;
  short_table.brick_table.resize(2);
  expect_refused(short_table, "brick table of 2 cells");
  Canvas grid = original;
  grid.brick_grid_dims[0] = 100;
  expect_refused(grid, "brick grid do not match along axis 0");
  Canvas box = original;
  box.dims[0] = 1000;
  expect_refused(box, "brick grid do not match along axis 0");
  Canvas moved = original;
  moved.brick_origins[0].i += 8;
  expect_refused(moved, "its origin is voxel (8, 0, 0)");
  Canvas missing = original;
  missing.brick_table[0] = -1;
  expect_refused(missing, "1 of 64 bricks are missing");
  Canvas unplaced = original;
  unplaced.voxel_size = 0;
  expect_refused(unplaced, "voxel size must be positive");
  Canvas z_row = original;
  z_row.mutable_metric(5)[5] = 100.0f;
  expect_refused(z_row, "m13, m23, m33 must be 0, 0, 1");
  Canvas unchanged = original;
  EXPECT_NO_THROW(unchanged.finalize());
}

TEST(CanvasConsistency, AllocateRefusesAnEmptyIndexBox) {
  Canvas canvas;
  EXPECT_THROW(canvas.allocate(3, 0.1, Vec3::Zero(), {-8, 8, 8}, {}), Error);
}

// An index box whose brick table would pass 2^31 cells is refused: its size wrapped to 0 at 2^30
// voxels a side, and the first brick was written past the table.
TEST(CanvasConsistency, AllocateRefusesABrickTableThatWouldWrap) {
  Canvas canvas;
  const std::string message = test::error_of([&] {
    canvas.allocate(3, 0.1, Vec3::Zero(), {1 << 30, 1 << 30, 1 << 30}, {VoxelIndex{0, 0, 0}});
  });
  EXPECT_NE(message.find("is too large: its brick table would hold"), std::string::npos) << message;
}

// set_active and mutable_metric check their slot (set_active past the canvas wrote anywhere), and
// set_active refuses the tensors the builder refuses (a non-symmetric one kept its upper
// triangle; one of eigenvalue 1e-35 was solved).
TEST(CanvasConsistency, SetActiveChecksItsSlotAndItsTensor) {
  Canvas canvas;
  canvas.allocate(2, 0.5, Vec3::Zero(), {8, 8, 1}, {VoxelIndex{0, 0, 0}});
  const std::size_t past = canvas.slot_count() + 1000000;
  EXPECT_THROW(canvas.set_active(past, Mat3::Identity()), Error);
  EXPECT_THROW(canvas.mutable_metric(past), Error);
  Mat3 skew = Mat3::Identity();
  skew(0, 1) = 0.9;
  skew(1, 0) = -0.9;
  EXPECT_THROW(canvas.set_active(0, skew), Error);
  EXPECT_THROW(canvas.set_active(0, Vec3(1e-35, 1, 1).asDiagonal()), Error);
  EXPECT_NO_THROW(canvas.set_active(0, Vec3(2, 1, 1).asDiagonal()));
  EXPECT_THROW(Canvas::stored_tensor(Mat3::Identity(), 7), Error);
  // An activity flag of 2 was taken as active and counted twice.
  canvas.active[1] = 2;
  EXPECT_THROW(canvas.finalize(), Error);
  canvas.active[1] = 0;
  EXPECT_NO_THROW(canvas.finalize());
}

}  // namespace
}  // namespace rvor
