#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include "rvor/error.h"
#include "rvor/field_summary.h"

namespace rvor {

namespace {

bool reached(const VoronoiField& field, std::size_t slot) {
  return std::isfinite(field.distance[slot]) && field.label[slot] >= 0;
}

// The unreached active voxels connected through unreached ones, face to face, to a reached voxel.
std::size_t unreached_beside_reached(const Canvas& canvas, const VoronoiField& field) {
  std::vector<std::uint8_t> found(canvas.slot_count(), 0);
  std::vector<std::size_t> to_visit;
  const auto find_unreached_neighbours = [&](std::size_t slot) {
    const VoxelIndex v = canvas.voxel_of(slot);
    for (int axis = 0; axis < canvas.dimension; ++axis)
      for (const int step : {-1, 1}) {
        VoxelIndex n = v;
        (axis == 0 ? n.i : axis == 1 ? n.j : n.k) += step;
        const std::int64_t next = canvas.slot_of(n);  // -1 outside the canvas or inactive
        if (next < 0 || reached(field, static_cast<std::size_t>(next)) || found[next]) continue;
        found[next] = 1;
        to_visit.push_back(static_cast<std::size_t>(next));
      }
  };
  std::size_t count = 0;
  for (std::size_t slot = 0; slot < canvas.slot_count(); ++slot) {
    if (!canvas.active[slot] || !reached(field, slot)) continue;
    find_unreached_neighbours(slot);
    while (!to_visit.empty()) {
      const std::size_t next = to_visit.back();
      to_visit.pop_back();
      ++count;
      find_unreached_neighbours(next);
    }
  }
  return count;
}

}  // namespace

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
    if (!reached(field, slot)) {
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
  if (summary.unreached_voxels > 0 && summary.reached_voxels > 0)
    summary.unreached_beside_reached = unreached_beside_reached(canvas, field);
  return summary;
}

}  // namespace rvor
