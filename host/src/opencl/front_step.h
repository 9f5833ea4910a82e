#pragma once
// Front stepping (docs/scheme.md, "Front stepping"): when a brick_lanes solve keeps evaluations
// above a rising threshold tentative, and by how much the threshold rises.
#include <cstddef>
#include <vector>

#include "rvor/canvas.h"
#include "rvor/metric.h"

namespace rvor::opencl {

// The step of a solve in voxel lengths, 0 for none. requested: OpenCLOptions::front_step (< 0:
// automatic). Automatic steps 3 voxel lengths where it was measured to pay: stencils with
// non-axis offsets somewhere (axis stencils only lost) and Voronoi cells at least 50 voxels
// across, as (active voxels per seed)^(1 / dimension); many smaller cells lost in 3D.
double front_step_voxels(double requested, int dimension, std::size_t active_voxels,
                         std::size_t seeds, bool axis_readers);

// A voxel length in distance units: the median over the seeds of the shortest axis step in the
// seed's metric, h sqrt(min_i G_ii). The seeds must lie in the canvas (seed_records checks them).
double voxel_length(const Canvas& canvas, const std::vector<Vec3>& seeds);

}  // namespace rvor::opencl
