// The seed blocks' claims (rvor/seed_blocks.h) of a solve with dense seeds: milliseconds per
// foreign_seed_claims call at 128^3 with 20000 seeds, in a uniform metric and in one whose scale
// varies 40-fold across the box (the radial_shock_3d situation, where a block of the fine part is
// within reach of coarse seeds from far away).
#include <benchmark/benchmark.h>

#include <cmath>
#include <vector>

#include "rvor/seed_blocks.h"
#include "rvor/seeds.h"
#include "support/box_canvas.h"

namespace {

rvor::Mat3 scale_varying_metric(const rvor::Vec3& p) {
  const double scale = std::pow(40.0, 0.5 * (p.x() + 1));  // 1 at x = -1, 40 at x = 1
  return scale * scale * rvor::Mat3::Identity();
}

void claims_of_a_solve(benchmark::State& state, const rvor::Canvas& canvas) {
  const std::vector<rvor::Vec3> seeds =
      rvor::random_seeds(canvas, static_cast<std::size_t>(state.range(0)), 3);
  for (auto _ : state) benchmark::DoNotOptimize(rvor::foreign_seed_claims(canvas, seeds));
}

void BM_ClaimsUniform(benchmark::State& state) {
  static const rvor::Canvas canvas = rvor::test::make_uniform_box_canvas(
      3, rvor::Vec3(-1, -1, -1), rvor::Vec3(1, 1, 1), 128, rvor::Mat3::Identity());
  claims_of_a_solve(state, canvas);
}

void BM_ClaimsScaleVarying(benchmark::State& state) {
  static const rvor::Canvas canvas = rvor::test::make_box_canvas(
      3, rvor::Vec3(-1, -1, -1), rvor::Vec3(1, 1, 1), 128, scale_varying_metric);
  claims_of_a_solve(state, canvas);
}

// N copies of one seed among 1000 others: each copy's block was read by all the others.
void BM_ClaimsCopiesOfOneSeed(benchmark::State& state) {
  static const rvor::Canvas canvas = rvor::test::make_uniform_box_canvas(
      3, rvor::Vec3(-1, -1, -1), rvor::Vec3(1, 1, 1), 128, rvor::Mat3::Identity());
  std::vector<rvor::Vec3> seeds = rvor::random_seeds(canvas, 1000, 3);
  seeds.insert(seeds.end(), static_cast<std::size_t>(state.range(0)), seeds.front());
  for (auto _ : state) benchmark::DoNotOptimize(rvor::foreign_seed_claims(canvas, seeds));
}

BENCHMARK(BM_ClaimsUniform)->ArgName("seeds")->Arg(1000)->Arg(20000)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_ClaimsScaleVarying)
    ->ArgName("seeds")
    ->Arg(1000)
    ->Arg(20000)
    ->Unit(benchmark::kMillisecond);
BENCHMARK(BM_ClaimsCopiesOfOneSeed)
    ->ArgName("copies")
    ->Arg(1000)
    ->Arg(3000)
    ->Unit(benchmark::kMillisecond);

}  // namespace
