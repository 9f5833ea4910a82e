#pragma once
// The up-front memory check of the canvas builder (private to rvor_canvas).
#include <cstdint>
#include <string>

#include "rvor/memory_budget.h"

namespace rvor {

// Bytes a canvas of `active_voxels` voxels (plus a brick table of `brick_table_cells` entries)
// and a propagation over it need, its tensors stored once or per slot (`uniform_metric`).
double estimated_canvas_bytes(double active_voxels, double brick_table_cells, bool uniform_metric);

// Throws rvor::Error "canvas of ~N active voxels needs ~X, over the memory budget of Y
// (--memory-budget)" when the estimate exceeds `budget` (0 = default_memory_budget()); with
// `held_bytes` (memory already taken, the metric field's grids) the estimate and the message
// count them too.
void check_memory_budget(double active_voxels, double brick_table_cells, bool uniform_metric,
                         std::uint64_t budget, std::uint64_t held_bytes = 0);

}  // namespace rvor
