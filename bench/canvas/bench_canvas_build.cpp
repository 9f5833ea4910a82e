// build_canvas on the standard bench cases' domains at 128^3: the domain's voxelisation, the
// metric sampled and checked at every voxel, and the canvas's content hash. Active voxels per
// second, for a uniform field (stored once, the canvas's uniform form) and for varying ones
// (a tensor per voxel). And the checks of a mesh domain on a double cone, whose two fans made
// them quadratic in the fan's size.
#include <benchmark/benchmark.h>

#include <cmath>
#include <filesystem>
#include <fstream>

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

// A double cone as OFF: apex (0, 0, 1) over a flat disc fanned from the origin, `rim` vertices
// round both.
std::string write_double_cone(int rim) {
  const std::string path =
      (std::filesystem::temp_directory_path() / ("rvor_bench_cone_" + std::to_string(rim) + ".off"))
          .string();
  std::ofstream out(path);
  out.precision(17);
  out << "OFF\n" << rim + 2 << " " << 2 * rim << " 0\n0 0 1\n0 0 0\n";
  for (int i = 0; i < rim; ++i)
    out << std::cos(2 * M_PI * i / rim) << " " << std::sin(2 * M_PI * i / rim) << " 0\n";
  for (int i = 0; i < rim; ++i)
    out << "3 0 " << 2 + i << " " << 2 + (i + 1) % rim << "\n3 1 " << 2 + (i + 1) % rim << " "
        << 2 + i << "\n";
  return path;
}

// The canvas of a double cone at 16^3: the mesh's checks (closed, not crossing itself, convex)
// outweigh the voxelisation. Items: triangles.
void BM_MeshDomainChecks(benchmark::State& state) {
  const int rim = static_cast<int>(state.range(0));
  const std::string path = write_double_cone(rim);
  const rvor::DomainSpec domain = rvor::parse_domain("mesh:" + path);
  const std::unique_ptr<rvor::MetricField> metric = rvor::make_analytic_metric("euclidean", 3);
  rvor::CanvasOptions options;
  options.resolution = 16;
  for (auto _ : state) benchmark::DoNotOptimize(rvor::build_canvas(domain, *metric, options));
  std::filesystem::remove(path);
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations()) * 2 * rim);
}

}  // namespace

BENCHMARK(BM_BuildCanvas)->DenseRange(0, 3)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_MeshDomainChecks)
    ->Arg(5000)
    ->Arg(20000)
    ->Arg(100000)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
