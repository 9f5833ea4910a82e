// Nerve extraction + straight dual for N random seeds on an R^3 box canvas (uniform anisotropic
// metric), next to the propagation that produces the labels. The propagation runs twice per
// configuration (device from RVOR_BENCH_DEVICE, default "auto", i.e. OpenCL where available);
// the second solve's time is reported as the counter propagation_s (the first uploads the canvas
// and builds the kernels) and the ratio as dual_over_propagation. The
// bricks to visit come from the propagator (Propagator::multi_label_bricks: a kernel on the
// device state for the OpenCL engine), timed as multi_label_s and counted in the ratio;
// scanned_brick_fraction is the fraction of bricks it flags; nerve_all_bricks_s times the nerve
// scanning every brick (its own per-brick uniformity test instead of the flags), as the baseline.
// The design's target: 10,000 seeds at 256^3 in <= 10% of the propagation time:
//   bench_dual --benchmark_filter='NerveAndDual/256/10000'
#include <benchmark/benchmark.h>

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <map>

#include "rvor/dual.h"
#include "rvor/propagation.h"
#include "rvor/seeds.h"
#include "support/box_canvas.h"

namespace {

struct Labeled {
  rvor::Canvas canvas;
  std::vector<rvor::Vec3> seeds;
  rvor::VoronoiField field;
  double propagation_seconds = 0.0;
  std::unique_ptr<rvor::Propagator> propagator;
};

Labeled& labeled(int resolution, int seeds) {
  static std::map<std::pair<int, int>, Labeled> cache;
  auto [it, inserted] = cache.try_emplace({resolution, seeds});
  Labeled& l = it->second;
  if (!inserted) return l;
  rvor::Mat3 G;
  G << 4.0, 1.0, 0.0, 1.0, 2.0, 0.5, 0.0, 0.5, 1.0;
  l.canvas = rvor::test::make_uniform_box_canvas(3, rvor::Vec3(0, 0, 0), rvor::Vec3(1, 1, 1),
                                                 resolution, G);
  l.seeds = rvor::random_seeds(l.canvas, static_cast<std::size_t>(seeds), 1);
  const char* device = std::getenv("RVOR_BENCH_DEVICE");
  l.propagator = rvor::make_propagator(device ? device : "auto");
  // A first solve and flagging, untimed: they upload the canvas and have PoCL generate the
  // kernels' code at their first launch, which multi_label_s and propagation_s would time.
  l.propagator->solve(l.canvas, l.seeds, l.field);
  l.propagator->multi_label_bricks(l.canvas, l.field);
  l.propagation_seconds = l.propagator->solve(l.canvas, l.seeds, l.field).seconds;
  return l;
}

void NerveAndDual(benchmark::State& state) {
  Labeled& l = labeled(static_cast<int>(state.range(0)), static_cast<int>(state.range(1)));
  double flag_seconds = 0.0, nerve_seconds = 0.0, all_bricks_seconds = 0.0, dual_seconds = 0.0;
  std::size_t flagged = 0;
  for (auto _ : state) {
    const auto start = std::chrono::steady_clock::now();
    const std::vector<std::uint8_t> bricks = l.propagator->multi_label_bricks(l.canvas, l.field);
    flag_seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    flagged = static_cast<std::size_t>(std::count(bricks.begin(), bricks.end(), 1));
    const rvor::Nerve nerve = rvor::extract_nerve(l.canvas, l.field, l.seeds.size(), bricks);
    const rvor::StraightDual dual = rvor::build_straight_dual(l.canvas, nerve, l.seeds);
    benchmark::DoNotOptimize(dual.checks.is_triangulation);
    all_bricks_seconds += rvor::extract_nerve(l.canvas, l.field, l.seeds.size()).seconds;
    nerve_seconds += nerve.seconds;
    dual_seconds += dual.seconds;
  }
  const double n = static_cast<double>(state.iterations());
  state.counters["propagation_s"] = l.propagation_seconds;
  state.counters["multi_label_s"] = flag_seconds / n;
  state.counters["scanned_brick_fraction"] =
      static_cast<double>(flagged) / static_cast<double>(l.canvas.brick_count());
  state.counters["nerve_s"] = nerve_seconds / n;
  state.counters["nerve_all_bricks_s"] = all_bricks_seconds / n;
  state.counters["dual_s"] = dual_seconds / n;
  state.counters["dual_over_propagation"] =
      (flag_seconds + nerve_seconds + dual_seconds) / n / l.propagation_seconds;
}

BENCHMARK(NerveAndDual)
    ->Args({64, 500})
    ->Args({128, 2000})
    ->Args({256, 1000})
    ->Args({256, 10000})
    ->Unit(benchmark::kMillisecond)
    ->Iterations(3);

}  // namespace
