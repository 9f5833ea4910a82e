#pragma once
// Dense box/rectangle canvases built without OpenVDB, for solver tests and benchmarks: the same
// packed layout and voxel placement (cell-centred, `resolution` voxels along the longest side) as
// the OpenVDB builder gives for a box domain.
#include <cstdint>
#include <functional>
#include <vector>

#include "rvor/canvas.h"
#include "rvor/propagation.h"

namespace rvor::test {

using MetricFunction = std::function<Mat3(const Vec3&)>;

// lo/hi: the box (z ignored when dimension == 2).
Canvas make_box_canvas(int dimension, const Vec3& lo, const Vec3& hi, int resolution,
                       const MetricFunction& metric);
Canvas make_uniform_box_canvas(int dimension, const Vec3& lo, const Vec3& hi, int resolution,
                               const Mat3& G);
// A field of the canvas's shape holding `distance` and `label` at every slot.
VoronoiField constant_field(const Canvas& canvas, float distance, int label);
// The isotropic box [-1,1]^d at `resolution` voxels a side less a wall x in [-0.2, 0.03), with a
// door at y < -0.5: a domain that is not convex, whose wall cuts through bricks and quarters.
Canvas box_with_a_wall(int dimension, int resolution);
// The isotropic 64^2 box [-1,1]^2 less the voxel columns i in [28, 36): two bands that share no
// face, x < -0.125 and x > 0.125, marked convex_domain as if a builder had said so.
Canvas two_bands_claimed_convex();
// Its seeds, both in the left band.
std::vector<Vec3> left_band_seeds();
// The isotropic box [-1,1]^d at 64^2 or 32^3 voxels less the voxel layer 20 along `axis`, which
// cuts the quarters of voxels 20 to 23 (the upper half of the bricks of voxels 16 to 23): two
// pieces, the lower one holding lower_piece_seeds.
Canvas split_inside_a_quarter(int dimension, int axis);
std::vector<Vec3> lower_piece_seeds(int dimension, int axis);

// Makes every slot of the canvas's middle brick 25 times slower but those a propagator samples to
// recognise a canvas (every slot_count/4096-th, host/src/canvas_identity.h), then finalizes it: a
// change in place that only the content hash shows.
void slow_down_a_brick_between_sampled_slots(Canvas& canvas);

// How many voxels of each piece `field` labels, and how many each piece has.
struct BandCounts {
  std::size_t left_labelled = 0, left_voxels = 0, right_labelled = 0, right_voxels = 0;
};
// The pieces of voxel index below `first_right` along `axis` (left) and the others (right).
BandCounts count_piece_labels(const Canvas& canvas, int axis, int first_right,
                              const std::vector<int32_t>& labels);
// Of two_bands_claimed_convex.
BandCounts count_band_labels(const Canvas& canvas, const std::vector<int32_t>& labels);
// Every voxel of the left piece labelled, none of the right one, which has voxels (gtest checks).
void expect_only_left_labelled(const BandCounts& counts);

}  // namespace rvor::test
