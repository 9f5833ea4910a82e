// Selling's decomposition, the per-voxel cost of packing a varying metric's canvas (canvas upload
// of the OpenCL engine, stencils of the CPU reference): nanoseconds per decomposition of random
// dual metrics with anisotropy (square root of the eigenvalue ratio) up to the argument.
#include <benchmark/benchmark.h>

#include <random>
#include <vector>

#include <Eigen/Geometry>

#include "rvor/selling.h"

namespace {

// Random orientations; eigenvalues a^2 >= b^2 >= 1 with a up to `anisotropy`.
std::vector<rvor::Mat3> random_dual_metrics(int count, double anisotropy) {
  std::mt19937_64 random(7);
  std::uniform_real_distribution<double> unit(0, 1);
  std::vector<rvor::Mat3> metrics;
  for (int n = 0; n < count; ++n) {
    Eigen::Quaterniond q(unit(random) - 0.5, unit(random) - 0.5, unit(random) - 0.5,
                         unit(random) - 0.5);
    q.normalize();
    const rvor::Mat3 rotation = q.toRotationMatrix();
    const double a = 1 + (anisotropy - 1) * unit(random), b = 1 + (a - 1) * unit(random);
    const rvor::Vec3 eigenvalues(a * a, b * b, 1);
    metrics.push_back(rotation * eigenvalues.asDiagonal() * rotation.transpose());
  }
  return metrics;
}

void BM_SellingDecomposition(benchmark::State& state) {
  const std::vector<rvor::Mat3> metrics =
      random_dual_metrics(100000, static_cast<double>(state.range(0)));
  std::size_t next = 0;
  for (auto _ : state) {
    benchmark::DoNotOptimize(rvor::selling_decomposition(metrics[next], 3));
    next = next + 1 == metrics.size() ? 0 : next + 1;
  }
}

BENCHMARK(BM_SellingDecomposition)
    ->ArgName("anisotropy")
    ->Arg(2)
    ->Arg(40)
    ->Unit(benchmark::kNanosecond);

}  // namespace
