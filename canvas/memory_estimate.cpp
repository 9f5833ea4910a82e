#include "memory_estimate.h"

#include <cstdio>

#include "rvor/canvas_builder.h"
#include "rvor/error.h"

namespace rvor {

double estimated_canvas_bytes(double active_voxels, double brick_table_cells, bool uniform_metric) {
  return active_voxels * static_cast<double>(estimated_bytes_per_active_voxel(uniform_metric)) +
         brick_table_cells * sizeof(std::int32_t);
}

void check_memory_budget(double active_voxels, double brick_table_cells, bool uniform_metric,
                         std::uint64_t budget, std::uint64_t held_bytes) {
  budget = resolved_memory_budget(budget);
  const double needed = estimated_canvas_bytes(active_voxels, brick_table_cells, uniform_metric);
  const double held = static_cast<double>(held_bytes);
  if (needed + held <= static_cast<double>(budget)) return;
  char voxels[32];
  // Whole below ten million ("4096"), three digits above ("2.81e+14").
  std::snprintf(voxels, sizeof voxels, active_voxels < 1e7 ? "%.0f" : "%.3g", active_voxels);
  const std::string held_text =
      held_bytes != 0 ? ", with the metric field's " + format_bytes(held) + " already held" : "";
  throw Error("canvas of ~" + std::string(voxels) + " active voxels needs ~" +
              format_bytes(needed) + held_text + ", over the memory budget of " +
              format_bytes(static_cast<double>(budget)) + " (--memory-budget)");
}

}  // namespace rvor
