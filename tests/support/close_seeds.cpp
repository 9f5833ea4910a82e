#include "close_seeds.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "rvor/seed_blocks.h"
#include "rvor/seeds.h"

namespace rvor::test {

std::vector<Vec3> close_seed_pairs(const Canvas& canvas, int pairs, unsigned rng_seed) {
  std::vector<Vec3> seeds;
  for (const Vec3& first : random_seeds(canvas, static_cast<std::size_t>(pairs), rng_seed)) {
    seeds.push_back(first);
    Vec3 step = Vec3(3.3, 4.1, canvas.dimension == 3 ? 2.7 : 0) * canvas.voxel_size;
    for (int a = 0; a < 3; ++a) step[a] *= first[a] > 0 ? -1 : 1;
    seeds.push_back(first + step);
  }
  return seeds;
}

void expect_exact_seed_blocks(const Canvas& canvas, const Mat3& G, const std::vector<Vec3>& seeds,
                              const std::vector<double>& distance,
                              const std::vector<int32_t>& label, double relative) {
  const Mat3 F = metric_sqrt(G);
  std::size_t checked = 0, wrong = 0;
  for (const Vec3& seed : seeds)
    for_each_seed_block_voxel(
        canvas.voxel_containing(seed), canvas.dimension, [&](const VoxelIndex& v) {
          const int64_t slot = canvas.slot_of(v);
          if (slot < 0 || wrong > 0) return;  // the first failure only
          const Vec3 x = canvas.world_of(static_cast<std::size_t>(slot));
          double nearest = std::numeric_limits<double>::infinity();
          for (const Vec3& other : seeds) nearest = std::min(nearest, (F * (x - other)).norm());
          const double tolerance = relative * nearest;
          const bool exact = label[slot] >= 0 && std::abs(distance[slot] - nearest) <= tolerance &&
                             std::abs((F * (x - seeds[label[slot]])).norm() - nearest) <= tolerance;
          EXPECT_TRUE(exact) << "voxel " << slot << ": distance " << distance[slot] << ", label "
                             << label[slot] << ", nearest " << nearest;
          wrong += !exact;
          ++checked;
        });
  EXPECT_GT(checked, seeds.size());
}

}  // namespace rvor::test
