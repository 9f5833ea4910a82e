#include <algorithm>
#include <cmath>
#include <vector>

#include "rvor/error.h"
#include "rvor/field_summary.h"

namespace rvor {

FieldSummary summarize_field(const Canvas& canvas, const VoronoiField& field,
                             std::size_t seed_count) {
  require_field_for(canvas, field, "field summary");
  FieldSummary summary;
  std::vector<std::size_t> cell_sizes(seed_count, 0);
  double distance_sum = 0.0;
  for (std::size_t slot = 0; slot < canvas.slot_count(); ++slot) {
    if (!canvas.active[slot]) continue;
    const float d = field.distance[slot];
    const int label = field.label[slot];
    if (label >= 0 && static_cast<std::size_t>(label) >= seed_count)
      throw Error("field summary: voxel " + std::to_string(slot) + " has label " +
                  std::to_string(label) + ", but there are " + std::to_string(seed_count) +
                  " seeds");
    if (!std::isfinite(d) || label < 0) {
      ++summary.unreached_voxels;
      continue;
    }
    ++summary.reached_voxels;
    ++cell_sizes[label];
    distance_sum += d;
    summary.max_distance = std::max(summary.max_distance, static_cast<double>(d));
  }
  if (summary.reached_voxels > 0) summary.mean_distance = distance_sum / summary.reached_voxels;
  summary.smallest_cell = summary.reached_voxels;
  for (std::size_t seed = 0; seed < seed_count; ++seed) {
    const std::size_t size = cell_sizes[seed];
    if (size == 0) {
      if (summary.empty_cells++ == 0) summary.first_empty_cell = seed;
      continue;
    }
    ++summary.non_empty_cells;
    summary.smallest_cell = std::min(summary.smallest_cell, size);
    summary.largest_cell = std::max(summary.largest_cell, size);
  }
  if (summary.non_empty_cells == 0) summary.smallest_cell = 0;
  return summary;
}

}  // namespace rvor
