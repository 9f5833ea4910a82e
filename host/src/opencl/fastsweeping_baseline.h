#pragma once
// The isotropic speed and accuracy baseline of rvor bench (internal): OpenVDB's
// tools/FastSweeping on the canvas's active voxels, with the nearest seed's label carried as an
// int extension field. OpenVDB stays out of this header (it is slow to compile).
#include <cstddef>
#include <vector>

#include "rvor/canvas.h"
#include "rvor/propagation.h"

namespace rvor::baseline {

struct FastSweepingRun {
  VoronoiField field;          // per canvas slot: Euclidean distance (world units) and label
  double init_seconds = 0.0;   // FastSweeping::initExt: boundary values and the sweep mask
  double sweep_seconds = 0.0;  // FastSweeping::sweep: the part compared with the engines
  std::size_t swept_voxels = 0;
};

// Seeds become small spheres (radius one voxel) of a signed distance grid with the canvas's
// active topology and transform; FastSweeping extends it (and the labels) to every active voxel
// and the radius is added back. Distances are isotropic whatever the canvas's metric.
FastSweepingRun fast_sweeping_voronoi(const Canvas& canvas, const std::vector<Vec3>& seeds);

}  // namespace rvor::baseline
