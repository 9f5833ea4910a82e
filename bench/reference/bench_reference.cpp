// Throughput of the CPU reference solver: converged voxels per second (active voxels of the canvas
// divided by the solve time), for a euclidean and an anisotropic uniform metric.
#include <benchmark/benchmark.h>

#include <vector>

#include "rvor/propagation.h"
#include "rvor/seeds.h"
#include "support/box_canvas.h"

namespace {

enum MetricKind { kEuclidean = 0, kAnisotropic = 1 };

rvor::Mat3 bench_metric(int kind) {
  if (kind == kEuclidean) return rvor::Mat3::Identity();
  // Anisotropy 10 along (1,1,1)/sqrt(3): F has eigenvalues 10, 1, 1.
  const rvor::Vec3 axis = rvor::Vec3(1, 1, 1).normalized();
  return rvor::Mat3::Identity() + 99.0 * axis * axis.transpose();
}

// Arguments: resolution, seed count, metric kind.
void BM_ReferenceSolve(benchmark::State& state) {
  const int resolution = static_cast<int>(state.range(0));
  const std::size_t seed_count = static_cast<std::size_t>(state.range(1));
  const int kind = static_cast<int>(state.range(2));
  const rvor::Canvas canvas = rvor::test::make_uniform_box_canvas(
      3, rvor::Vec3(-1, -1, -1), rvor::Vec3(1, 1, 1), resolution, bench_metric(kind));
  const std::vector<rvor::Vec3> seeds = rvor::random_seeds(canvas, seed_count, 11);
  auto propagator = rvor::make_reference_propagator();
  rvor::VoronoiField field;
  propagator->solve(canvas, seeds, field);  // builds (and caches) the stencils outside the timing
  double voxels = 0;
  for (auto _ : state) {
    const rvor::PropagationStats stats = propagator->solve(canvas, seeds, field);
    benchmark::DoNotOptimize(field.distance.data());
    state.SetIterationTime(stats.seconds);
    voxels += static_cast<double>(canvas.active_voxel_count);
  }
  state.counters["voxels"] = benchmark::Counter(voxels, benchmark::Counter::kIsRate);
  state.SetLabel(kind == kEuclidean ? "euclidean" : "anisotropic 10, rotated");
}

BENCHMARK(BM_ReferenceSolve)
    ->ArgNames({"res", "seeds", "aniso"})
    ->ArgsProduct({{64, 128}, {1, 100}, {kEuclidean, kAnisotropic}})
    ->UseManualTime()
    ->Unit(benchmark::kMillisecond);

}  // namespace
