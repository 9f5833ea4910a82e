// Several seeds: labels of the nearer seed, incremental insertion, independence of seed order.
#include <gtest/gtest.h>

#include <cstdio>
#include <string>

#include "rvor/seeds.h"
#include "solver_fixtures.h"

namespace rvor::test {
namespace {

Mat3 rotated_metric(int dimension, double anisotropy) {
  return uniform_anisotropic_metric(dimension == 3 ? Vec3(1, 1, 1) : Vec3(1, 1, 0), anisotropy);
}

// Longest voxel diagonal measured in the metric.
double diagonal_length(const Canvas& canvas, const Mat3& F) {
  double longest = 0;
  for (int sy : {-1, 1})
    for (int sz : {-1, 1}) {
      const Vec3 diagonal(1, sy, canvas.dimension == 3 ? sz : 0);
      longest = std::max(longest, (F * diagonal).norm() * canvas.voxel_size);
    }
  return longest;
}

// True when a voxel within `radius` (index units, box) carries another label in `field`: the
// voxel is next to a Voronoi boundary, where ties and label switches happen.
bool near_label_boundary(const Canvas& canvas, const detail::ExactField& field, std::size_t slot,
                         int radius) {
  const VoxelIndex x = canvas.voxel_of(slot);
  const int rz = canvas.dimension == 3 ? radius : 0;
  for (int dk = -rz; dk <= rz; ++dk)
    for (int dj = -radius; dj <= radius; ++dj)
      for (int di = -radius; di <= radius; ++di) {
        const int64_t other = canvas.slot_of(x.i + di, x.j + dj, x.k + dk);
        if (other >= 0 && field.label[other] != field.label[slot]) return true;
      }
  return false;
}

struct FieldComparison {
  std::size_t label_mismatches = 0;
  std::size_t distance_mismatches = 0;  // relative difference above the tolerance
  std::size_t mismatches_away_from_boundaries = 0;
  double max_relative_difference = 0;
  double max_relative_difference_away = 0;
};

// `relabel` maps labels of `b` to labels of `a`.
FieldComparison compare_fields(const Canvas& canvas, const detail::ExactField& a,
                               const detail::ExactField& b, double tolerance,
                               const std::function<int32_t(int32_t)>& relabel,
                               int boundary_radius) {
  FieldComparison result;
  for (std::size_t slot = 0; slot < canvas.slot_count(); ++slot) {
    if (!canvas.active[slot]) continue;
    const double difference =
        std::abs(a.distance[slot] - b.distance[slot]) / std::max(a.distance[slot], 1e-300);
    const bool label_differs = a.label[slot] != relabel(b.label[slot]);
    const bool distance_differs = difference > tolerance;
    result.label_mismatches += label_differs;
    result.distance_mismatches += distance_differs;
    result.max_relative_difference = std::max(result.max_relative_difference, difference);
    if (near_label_boundary(canvas, a, slot, boundary_radius)) continue;
    result.max_relative_difference_away = std::max(result.max_relative_difference_away, difference);
    result.mismatches_away_from_boundaries += label_differs || distance_differs;
  }
  return result;
}

void print(const std::string& what, const FieldComparison& c, std::size_t voxels) {
  std::printf(
      "[ measured ] %s: %zu voxels, %zu label / %zu distance (>1e-9 rel.) mismatches, max rel. "
      "difference %.2e; away from label boundaries: %zu mismatches, max rel. difference %.2e\n",
      what.c_str(), voxels, c.label_mismatches, c.distance_mismatches, c.max_relative_difference,
      c.mismatches_away_from_boundaries, c.max_relative_difference_away);
}

class SeedsByDimension : public ::testing::TestWithParam<int> {};

TEST_P(SeedsByDimension, TwoSeedsLabelTheNearerSeed) {
  const int dimension = GetParam();
  const Mat3 G = rotated_metric(dimension, 10);
  const Mat3 F = metric_sqrt(G);
  const Canvas canvas = make_uniform_box_canvas(dimension, Vec3(-1, -1, -1), Vec3(1, 1, 1),
                                                dimension == 3 ? 64 : 256, G);
  const std::vector<Vec3> seeds = {Vec3(-0.3, 0.1, dimension == 3 ? 0.2 : 0),
                                   Vec3(0.35, -0.2, dimension == 3 ? -0.1 : 0)};
  const detail::ExactField field = solve_exact(canvas, seeds);
  const double margin = 2 * diagonal_length(canvas, F);
  std::size_t checked = 0, wrong = 0;
  for (std::size_t slot = 0; slot < canvas.slot_count(); ++slot) {
    if (!canvas.active[slot]) continue;
    const Vec3 x = canvas.world_of(slot);
    const double d0 = (F * (x - seeds[0])).norm(), d1 = (F * (x - seeds[1])).norm();
    if (std::abs(d0 - d1) <= margin) continue;
    ++checked;
    wrong += field.label[slot] != (d0 < d1 ? 0 : 1);
  }
  std::printf("[ measured ] %dD two seeds: %zu voxels checked, %zu wrong labels\n", dimension,
              checked, wrong);
  EXPECT_GT(checked, canvas.active_voxel_count / 2);
  EXPECT_EQ(wrong, 0u);
}

TEST_P(SeedsByDimension, InsertingOneByOneEqualsSolvingAll) {
  const int dimension = GetParam();
  const Canvas canvas =
      make_uniform_box_canvas(dimension, Vec3(-1, -1, -1), Vec3(1, 1, 1), dimension == 3 ? 64 : 256,
                              rotated_metric(dimension, 4));
  const std::vector<Vec3> seeds = random_seeds(canvas, 100, 42);
  detail::ReferenceSolver solver(canvas);
  detail::ExactField all;
  const PropagationStats all_stats = solver.solve(canvas, seeds, all);

  detail::ExactField incremental;
  double insert_seconds = 0;
  solver.solve(canvas, {seeds[0]}, incremental);
  for (std::size_t n = 1; n < seeds.size(); ++n) {
    const std::vector<Vec3> prefix(seeds.begin(), seeds.begin() + n + 1);
    insert_seconds += solver.insert(canvas, prefix, n, incremental).seconds;
  }
  const FieldComparison c = compare_fields(
      canvas, all, incremental, 1e-9, [](int32_t l) { return l; }, 2);
  print(std::to_string(dimension) + "D 100 seeds, inserted one by one vs all at once", c,
        canvas.active_voxel_count);
  std::printf("[ measured ] solve all %.3f s, 99 inserts %.3f s\n", all_stats.seconds,
              insert_seconds);
  EXPECT_EQ(c.mismatches_away_from_boundaries, 0u);
  EXPECT_LE(c.label_mismatches, canvas.active_voxel_count / 1000);
}

TEST_P(SeedsByDimension, SeedOrderDoesNotMatter) {
  const int dimension = GetParam();
  const Canvas canvas =
      make_uniform_box_canvas(dimension, Vec3(-1, -1, -1), Vec3(1, 1, 1), dimension == 3 ? 64 : 256,
                              rotated_metric(dimension, 4));
  const std::vector<Vec3> seeds = random_seeds(canvas, 100, 7);
  const std::vector<Vec3> reversed(seeds.rbegin(), seeds.rend());
  const detail::ExactField forward = solve_exact(canvas, seeds);
  const detail::ExactField backward = solve_exact(canvas, reversed);
  const int32_t last = static_cast<int32_t>(seeds.size()) - 1;
  const FieldComparison c = compare_fields(
      canvas, forward, backward, 1e-9, [last](int32_t l) { return l < 0 ? l : last - l; }, 2);
  print(std::to_string(dimension) + "D 100 seeds, reversed order", c, canvas.active_voxel_count);
  EXPECT_EQ(c.mismatches_away_from_boundaries, 0u);
  EXPECT_LE(c.label_mismatches, canvas.active_voxel_count / 1000);
}

// The public interface: a chain of insert() calls on float fields keeps the double state.
TEST_P(SeedsByDimension, PublicInsertMatchesPublicSolve) {
  const int dimension = GetParam();
  const Canvas canvas =
      make_uniform_box_canvas(dimension, Vec3(-1, -1, -1), Vec3(1, 1, 1), dimension == 3 ? 32 : 128,
                              rotated_metric(dimension, 4));
  const std::vector<Vec3> seeds = random_seeds(canvas, 20, 3);
  auto propagator = make_reference_propagator();
  VoronoiField all, incremental;
  propagator->solve(canvas, seeds, all);
  propagator->solve(canvas, {seeds[0]}, incremental);
  for (std::size_t n = 1; n < seeds.size(); ++n)
    propagator->insert(canvas, std::vector<Vec3>(seeds.begin(), seeds.begin() + n + 1), n,
                       incremental);
  std::size_t differing = 0;
  for (std::size_t slot = 0; slot < canvas.slot_count(); ++slot)
    differing +=
        all.label[slot] != incremental.label[slot] ||
        std::abs(all.distance[slot] - incremental.distance[slot]) > 1e-6f * all.distance[slot];
  std::printf("[ measured ] %dD public insert vs solve, 20 seeds: %zu of %zu voxels differ\n",
              dimension, differing, canvas.active_voxel_count);
  EXPECT_LE(differing, canvas.active_voxel_count / 100);
}

INSTANTIATE_TEST_SUITE_P(Reference, SeedsByDimension, ::testing::Values(2, 3),
                         [](const ::testing::TestParamInfo<int>& info) {
                           return "D" + std::to_string(info.param);
                         });

}  // namespace
}  // namespace rvor::test
