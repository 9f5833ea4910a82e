#pragma once
// Statistics of a solved field, for report.json and the terminal summary.
#include <cstddef>

#include "rvor/canvas.h"
#include "rvor/propagation.h"

namespace rvor {

struct FieldSummary {
  std::size_t reached_voxels = 0;    // active voxels with a finite distance
  std::size_t unreached_voxels = 0;  // active voxels no seed reached
  // Of those, the ones in a face-connected piece of the canvas that a seed did reach: no stencil
  // leads from them to a reached voxel (stencils long against the metric's variation or the
  // canvas, as a strongly anisotropic shell at a coarse resolution, or a corner that a rotated
  // stencil reaches only from outside the canvas). The others lie in pieces without seeds.
  std::size_t unreached_beside_reached = 0;
  std::size_t non_empty_cells = 0;   // labels that own at least one voxel
  std::size_t empty_cells = 0;       // seeds that own no voxel (sharing one with another seed)
  std::size_t first_empty_cell = 0;  // the first such seed, when there is one
  std::size_t smallest_cell = 0;     // voxels in the smallest non-empty cell
  std::size_t largest_cell = 0;      // voxels in the largest cell
  double max_distance = 0.0;         // the farthest voxel from its seed (metric units)
  double mean_distance = 0.0;
};

FieldSummary summarize_field(const Canvas& canvas, const VoronoiField& field,
                             std::size_t seed_count);

}  // namespace rvor
