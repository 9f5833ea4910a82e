#pragma once
// Seeds in pairs a few voxels apart, where a voxel of one seed's initialisation block can be nearer
// to the other seed, whose block does not contain it (rvor/seed_blocks.h), and the check that
// every block voxel holds its nearest seed's exact distance under a uniform metric.
#include <vector>

#include "rvor/canvas.h"

namespace rvor::test {

// `pairs` random seeds (seeds.h random_seeds, `rng_seed`), each followed by a partner 3 to 5 voxels
// away towards the canvas centre (which must be the origin).
std::vector<Vec3> close_seed_pairs(const Canvas& canvas, int pairs, unsigned rng_seed);

// Expects, at every active voxel of every seed's (2r+1)^d block, the distance to the nearest seed
// under G (the canvas's uniform metric) within `relative` and a label of a seed at that distance.
void expect_exact_seed_blocks(const Canvas& canvas, const Mat3& G, const std::vector<Vec3>& seeds,
                              const std::vector<double>& distance,
                              const std::vector<int32_t>& label, double relative);

}  // namespace rvor::test
