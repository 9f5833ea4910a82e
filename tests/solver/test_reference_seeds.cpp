// Several seeds: labels of the nearer seed, incremental insertion, independence of seed order.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <limits>
#include <string>

#include "rvor/error.h"
#include "rvor/propagation.h"
#include "rvor/seeds.h"
#include "solver_fixtures.h"
#include "support/bad_fields.h"
#include "support/close_seeds.h"

namespace rvor::test {
namespace {

Mat3 rotated_metric(int dimension, double anisotropy) {
  return uniform_anisotropic_metric(dimension == 3 ? Vec3(1, 1, 1) : Vec3(1, 1, 0), anisotropy);
}

// The box [-1,1]^d at `resolution` under the uniform metric of anisotropy 4 along its diagonal.
Canvas rotated_box(int dimension, int resolution) {
  return make_uniform_box_canvas(dimension, Vec3(-1, -1, -1), Vec3(1, 1, 1), resolution,
                                 rotated_metric(dimension, 4));
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
                         int radius);

// Chebyshev distance (voxels) from a voxel to the nearest voxel of another label, capped.
int label_boundary_distance(const Canvas& canvas, const detail::ExactField& field, std::size_t slot,
                            int cap) {
  for (int r = 1; r < cap; ++r)
    if (near_label_boundary(canvas, field, slot, r)) return r;
  return cap;
}

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

// Differences between two fields, by Chebyshev distance (voxels) from the voxel to the nearest
// voxel of another label in the first field: bucket 0 = adjacent (distance 1), ..., 3 = 4 or more.
struct FieldComparison {
  static constexpr int kBuckets = 4;
  std::size_t label_mismatches[kBuckets] = {};
  std::size_t distance_mismatches[kBuckets] = {};  // relative difference above the tolerance
  double max_relative_difference[kBuckets] = {};
  double mean_relative_difference = 0;  // over all active voxels

  std::size_t label_mismatches_beyond(int bucket) const {
    std::size_t n = 0;
    for (int b = bucket; b < kBuckets; ++b) n += label_mismatches[b];
    return n;
  }
  double max_difference_beyond(int bucket) const {
    double m = 0;
    for (int b = bucket; b < kBuckets; ++b) m = std::max(m, max_relative_difference[b]);
    return m;
  }
};

// `relabel` maps labels of `b` to labels of `a`.
FieldComparison compare_fields(const Canvas& canvas, const detail::ExactField& a,
                               const detail::ExactField& b, double tolerance,
                               const std::function<int32_t(int32_t)>& relabel) {
  FieldComparison result;
  double sum = 0;
  for (std::size_t slot = 0; slot < canvas.slot_count(); ++slot) {
    if (!canvas.active[slot]) continue;
    const double difference =
        std::abs(a.distance[slot] - b.distance[slot]) / std::max(a.distance[slot], 1e-300);
    sum += difference;
    const bool label_differs = a.label[slot] != relabel(b.label[slot]);
    if (!label_differs && difference <= tolerance) continue;
    const int bucket = label_boundary_distance(canvas, a, slot, FieldComparison::kBuckets + 1) - 1;
    result.label_mismatches[bucket] += label_differs;
    result.distance_mismatches[bucket] += difference > tolerance;
    result.max_relative_difference[bucket] =
        std::max(result.max_relative_difference[bucket], difference);
  }
  result.mean_relative_difference = sum / static_cast<double>(canvas.active_voxel_count);
  return result;
}

void print(const std::string& what, const FieldComparison& c, std::size_t voxels) {
  std::printf(
      "[ measured ] %s (%zu voxels): mean relative difference %.2e; by distance to the nearest "
      "label boundary:\n",
      what.c_str(), voxels, c.mean_relative_difference);
  for (int b = 0; b < FieldComparison::kBuckets; ++b)
    std::printf(
        "[ measured ]   %s%d voxel(s): %zu label mismatches, %zu distances differing by more "
        "than 1e-9 relative, max relative difference %.2e\n",
        b + 1 == FieldComparison::kBuckets ? ">= " : "", b + 1, c.label_mismatches[b],
        c.distance_mismatches[b], c.max_relative_difference[b]);
}

class SeedsByDimension : public ::testing::TestWithParam<int> {};

// Drawn seeds lie in distinct voxels, sparse (redrawn repeats) or dense (a shuffle), up to every
// voxel of the canvas: two in one voxel would leave one an empty cell.
TEST_P(SeedsByDimension, RandomSeedsLieInDistinctVoxels) {
  const int dimension = GetParam();
  const Canvas canvas = make_uniform_box_canvas(dimension, Vec3(-1, -1, -1), Vec3(1, 1, 1),
                                                dimension == 3 ? 8 : 16, Mat3::Identity());
  for (const std::size_t count :
       {std::size_t{40}, canvas.active_voxel_count / 2 + 1, canvas.active_voxel_count}) {
    std::vector<int64_t> slots;
    for (const Vec3& seed : random_seeds(canvas, count, 3))
      slots.push_back(canvas.slot_of(canvas.voxel_containing(seed)));
    std::sort(slots.begin(), slots.end());
    EXPECT_EQ(std::unique(slots.begin(), slots.end()), slots.end()) << count << " seeds";
    EXPECT_GE(slots.front(), 0) << count << " seeds";
  }
}

TEST_P(SeedsByDimension, TwoSeedsLabelTheNearerSeed) {
  const int dimension = GetParam();
  const Mat3 G = rotated_metric(dimension, 10);
  const Mat3 F = metric_sqrt(G);
  const Canvas canvas = make_uniform_box_canvas(dimension, Vec3(-1, -1, -1), Vec3(1, 1, 1),
                                                dimension == 3 ? 64 : 256, G);
  // Seeds apart along the strong axis, so that many voxels are clearly nearer to one of them.
  const std::vector<Vec3> seeds = {Vec3(-0.3, -0.25, dimension == 3 ? -0.3 : 0),
                                   Vec3(0.3, 0.35, dimension == 3 ? 0.25 : 0)};
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
  const Canvas canvas = rotated_box(dimension, dimension == 3 ? 64 : 256);
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
  const FieldComparison c =
      compare_fields(canvas, all, incremental, 1e-9, [](int32_t l) { return l; });
  print(std::to_string(dimension) + "D 100 seeds, inserted one by one vs all at once", c,
        canvas.active_voxel_count);
  std::printf("[ measured ] solve all %.3f s (%llu pops, %llu local solves), 99 inserts %.3f s\n",
              all_stats.seconds, static_cast<unsigned long long>(all_stats.iterations),
              static_cast<unsigned long long>(all_stats.voxel_updates), insert_seconds);
  // Every update recomputes u = T(u) (docs/scheme.md), so insertion reaches the same fixed point
  // as a solve from scratch: the same labels everywhere, the same distances up to rounding.
  EXPECT_EQ(c.label_mismatches_beyond(0), 0u);
  EXPECT_LE(c.max_difference_beyond(0), 1e-9);
}

TEST_P(SeedsByDimension, SeedOrderDoesNotMatter) {
  const int dimension = GetParam();
  const Canvas canvas = rotated_box(dimension, dimension == 3 ? 64 : 256);
  const std::vector<Vec3> seeds = random_seeds(canvas, 100, 7);
  const std::vector<Vec3> reversed(seeds.rbegin(), seeds.rend());
  const detail::ExactField forward = solve_exact(canvas, seeds);
  const detail::ExactField backward = solve_exact(canvas, reversed);
  const int32_t last = static_cast<int32_t>(seeds.size()) - 1;
  const FieldComparison c = compare_fields(canvas, forward, backward, 1e-9,
                                           [last](int32_t l) { return l < 0 ? l : last - l; });
  print(std::to_string(dimension) + "D 100 seeds, reversed order", c, canvas.active_voxel_count);
  EXPECT_EQ(c.label_mismatches_beyond(1), 0u);
  EXPECT_LE(c.label_mismatches[0], canvas.active_voxel_count / 1000);  // near-ties only
  EXPECT_LE(c.max_difference_beyond(1), 1e-9);
}

// Seeds in pairs a few voxels apart: a voxel of one seed's block can be nearer to the other seed,
// whose block does not contain it. Every seed-block voxel must then hold the nearest seed's exact
// value (rvor/seed_blocks.h), whether the seeds come at once or one by one.
TEST_P(SeedsByDimension, BlockVoxelsNearerToAnotherSeedTakeThatSeed) {
  const int dimension = GetParam();
  const Mat3 G = rotated_metric(dimension, 3);
  const Canvas canvas = make_uniform_box_canvas(dimension, Vec3(-1, -1, -1), Vec3(1, 1, 1),
                                                dimension == 3 ? 32 : 64, G);
  const std::vector<Vec3> seeds = close_seed_pairs(canvas, 12, 5);
  detail::ReferenceSolver solver(canvas);
  detail::ExactField all, incremental;
  solver.solve(canvas, seeds, all);
  solver.solve(canvas, {seeds[0]}, incremental);
  for (std::size_t n = 1; n < seeds.size(); ++n)
    solver.insert(canvas, std::vector<Vec3>(seeds.begin(), seeds.begin() + n + 1), n, incremental);
  // 1e-6: the canvas holds the metric in float.
  expect_exact_seed_blocks(canvas, G, seeds, all.distance, all.label, 1e-6);
  expect_exact_seed_blocks(canvas, G, seeds, incremental.distance, incremental.label, 1e-6);
}

// The public interface: a chain of insert() calls on float fields keeps the double state, so it
// gives exactly the float image of the double-precision chain.
TEST_P(SeedsByDimension, PublicInsertKeepsDoublePrecision) {
  const int dimension = GetParam();
  const Canvas canvas = rotated_box(dimension, dimension == 3 ? 32 : 128);
  const std::vector<Vec3> seeds = random_seeds(canvas, 20, 3);
  auto propagator = make_reference_propagator();
  detail::ReferenceSolver solver(canvas);
  VoronoiField field;
  detail::ExactField exact;
  propagator->solve(canvas, {seeds[0]}, field);
  solver.solve(canvas, {seeds[0]}, exact);
  for (std::size_t n = 1; n < seeds.size(); ++n) {
    const std::vector<Vec3> prefix(seeds.begin(), seeds.begin() + n + 1);
    const PropagationStats stats = propagator->insert(canvas, prefix, n, field);
    EXPECT_GT(stats.iterations, 0u);
    solver.insert(canvas, prefix, n, exact);
  }
  for (std::size_t slot = 0; slot < canvas.slot_count(); ++slot) {
    ASSERT_EQ(field.distance[slot], static_cast<float>(exact.distance[slot]));
    ASSERT_EQ(field.label[slot], exact.label[slot]);
  }
}

// insert() starts from the caller's field: one that no solve for the old seeds returns is refused
// with the slot named (a label of an unknown seed indexed past the seeds), and the propagator
// still inserts into a solved field afterwards.
TEST_P(SeedsByDimension, InsertRefusesAFieldNotSolvedForTheOldSeeds) {
  const int dimension = GetParam();
  const Canvas canvas = rotated_box(dimension, dimension == 3 ? 16 : 48);
  const std::vector<Vec3> seeds = random_seeds(canvas, 6, 11);
  const std::vector<Vec3> old_seeds(seeds.begin(), seeds.end() - 1);
  auto propagator = make_reference_propagator();
  VoronoiField solved, all, field;
  propagator->solve(canvas, seeds, all);
  propagator->solve(canvas, old_seeds, solved);
  expect_corrupted_fields_refused(*propagator, canvas, seeds, old_seeds.size(), solved);
  field = solved;
  propagator->insert(canvas, seeds, old_seeds.size(), field);
  EXPECT_EQ(field.label, all.label);
}

// Single-seed solves (the dual's local fields) keep each voxel's neighbour slots and factorization
// corrections between evaluations, and skip the evaluations that cannot change a voxel: the same
// fields bit for bit as the same solve without them, on a varying metric (factorization
// weights between 0 and 1), with and without a distance limit.
TEST_P(SeedsByDimension, SingleSourceTermsKeptGiveTheSameFieldBitForBit) {
  const int dimension = GetParam();
  const PullBack pull_back{dimension, 0.6, 4.0};
  const Canvas canvas =
      make_box_canvas(dimension, Vec3(-1, -1, -1), Vec3(1, 1, 1), dimension == 3 ? 32 : 128,
                      [&](const Vec3& x) { return pull_back.metric(x); });
  const Vec3 seed(0.13, -0.41, dimension == 3 ? 0.27 : 0.0);
  for (const double limit : {std::numeric_limits<double>::infinity(), 0.9}) {
    detail::ExactField kept, evaluated;
    detail::ReferenceSolver keeping(canvas), evaluating(canvas);
    keeping.set_distance_limit(limit);
    evaluating.set_distance_limit(limit);
    evaluating.keep_single_source_terms(false);
    const PropagationStats kept_stats = keeping.solve(canvas, {seed}, kept);
    const PropagationStats evaluated_stats = evaluating.solve(canvas, {seed}, evaluated);
    EXPECT_EQ(kept_stats.iterations, evaluated_stats.iterations);
    // Voxels that cannot change are skipped (settled_below): about half of the evaluations.
    EXPECT_LT(kept_stats.voxel_updates, evaluated_stats.voxel_updates * 3 / 4);
    std::size_t reached = 0;
    for (std::size_t slot = 0; slot < canvas.slot_count(); ++slot) {
      ASSERT_EQ(kept.distance[slot], evaluated.distance[slot]) << "slot " << slot;
      ASSERT_EQ(kept.label[slot], evaluated.label[slot]) << "slot " << slot;
      reached += kept.distance[slot] <= limit ? 1 : 0;
    }
    EXPECT_GT(reached, canvas.active_voxel_count / 10);
    std::printf(
        "[ measured ] %dD single seed, limit %g: %.2f evaluations per reached voxel in "
        "%.3f s kept and skipping, %.2f in %.3f s without\n",
        dimension, limit, double(kept_stats.voxel_updates) / double(reached), kept_stats.seconds,
        double(evaluated_stats.voxel_updates) / double(reached), evaluated_stats.seconds);
  }
}

// The solves skip evaluating a voxel for a neighbour's change it has already read (run_queue).
// Whatever they skip, the field must be the fixed point: one more evaluation of every voxel changes
// none, after a solve (one seed, many seeds: labels meet) and after inserting seeds, on a varying
// metric, a rotated uniform one, and a diagonal one that starts at the nearest seeds' distances
// (the exact start, whose first evaluations run in order of value before the worklist).
TEST_P(SeedsByDimension, SkippedEvaluationsLeaveTheFixedPoint) {
  const int dimension = GetParam();
  const int resolution = dimension == 3 ? 24 : 96;
  const PullBack pull_back{dimension, 0.6, 4.0};
  const Canvas varying = make_box_canvas(dimension, Vec3(-1, -1, -1), Vec3(1, 1, 1), resolution,
                                         [&](const Vec3& x) { return pull_back.metric(x); });
  const Canvas rotated = rotated_box(dimension, resolution);
  Mat3 axes = Mat3::Identity();
  axes(1, 1) = 9;
  if (dimension == 3) axes(2, 2) = 3;
  const Canvas diagonal =
      make_uniform_box_canvas(dimension, Vec3(-1, -1, -1), Vec3(1, 1, 1), resolution, axes);
  for (const Canvas* canvas : {&varying, &rotated, &diagonal})
    for (const std::size_t count : {std::size_t{1}, std::size_t(dimension == 3 ? 30 : 150)}) {
      const std::vector<Vec3> seeds = random_seeds(*canvas, count, 5);
      detail::ReferenceSolver solver(*canvas);
      solver.set_exact_start(canvas == &diagonal);
      EXPECT_THROW(solver.unsettled_voxels(), Error);  // nothing solved yet
      detail::ExactField field;
      const PropagationStats stats = solver.solve(*canvas, seeds, field);
      EXPECT_EQ(stats.exact_start, canvas == &diagonal);
      EXPECT_EQ(solver.unsettled_voxels(), 0u) << count << " seeds";
      std::printf("[ measured ] %dD, %s metric, %zu seeds: %.2f evaluations per voxel\n", dimension,
                  canvas == &varying   ? "varying"
                  : canvas == &rotated ? "rotated"
                                       : "diagonal",
                  count, double(stats.voxel_updates) / double(canvas->active_voxel_count));
      if (count == 1) continue;
      const std::vector<Vec3> old_seeds(seeds.begin(), seeds.end() - 20);
      solver.solve(*canvas, old_seeds, field);
      solver.insert(*canvas, seeds, old_seeds.size(), field);
      EXPECT_EQ(solver.unsettled_voxels(), 0u) << "after inserting 20 seeds";
    }
}

INSTANTIATE_TEST_SUITE_P(Reference, SeedsByDimension, ::testing::Values(2, 3),
                         [](const ::testing::TestParamInfo<int>& info) {
                           return "D" + std::to_string(info.param);
                         });

// A tensor written with Canvas::mutable_metric after the builder checked it reaches the stencils
// unchecked: the error names its voxel and the tensor as stored, where it gave the inverse of its
// xy block with no place ("selling_decomposition: matrix [-0.0104 0.104 ...]").
TEST(CanvasTensors, ATensorThatIsNotSpdIsNamedByItsVoxel) {
  Canvas canvas = make_uniform_box_canvas(2, Vec3(-1, -1, 0), Vec3(1, 1, 0), 16, Mat3::Identity());
  const float not_spd[6] = {4, 10, 1, 0, 0, 1};
  std::copy(not_spd, not_spd + 6, canvas.mutable_metric(5));
  canvas.finalize();
  VoronoiField field;
  try {
    make_reference_propagator()->solve(canvas, {Vec3(0.1, 0.1, 0)}, field);
    ADD_FAILURE() << "solved on a tensor that is not SPD";
  } catch (const Error& e) {
    const std::string message = e.what();
    EXPECT_EQ(message.rfind("canvas voxel (5, 0, 0) at (", 0), 0u) << message;
    EXPECT_NE(message.find("not symmetric positive definite"), std::string::npos) << message;
  }
}

TEST(ReferenceStencils, OffsetsPastInt8AreRefusedWithTheVoxel) {
  expect_offsets_past_int8_refused(*make_reference_propagator());
}

}  // namespace
}  // namespace rvor::test
