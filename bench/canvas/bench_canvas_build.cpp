// build_canvas on the standard bench cases' domains at 128^3: the domain's voxelisation, the
// metric sampled and checked at every voxel, and the canvas's content hash. Active voxels per
// second, for a uniform field (stored once, the canvas's uniform form) and for varying ones
// (a tensor per voxel).
#include <benchmark/benchmark.h>

#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "rvor/canvas_builder.h"
#include "rvor/domain.h"
#include "rvor/metric_field.h"

namespace {

struct BuildCase {
  const char* metric;
  const char* domain;
};

const std::vector<BuildCase>& build_cases() {
  static const std::vector<BuildCase> cases = {{"euclidean", "box:-1,-1,-1,1,1,1"},
                                               {"uniform:10,3,5,2,1,4", "box:0,0,0,1,1,1"},
                                               {"hyperbolic_shock", "box:-1,-1,-1,1,1,1"},
                                               {"radial_shock_3d", "box:1,1,1,11,11,11"}};
  return cases;
}

void BM_BuildCanvas(benchmark::State& state) {
  const BuildCase& c = build_cases()[static_cast<std::size_t>(state.range(0))];
  const rvor::DomainSpec domain = rvor::parse_domain(c.domain);
  const std::unique_ptr<rvor::MetricField> metric = rvor::make_analytic_metric(c.metric, 3);
  rvor::CanvasOptions options;
  options.resolution = 128;
  std::size_t active = 0;
  for (auto _ : state) {
    const rvor::Canvas canvas = rvor::build_canvas(domain, *metric, options);
    active = canvas.active_voxel_count;
    benchmark::DoNotOptimize(canvas.content_hash());
  }
  state.SetLabel(c.metric);
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations() * active));
}

}  // namespace

BENCHMARK(BM_BuildCanvas)->DenseRange(0, 3)->Unit(benchmark::kMillisecond)->UseRealTime();
