// build_canvas on the standard bench cases' domains at 128^3: the domain's voxelisation, the
// metric sampled and checked at every voxel, and the canvas's content hash. Active voxels per
// second, for a uniform field (stored once, the canvas's uniform form) and for varying ones
// (a tensor per voxel). And the checks of a mesh domain on a double cone, whose two fans made
// them quadratic in the fan's size; and the voxelisation of a cylinder whose ends are fans of
// slivers, which tested every voxel of each sliver's bounding box.
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
#include "surface_mesh.h"

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

// A cylinder along x, radius `radius` voxels and 4 long, its two ends fans of `rim` slivers.
rvor::SurfaceMesh sliver_fan_cylinder(int rim, double radius) {
  rvor::SurfaceMesh mesh;
  mesh.vertices = {rvor::Vec3(0, 0, 0), rvor::Vec3(4, 0, 0)};
  for (const double x : {0.0, 4.0})
    for (int i = 0; i < rim; ++i)
      mesh.vertices.emplace_back(x, radius * std::cos(2 * M_PI * i / rim),
                                 radius * std::sin(2 * M_PI * i / rim));
  for (int i = 0; i < rim; ++i) {
    const int next = (i + 1) % rim;
    mesh.triangles.push_back({0, 2 + next, 2 + i});
    mesh.triangles.push_back({1, 2 + rim + i, 2 + rim + next});
    rvor::add_polygon(mesh, {2 + i, 2 + next, 2 + rim + next, 2 + rim + i});
  }
  return mesh;
}

// inside_runs alone on the sliver fans, 4 x 1200 x 1200 voxels (the canvas's other checks would
// outweigh it). Items: triangles. Each sliver tested its whole (y, z) bounding box: 18 s at a rim
// of 20 000 before the rows between its edges were taken instead.
void BM_VoxelizeSliverFans(benchmark::State& state) {
  const int rim = static_cast<int>(state.range(0));
  const double radius = 600;
  const rvor::SurfaceMesh mesh = sliver_fan_cylinder(rim, radius);
  const rvor::Vec3 origin(0.5, 0.5 - radius, 0.5 - radius);
  for (auto _ : state)
    benchmark::DoNotOptimize(rvor::inside_runs(mesh, origin, 1.0, {4, 1200, 1200}));
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations() * mesh.triangles.size()));
}

}  // namespace

BENCHMARK(BM_BuildCanvas)->DenseRange(0, 3)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_MeshDomainChecks)
    ->Arg(5000)
    ->Arg(20000)
    ->Arg(100000)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
BENCHMARK(BM_VoxelizeSliverFans)
    ->Arg(2000)
    ->Arg(20000)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
