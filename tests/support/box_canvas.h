#pragma once
// Dense box/rectangle canvases built without OpenVDB, for solver tests and benchmarks: the same
// packed layout and voxel placement (cell-centred, `resolution` voxels along the longest side) as
// the OpenVDB builder gives for a box domain.
#include <functional>

#include "rvor/canvas.h"

namespace rvor::test {

using MetricFunction = std::function<Mat3(const Vec3&)>;

// lo/hi: the box (z ignored when dimension == 2).
Canvas make_box_canvas(int dimension, const Vec3& lo, const Vec3& hi, int resolution,
                       const MetricFunction& metric);
Canvas make_uniform_box_canvas(int dimension, const Vec3& lo, const Vec3& hi, int resolution,
                               const Mat3& G);

}  // namespace rvor::test
