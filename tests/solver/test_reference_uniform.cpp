// Uniform anisotropic metrics: the factored scheme must reproduce |F (x - p)| closely.
#include <gtest/gtest.h>

#include <string>

#include "rvor/error.h"
#include "solver_fixtures.h"

namespace rvor::test {
namespace {

constexpr double kAnisotropy = 10;
constexpr double kMinExact = 0.1;  // errors are measured beyond this metric distance

struct UniformCase {
  int dimension;
  int resolution;
  bool rotated;
};

std::string name_of(const UniformCase& c) {
  return std::to_string(c.dimension) + "D " + std::to_string(c.resolution) +
         (c.rotated ? " rotated" : " axis-aligned") + " anisotropy 10";
}

class UniformMetric : public ::testing::TestWithParam<UniformCase> {};

TEST_P(UniformMetric, DistanceMatchesExactNorm) {
  const UniformCase c = GetParam();
  const Vec3 axis = c.rotated ? (c.dimension == 3 ? Vec3(1, 1, 1) : Vec3(1, 1, 0)) : Vec3(1, 0, 0);
  const Mat3 G = uniform_anisotropic_metric(axis, kAnisotropy);
  const Canvas canvas =
      make_uniform_box_canvas(c.dimension, Vec3(-1, -1, -1), Vec3(1, 1, 1), c.resolution, G);
  const Vec3 seed = voxel_centre_near(canvas, Vec3(0.1, -0.05, c.dimension == 3 ? 0.02 : 0));
  const Mat3 F = metric_sqrt(G);

  PropagationStats stats;
  const detail::ExactField field = solve_exact(canvas, {seed}, &stats);
  const ErrorStats errors = relative_errors(
      canvas, field.distance, [&](const Vec3& x) { return (F * (x - seed)).norm(); }, kMinExact);
  report(name_of(c), errors, stats);

  EXPECT_EQ(errors.unreached, 0u);
  EXPECT_LE(errors.max_relative, 0.01);
  for (std::size_t slot = 0; slot < canvas.slot_count(); ++slot)
    if (canvas.active[slot]) {
      ASSERT_EQ(field.label[slot], 0);
    }
}

INSTANTIATE_TEST_SUITE_P(Reference, UniformMetric,
                         ::testing::Values(UniformCase{2, 128, false}, UniformCase{2, 128, true},
                                           UniformCase{2, 512, false}, UniformCase{2, 512, true},
                                           UniformCase{3, 128, false}, UniformCase{3, 128, true}),
                         [](const ::testing::TestParamInfo<UniformCase>& info) {
                           return "D" + std::to_string(info.param.dimension) + "_" +
                                  std::to_string(info.param.resolution) +
                                  (info.param.rotated ? "_rotated" : "_aligned");
                         });

// The public float interface gives the same field (to float rounding) as the double solver.
TEST(ReferencePropagator, PublicInterfaceMatchesExactSolver) {
  const Mat3 G = uniform_anisotropic_metric(Vec3(1, 1, 1), 4);
  const Canvas canvas = make_uniform_box_canvas(3, Vec3(-1, -1, -1), Vec3(1, 1, 1), 32, G);
  const std::vector<Vec3> seeds = {Vec3(0.1, -0.05, 0.02), Vec3(-0.5, 0.4, 0.3)};
  auto propagator = make_reference_propagator();
  EXPECT_EQ(propagator->device_description(), "cpu reference");
  VoronoiField field;
  const PropagationStats stats = propagator->solve(canvas, seeds, field);
  EXPECT_GT(stats.iterations, 0u);
  EXPECT_GE(stats.voxel_updates, stats.iterations);
  const detail::ExactField exact = solve_exact(canvas, seeds);
  ASSERT_EQ(field.distance.size(), canvas.slot_count());
  for (std::size_t slot = 0; slot < canvas.slot_count(); ++slot) {
    EXPECT_EQ(field.distance[slot], static_cast<float>(exact.distance[slot]));
    EXPECT_EQ(field.label[slot], exact.label[slot]);
  }
}

// The propagator keeps its stencils for the canvas it saw last; a canvas changed in place between
// the slots it samples, then finalized, is solved on its new metric (Canvas::content_hash).
TEST(ReferencePropagator, SolvesACanvasChangedInPlaceOnItsNewMetric) {
  Canvas canvas = make_uniform_box_canvas(2, Vec3(-1, -1, 0), Vec3(1, 1, 0), 256, Mat3::Identity());
  const std::vector<Vec3> seeds = {Vec3(0.1, -0.05, 0), Vec3(-0.5, 0.4, 0)};
  auto propagator = make_reference_propagator();
  VoronoiField before, after;
  propagator->solve(canvas, seeds, before);
  slow_down_a_brick_between_sampled_slots(canvas);
  propagator->solve(canvas, seeds, after);
  const detail::ExactField exact = solve_exact(canvas, seeds);
  for (std::size_t slot = 0; slot < canvas.slot_count(); ++slot)
    ASSERT_EQ(after.distance[slot], static_cast<float>(exact.distance[slot])) << "slot " << slot;
  EXPECT_NE(after.distance, before.distance);
}

// A one-seed reference solve's voxel updates per active voxel.
// From +inf: the exact start would begin a diagonal metric at the answer and settle nothing.
double reference_updates_per_voxel(const Canvas& canvas, const Vec3& seed) {
  VoronoiField field;
  const PropagationStats stats = make_reference_propagator(false)->solve(canvas, {seed}, field);
  return static_cast<double>(stats.voxel_updates) / static_cast<double>(canvas.active_voxel_count);
}

// Strong anisotropy nearly along an axis has long stencil offsets; their source factorization
// near the seed is weighted down (docs/scheme.md, "Local update", step 2), without which this
// solve stopped after 1000 recomputations per voxel.
TEST(ReferencePropagator, SettlesUnderStrongAnisotropyNearlyAlongAnAxis) {
  for (const double anisotropy : {25.0, 40.0, 100.0}) {
    const double angle = (anisotropy == 25.0 ? 1.7 : 0.5) * M_PI / 180;
    const Vec3 along(std::cos(angle), std::sin(angle), 0);
    const Vec3 across(-std::sin(angle), std::cos(angle), 0);
    const Mat3 G = anisotropy * anisotropy * along * along.transpose() +
                   across * across.transpose() + Vec3::UnitZ() * Vec3::UnitZ().transpose();
    const Canvas canvas = make_uniform_box_canvas(2, Vec3(-1, -1, 0), Vec3(1, 1, 0), 127, G);
    const double per_voxel = reference_updates_per_voxel(canvas, Vec3(0.13, -0.21, 0));
    std::printf("[ measured ] anisotropy %.0f: %.1f updates per voxel\n", anisotropy, per_voxel);
    EXPECT_LT(per_voxel, 20.0) << "anisotropy " << anisotropy;
  }
}

// Anisotropy 1000 along an axis: the quadratic's discriminant written as b^2 - a c cancelled to
// 1e-11 of the value, above the 1e-12 change threshold, and two voxels beside the seed
// re-evaluated each other forever (reference_solver.cpp, solve_sorted_quadratic).
TEST(ReferencePropagator, SettlesUnderAnisotropy1000AlongAnAxis) {
  for (const int dimension : {2, 3}) {
    const Mat3 G = Vec3(1e6, 1, 1).asDiagonal();
    const Canvas canvas = make_uniform_box_canvas(dimension, Vec3(-1, -1, -1), Vec3(1, 1, 1),
                                                  dimension == 2 ? 32 : 24, G);
    const double per_voxel = reference_updates_per_voxel(canvas, Vec3(0.03, -0.11, 0.05));
    std::printf("[ measured ] %dD anisotropy 1000: %.1f updates per voxel\n", dimension, per_voxel);
    EXPECT_LT(per_voxel, 20.0) << dimension << "D";
  }
}

TEST(ReferencePropagator, RejectsSeedsOutsideTheDomain) {
  const Canvas canvas =
      make_uniform_box_canvas(2, Vec3(-1, -1, 0), Vec3(1, 1, 0), 16, Mat3::Identity());
  auto propagator = make_reference_propagator();
  VoronoiField field;
  EXPECT_THROW(propagator->solve(canvas, {Vec3(2, 0, 0)}, field), Error);
  EXPECT_THROW(propagator->solve(canvas, {}, field), Error);
}

}  // namespace
}  // namespace rvor::test
