#pragma once
// How anisotropic a canvas's metric is, and how far its Selling stencils reach, sampled at evenly
// spread active voxels: what the accuracy of the scheme depends on beyond the resolution.
#include "rvor/canvas.h"

namespace rvor {

struct MetricReach {
  double max_anisotropy = 1.0;  // sqrt(lambda_max / lambda_min) of the metric (its xy block in 2D)
  int longest_offset = 0;       // the largest |component| of a stencil offset, in voxels
};

// At most about 20 000 samples: a few milliseconds at any size (`perf record` of `rvor voronoi
// --domain box:1,1,1,11,11,11 --metric radial_shock_3d --resolution 256 --random-seeds 1000`:
// under 0.01% of the run's samples).
MetricReach sampled_metric_reach(const Canvas& canvas);

// The anisotropy up to which the tests check that every engine settles and agrees at any angle
// (README, "Strong anisotropy"); along a grid axis (unit offsets) any anisotropy is exact.
constexpr double kValidatedAnisotropy = 100.0;

// Whether results on this canvas lie outside what the tests validate: anisotropy beyond
// kValidatedAnisotropy with stencils longer than one voxel.
inline bool beyond_validated_anisotropy(const MetricReach& reach) {
  return reach.max_anisotropy > kValidatedAnisotropy && reach.longest_offset > 1;
}

}  // namespace rvor
