// The OpenCL engine and OpenVDB FastSweeping on one small case (64^3 box, 100 seeds), counters
// as rates: `voxels` is converged active voxels per second; and insertions of 1, 10 and 100 seeds
// into it. The full comparison, with the CPU reference and the 256^3 cases, is `rvor
// bench`.
#include <benchmark/benchmark.h>

#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "fastsweeping_baseline.h"
#include "rvor/benchmark.h"
#include "rvor/canvas_builder.h"
#include "rvor/domain.h"
#include "rvor/error.h"
#include "rvor/metric_field.h"
#include "rvor/opencl_propagator.h"
#include "rvor/seeds.h"
#include "rvor/voronoi_session.h"

namespace {

constexpr int kResolution = 64;
constexpr std::size_t kSeeds = 100;

struct SmallCase {
  rvor::Canvas canvas;
  std::vector<rvor::Vec3> seeds;
};

// Built once: the benchmarks time propagation, not canvas construction.
const SmallCase& small_case(const std::string& metric) {
  static std::map<std::string, std::unique_ptr<SmallCase>> cases;
  std::unique_ptr<SmallCase>& entry = cases[metric];
  if (!entry) {
    const rvor::BenchCase spec =
        metric == "euclidean" ? rvor::standard_bench_cases()[0] : rvor::standard_bench_cases()[1];
    const rvor::DomainSpec domain = rvor::parse_domain(spec.domain);
    rvor::CanvasOptions options;
    options.resolution = kResolution;
    entry = std::make_unique<SmallCase>();
    entry->canvas = rvor::build_canvas(domain, *rvor::make_analytic_metric(metric, 3), options);
    entry->seeds = rvor::random_seeds(entry->canvas, kSeeds, 1);
  }
  return *entry;
}

// Voxels (and, where the solver counts them, voxel updates) per second of the timed solves.
void set_rates(benchmark::State& state, std::size_t voxels, std::optional<double> updates) {
  const double processed = double(voxels) * double(state.iterations());
  state.counters["voxels"] = benchmark::Counter(processed, benchmark::Counter::kIsRate);
  if (!updates) return;
  state.counters["updates"] = benchmark::Counter(*updates, benchmark::Counter::kIsRate);
  state.counters["updates_per_voxel"] = *updates / processed;
}

void opencl_solve(benchmark::State& state, const std::string& metric) {
  const SmallCase& c = small_case(metric);
  std::unique_ptr<rvor::Propagator> engine;
  try {
    engine = rvor::make_opencl_propagator("auto");
  } catch (const rvor::Error& e) {
    return state.SkipWithError(e.what());
  }
  rvor::VoronoiField field;
  engine->solve(c.canvas, c.seeds, field);  // uploads the canvas and builds the program
  double updates = 0;
  for (auto _ : state) {
    const rvor::PropagationStats stats = engine->solve(c.canvas, c.seeds, field);
    state.SetIterationTime(stats.seconds);
    updates += double(stats.voxel_updates);
  }
  set_rates(state, c.canvas.active_voxel_count, updates);
  state.SetLabel(engine->device_description());
}

// One insertion of range(0) seeds into the solved case through a VoronoiSession (what
// farthest-point seeding and refinement run); only the insertion is timed, and `share_of_a_solve`
// is its time over the solve's before it.
void opencl_insertion(benchmark::State& state, const std::string& metric) {
  const SmallCase& c = small_case(metric);
  const std::vector<rvor::Vec3> extra =
      rvor::random_seeds(c.canvas, static_cast<std::size_t>(state.range(0)), 2);
  std::unique_ptr<rvor::Propagator> engine;
  try {
    engine = rvor::make_opencl_propagator("auto");
  } catch (const rvor::Error& e) {
    return state.SkipWithError(e.what());
  }
  rvor::VoronoiSession session(std::move(engine));
  // Uploads the canvas and builds the program, then one untimed insertion: an insertion launches
  // kernels a solve does not, whose code PoCL generates at their first launch (README,
  // "Throughput": with a cold kernel cache an insertion took 127 ms against 2 ms).
  session.solve(c.canvas, c.seeds);
  session.insert(c.canvas, extra);
  double solve_seconds = 0, insert_seconds = 0, rounds = 0;
  for (auto _ : state) {
    solve_seconds += session.solve(c.canvas, c.seeds).seconds;
    const rvor::PropagationStats stats = session.insert(c.canvas, extra);
    state.SetIterationTime(stats.seconds);
    insert_seconds += stats.seconds;
    rounds += double(stats.iterations);
  }
  state.counters["share_of_a_solve"] = insert_seconds / solve_seconds;
  state.counters["rounds"] = rounds / double(state.iterations());
  state.SetLabel(session.device_description());
}

// Only FastSweeping's sweep() is timed, as in rvor bench (its initialisation is one more pass).
void fastsweeping_solve(benchmark::State& state, const std::string& metric) {
  const SmallCase& c = small_case(metric);
  for (auto _ : state) {
    const rvor::baseline::FastSweepingRun run =
        rvor::baseline::fast_sweeping_voronoi(c.canvas, c.seeds);
    state.SetIterationTime(run.sweep_seconds);
  }
  set_rates(state, c.canvas.active_voxel_count, std::nullopt);  // FastSweeping counts none
  state.SetLabel("OpenVDB FastSweeping, isotropic, int label extension");
}

BENCHMARK_CAPTURE(opencl_solve, euclidean, std::string("euclidean"))
    ->UseManualTime()
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(opencl_solve, radial_shock_3d, std::string("radial_shock_3d"))
    ->UseManualTime()
    ->Unit(benchmark::kMillisecond);
// Insertions of 1, 10 and 100 seeds.
void insertion_batches(benchmark::internal::Benchmark* b) {
  b->Arg(1)->Arg(10)->Arg(100)->UseManualTime()->Unit(benchmark::kMillisecond);
}
BENCHMARK_CAPTURE(opencl_insertion, euclidean, std::string("euclidean"))->Apply(insertion_batches);
BENCHMARK_CAPTURE(opencl_insertion, radial_shock_3d, std::string("radial_shock_3d"))
    ->Apply(insertion_batches);
BENCHMARK_CAPTURE(fastsweeping_solve, euclidean, std::string("euclidean"))
    ->UseManualTime()
    ->Unit(benchmark::kMillisecond);

}  // namespace
