// run_benchmark_case (rvor/benchmark.h): one canvas, one seed set, three solvers.
#include "rvor/benchmark.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <functional>
#include <iomanip>
#include <memory>
#include <sstream>

#include "fastsweeping_baseline.h"
#include "rvor/canvas_builder.h"
#include "rvor/domain.h"
#include "rvor/error.h"
#include "rvor/metric_field.h"
#include "rvor/metric_reach.h"
#include "rvor/propagation.h"
#include "rvor/seeds.h"
#include "rvor/voronoi_session.h"

namespace rvor {

namespace {

void report(const std::function<void(const std::string&)>& progress, const std::string& line) {
  if (progress) progress(line);
}

std::string fixed_text(double value, int digits) {
  std::ostringstream out;
  out.precision(digits);
  out << std::fixed << value;
  return out.str();
}

std::string seconds_text(double seconds) {
  return fixed_text(seconds, 3) + " s";
}

double per_second(std::size_t voxels, double seconds) {
  return seconds > 0 ? static_cast<double>(voxels) / seconds : 0.0;
}

std::unique_ptr<Propagator> budgeted(std::unique_ptr<Propagator> propagator, const BenchCase& c) {
  propagator->set_memory_budget(c.memory_budget);
  return propagator;
}

std::unique_ptr<Propagator> make_engine(const BenchCase& c) {
  if (c.device == "cpu") return budgeted(make_reference_propagator(c.exact_start), c);
  OpenCLOptions options;
  options.variant = c.variant;
  options.front_step = c.front_step;
  options.max_sweeps = c.max_sweeps;
  options.phase_iterations = c.phase_iterations;
  options.insertion_phase_iterations = c.insertion_phase_iterations;
  options.exact_start = c.exact_start;
  return budgeted(make_opencl_propagator(c.device, options), c);
}

// Inserts the seeds after the first r.bench_case.seeds, insert_batch at a time: insert(next, end)
// inserts all_seeds[next, end) and returns its stats.
void time_insertion(const std::function<PropagationStats(std::size_t, std::size_t)>& insert,
                    std::size_t seed_count, BenchResult& r) {
  const std::size_t solved = r.bench_case.seeds;
  if (seed_count <= solved) return;
  const std::size_t batch = std::max<std::size_t>(1, r.bench_case.insert_batch);
  double total = 0.0, largest = 0.0, in_rounds = 0.0, rounds = 0.0;
  bool exact_start = true;
  r.insertions = 0;
  for (std::size_t next = solved; next < seed_count; next += batch) {
    const PropagationStats stats = insert(next, std::min(seed_count, next + batch));
    ++r.insertions;
    total += stats.seconds;
    in_rounds += stats.round_seconds;
    rounds += static_cast<double>(stats.iterations);
    largest = std::max(largest, stats.seconds);
    exact_start = exact_start && stats.exact_start;
  }
  const double insertions = static_cast<double>(r.insertions);
  r.insert_mean_seconds = total / insertions;
  r.insert_mean_round_seconds = in_rounds / insertions;
  r.insert_mean_rounds = rounds / insertions;
  r.insert_max_seconds = largest;
  r.insert_exact_start = exact_start;
  r.insert_fraction = *r.insert_mean_seconds / r.seconds;
}

void record_solve(const PropagationStats& stats, const Canvas& canvas, BenchResult& r) {
  r.seconds = stats.seconds;
  r.iterations = stats.iterations;
  r.voxel_updates = stats.voxel_updates;
  r.relaxations_per_brick = static_cast<double>(stats.brick_relaxations) /
                            static_cast<double>(std::max<std::size_t>(1, canvas.brick_count()));
  r.visits_per_relaxation = stats.visits_per_relaxation;
  r.exact_start = stats.exact_start;
  r.device_bytes = stats.device_bytes;
}

// Records the fastest of the case's solves by solve_once(). With insertions to time and more
// than one solve, the first solve is followed by warm_up(), an untimed insertion into it: an
// insertion launches kernels a solve does not, and PoCL generates a kernel's code at its first
// launch (with a cold kernel cache the largest of 4 insertions at 48^3 took 127 ms, against 2 ms;
// README, "Throughput"). The next solve
// starts over.
void time_solves(const BenchCase& c, const Canvas& canvas,
                 const std::function<PropagationStats()>& solve_once,
                 const std::function<void()>& warm_up, BenchResult& r) {
  const int repetitions = std::max(1, c.repetitions);
  for (int repetition = 0; repetition < repetitions; ++repetition) {
    const PropagationStats stats = solve_once();
    if (repetition == 0 || stats.seconds < r.seconds) record_solve(stats, canvas, r);
    if (repetition == 0 && repetitions > 1 && c.inserted_seeds > 0) warm_up();
  }
}

// Solves and inserts through a VoronoiSession, or with checked_insert through the propagator
// with a copy of the solved field as the caller's. `field`: the solve's, for the comparisons.
void time_engine(const BenchCase& c, const Canvas& canvas, const std::vector<Vec3>& all_seeds,
                 VoronoiField& field, BenchResult& r) {
  const std::vector<Vec3> seeds(all_seeds.begin(), all_seeds.begin() + c.seeds);
  if (c.checked_insert) {
    const std::unique_ptr<Propagator> engine = make_engine(c);
    time_solves(
        c, canvas, [&] { return engine->solve(canvas, seeds, field); },
        [&] {
          VoronoiField copy = field;
          engine->insert(canvas, {all_seeds.begin(), all_seeds.begin() + c.seeds + 1}, c.seeds,
                         copy);
        },
        r);
    r.device_description = engine->device_description();  // after a solve: the variant that ran
    VoronoiField extended = field;
    time_insertion(
        [&](std::size_t next, std::size_t end) {
          return engine->insert(canvas, {all_seeds.begin(), all_seeds.begin() + end}, next,
                                extended);
        },
        all_seeds.size(), r);
  } else {
    VoronoiSession session(make_engine(c));
    time_solves(
        c, canvas, [&] { return session.solve(canvas, seeds); },
        [&] { session.insert(canvas, {all_seeds[c.seeds]}); }, r);
    r.device_description = session.device_description();
    field = session.field();
    time_insertion(
        [&](std::size_t next, std::size_t end) {
          return session.insert(canvas, {all_seeds.begin() + next, all_seeds.begin() + end});
        },
        all_seeds.size(), r);
  }
  r.voxels_per_second = per_second(r.active_voxels, r.seconds);
  r.updates_per_voxel = static_cast<double>(r.voxel_updates) / static_cast<double>(r.active_voxels);
  r.bytes_per_voxel = static_cast<double>(r.device_bytes) / static_cast<double>(r.active_voxels);
}

double label_agreement(const Canvas& canvas, const VoronoiField& a, const VoronoiField& b) {
  std::size_t same = 0;
  for (std::size_t slot = 0; slot < canvas.slot_count(); ++slot)
    if (canvas.active[slot] && a.label[slot] == b.label[slot]) ++same;
  return static_cast<double>(same) / static_cast<double>(canvas.active_voxel_count);
}

// The fastest of as many runs as the engine's solves (c.repetitions), as the engine's fastest
// solve counts: one run against the fastest of two favoured the engine under a changing load. The
// labels are compared on the first run's field, which is dropped before the next run.
void time_fastsweeping(const BenchCase& c, const Canvas& canvas, const std::vector<Vec3>& seeds,
                       const VoronoiField& engine_field, BenchResult& r) {
  for (int repetition = 0; repetition < std::max(1, c.repetitions); ++repetition) {
    const baseline::FastSweepingRun run = baseline::fast_sweeping_voronoi(canvas, seeds);
    if (repetition == 0)
      r.fastsweeping_label_agreement = label_agreement(canvas, engine_field, run.field);
    if (repetition > 0 && run.sweep_seconds >= *r.fastsweeping_seconds) continue;
    r.fastsweeping_seconds = run.sweep_seconds;
    r.fastsweeping_init_seconds = run.init_seconds;
  }
  r.fastsweeping_voxels_per_second = per_second(r.active_voxels, *r.fastsweeping_seconds);
  r.fastsweeping_ratio = r.voxels_per_second / *r.fastsweeping_voxels_per_second;
}

void compare_with_reference(const Canvas& canvas, const VoronoiField& engine,
                            const VoronoiField& reference, BenchResult& r) {
  double worst = 0.0;
  std::size_t mismatches = 0;
  for (std::size_t slot = 0; slot < canvas.slot_count(); ++slot) {
    if (!canvas.active[slot]) continue;
    if (engine.label[slot] != reference.label[slot]) ++mismatches;
    const double d_ref = reference.distance[slot];
    if (std::isfinite(d_ref) && d_ref > 0)
      worst = std::max(worst, std::abs(double(engine.distance[slot]) - d_ref) / d_ref);
  }
  r.reference_max_relative_difference = worst;
  r.reference_label_mismatches = mismatches;
}

// The reference beside an engine: its refusals say how to do without it.
PropagationStats solve_reference(const BenchCase& c, const Canvas& canvas,
                                 const std::vector<Vec3>& seeds, VoronoiField& reference) {
  try {
    return budgeted(make_reference_propagator(c.exact_start), c)->solve(canvas, seeds, reference);
  } catch (const Error& error) {
    throw Error(std::string(error.what()) +
                " (the bench's CPU reference: --no-reference skips it)");
  }
}

void time_reference(const BenchCase& c, const Canvas& canvas, const std::vector<Vec3>& seeds,
                    const VoronoiField& engine_field, BenchResult& r) {
  VoronoiField reference;
  const PropagationStats stats = solve_reference(c, canvas, seeds, reference);
  r.reference_seconds = stats.seconds;
  r.cpu_reference_voxels_per_second = per_second(r.active_voxels, stats.seconds);
  r.reference_ratio = r.voxels_per_second / *r.cpu_reference_voxels_per_second;
  compare_with_reference(canvas, engine_field, reference, r);
}

}  // namespace

std::vector<BenchCase> standard_bench_cases() {
  BenchCase euclidean;
  BenchCase radial_shock;
  radial_shock.domain = "box:1,1,1,11,11,11";
  radial_shock.metric = "radial_shock_3d";
  return {euclidean, radial_shock};
}

BenchResult run_benchmark_case(const BenchCase& c,
                               const std::function<void(const std::string&)>& progress) {
  BenchResult r;
  r.bench_case = c;
  auto start = std::chrono::steady_clock::now();
  const DomainSpec domain = parse_domain(c.domain);
  const std::unique_ptr<MetricField> metric = make_analytic_metric(c.metric, domain.dimension());
  CanvasOptions canvas_options;
  canvas_options.resolution = c.resolution;
  canvas_options.memory_budget = c.memory_budget;
  const Canvas canvas = build_canvas(domain, *metric, canvas_options);
  r.domain_description = domain.description();
  r.metric_description = metric->description();
  r.active_voxels = canvas.active_voxel_count;
  r.max_anisotropy = sampled_metric_reach(canvas).max_anisotropy;
  // Random draws are sequential, so the first c.seeds do not depend on c.inserted_seeds.
  const std::vector<Vec3> all_seeds = random_seeds(canvas, c.seeds + c.inserted_seeds, c.rng_seed);
  const std::vector<Vec3> seeds(all_seeds.begin(), all_seeds.begin() + c.seeds);
  report(progress,
         "canvas " + canvas.description + ": " + std::to_string(r.active_voxels) +
             " active voxels, " + std::to_string(seeds.size()) + " seeds (" +
             seconds_text(
                 std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count()) +
             ")");

  VoronoiField field;
  time_engine(c, canvas, all_seeds, field, r);
  if (c.device == "cpu") {  // the reference pops a queue: it has no rounds to count or time
    r.insert_mean_rounds.reset();
    r.insert_mean_round_seconds.reset();
  }
  report(progress, r.device_description + ": " + seconds_text(r.seconds));
  if (r.insert_mean_seconds)
    report(progress,
           "insert " + std::to_string(c.inserted_seeds) + " seeds " +
               (c.insert_batch > 1 ? "in batches of " + std::to_string(c.insert_batch)
                                   : std::string("one by one")) +
               ": mean " + seconds_text(*r.insert_mean_seconds) +
               (r.insert_mean_rounds ? " (" + seconds_text(*r.insert_mean_round_seconds) + " in " +
                                           fixed_text(*r.insert_mean_rounds, 1) + " rounds)"
                                     : std::string()) +
               ", largest " + seconds_text(*r.insert_max_seconds));
  if (c.fastsweeping && canvas.dimension == 3) {
    time_fastsweeping(c, canvas, seeds, field, r);
    report(progress, "OpenVDB FastSweeping: sweep " + seconds_text(*r.fastsweeping_seconds) +
                         ", init " + seconds_text(*r.fastsweeping_init_seconds) + "; " +
                         fixed_text(100.0 * *r.fastsweeping_label_agreement, 2) +
                         "% of the labels agree (isotropic, with the label carried along)");
  } else if (c.fastsweeping) {
    report(progress, "OpenVDB FastSweeping: skipped (the baseline runs on 3D canvases only)");
  }
  if (c.reference && c.device == "cpu") {  // the engine is the reference: no second run
    r.reference_seconds = r.seconds;
    r.cpu_reference_voxels_per_second = r.voxels_per_second;
    r.reference_ratio = 1.0;
  } else if (c.reference) {
    time_reference(c, canvas, seeds, field, r);
    std::ostringstream difference;
    difference << std::setprecision(2) << *r.reference_max_relative_difference;
    report(progress, "CPU reference: " + seconds_text(*r.reference_seconds) +
                         "; largest relative difference " + difference.str() + ", " +
                         std::to_string(*r.reference_label_mismatches) +
                         " voxels labelled otherwise");
  }
  return r;
}

}  // namespace rvor
