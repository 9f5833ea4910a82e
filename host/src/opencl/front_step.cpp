#include "front_step.h"

#include <algorithm>
#include <cmath>
#include <cstdint>

namespace rvor::opencl {

namespace {
constexpr double kAutomaticStep = 3.0;         // voxel lengths
constexpr double kSmallestSteppedCell = 50.0;  // voxels across
}  // namespace

double front_step_voxels(double requested, int dimension, std::size_t active_voxels,
                         std::size_t seeds, bool axis_readers) {
  if (requested >= 0.0) return requested;
  if (axis_readers || seeds == 0) return 0.0;
  const double voxels_per_seed = static_cast<double>(active_voxels) / static_cast<double>(seeds);
  const double cell = std::pow(voxels_per_seed, 1.0 / dimension);
  return cell >= kSmallestSteppedCell ? kAutomaticStep : 0.0;
}

double voxel_length(const Canvas& canvas, const std::vector<Vec3>& seeds) {
  std::vector<double> lengths(seeds.size());
  for (std::size_t s = 0; s < seeds.size(); ++s) {
    const std::int64_t slot = canvas.slot_of(canvas.voxel_containing(seeds[s]));
    const float* g = canvas.metric_of(static_cast<std::size_t>(slot));
    double shortest = std::min(g[0], g[2]);
    if (canvas.dimension == 3) shortest = std::min<double>(shortest, g[5]);
    lengths[s] = std::sqrt(shortest) * canvas.voxel_size;
  }
  const auto middle = lengths.begin() + static_cast<std::ptrdiff_t>(lengths.size() / 2);
  std::nth_element(lengths.begin(), middle, lengths.end());
  return *middle;
}

}  // namespace rvor::opencl
