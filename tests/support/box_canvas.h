#pragma once
// Dense box/rectangle canvases built without OpenVDB, for solver tests and benchmarks: the same
// packed layout and voxel placement (cell-centred, `resolution` voxels along the longest side) as
// the OpenVDB builder gives for a box domain.
#include <cstdint>
#include <functional>
#include <vector>

#include "rvor/canvas.h"

namespace rvor::test {

using MetricFunction = std::function<Mat3(const Vec3&)>;

// lo/hi: the box (z ignored when dimension == 2).
Canvas make_box_canvas(int dimension, const Vec3& lo, const Vec3& hi, int resolution,
                       const MetricFunction& metric);
Canvas make_uniform_box_canvas(int dimension, const Vec3& lo, const Vec3& hi, int resolution,
                               const Mat3& G);
// The isotropic box [-1,1]^d at `resolution` voxels a side less a wall x in [-0.25, 0), with a
// door at y < -0.5: a domain that is not convex.
Canvas box_with_a_wall(int dimension, int resolution);
// The isotropic 64^2 box [-1,1]^2 less the voxel columns i in [28, 36): two bands that share no
// face, x < -0.125 and x > 0.125, marked convex_domain as if a builder had said so.
Canvas two_bands_claimed_convex();
// Its seeds, both in the left band.
std::vector<Vec3> left_band_seeds();
// How many voxels of each band `field` labels, and how many each band has.
struct BandCounts {
  std::size_t left_labelled = 0, left_voxels = 0, right_labelled = 0, right_voxels = 0;
};
BandCounts count_band_labels(const Canvas& canvas, const std::vector<int32_t>& labels);

}  // namespace rvor::test
