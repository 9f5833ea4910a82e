#pragma once
// Propagation throughput on one case (domain, metric, resolution, seeds, device), with OpenVDB's
// FastSweeping (isotropic distance, labels as an int extension) and the CPU reference measured in
// the same run, on the same canvas and seeds. Used by `rvor bench` and bench/opencl.
#include <cstddef>
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "rvor/opencl_propagator.h"

namespace rvor {

struct BenchCase {
  std::string domain = "box:-1,-1,-1,1,1,1";  // parse_domain() spec
  std::string metric = "euclidean";           // make_analytic_metric() spec
  int resolution = 256;
  std::size_t seeds = 1000;
  std::uint64_t rng_seed = 1;
  std::string device = "auto";  // make_propagator() names; "cpu" times the reference itself
  RelaxationVariant variant = RelaxationVariant::automatic;  // OpenCL devices only
  // OpenCL brick_lanes solves: OpenCLOptions::front_step (automatic by default).
  double front_step = OpenCLOptions{}.front_step;
  // OpenCL brick_lanes and brick_sweep: OpenCLOptions::max_sweeps (0: automatic).
  int max_sweeps = OpenCLOptions{}.max_sweeps;
  // OpenCL voxel_phases: OpenCLOptions::phase_iterations and insertion_phase_iterations.
  int phase_iterations = OpenCLOptions{}.phase_iterations;
  int insertion_phase_iterations = OpenCLOptions{}.insertion_phase_iterations;
  // Uniform metrics: OpenCLOptions::exact_start, and the same for the CPU reference.
  bool exact_start = true;
  bool reference = true;     // also time the CPU reference (slow at 256^3)
  bool fastsweeping = true;  // also time OpenVDB FastSweeping (3D canvases)
  int repetitions = 1;  // solves with the same propagator, and FastSweeping runs; the fastest count
  // After the solve, insert this many further seeds (the next draws of the same generator),
  // insert_batch at a time, into the solved canvas: through a VoronoiSession, or with
  // checked_insert through Propagator::insert into a copy of the solved field (a caller's field,
  // which every insertion checks by reading all of it).
  std::size_t inserted_seeds = 0;
  std::size_t insert_batch = 1;  // seeds per insertion (the last may take fewer)
  bool checked_insert = false;
  // CanvasOptions::memory_budget for the canvas, and Propagator::set_memory_budget for the CPU
  // reference's arrays (0: the defaults).
  std::uint64_t memory_budget = 0;
};

// The cases `rvor bench` runs without case options: euclidean on [-1,1]^3 and radial_shock_3d on
// its [1,11]^3, 256^3, 1000 seeds from rng seed 1.
std::vector<BenchCase> standard_bench_cases();

struct BenchResult {
  BenchCase bench_case;
  std::string domain_description, metric_description, device_description;
  std::size_t active_voxels = 0;
  double max_anisotropy = 0.0;  // sqrt(lambda_max / lambda_min) of the metric, sampled

  // The engine under test. Seconds are those of Propagator::solve (first solve: includes the
  // canvas upload; with repetitions > 1 the fastest solve).
  double seconds = 0.0;
  std::uint64_t iterations = 0, voxel_updates = 0;
  double voxels_per_second = 0.0;  // active voxels / seconds
  double updates_per_voxel = 0.0;
  // OpenCL: brick relaxations of the solve per active brick (PropagationStats); cpu: 0.
  double relaxations_per_brick = 0.0;
  std::uint64_t visits_per_relaxation = 0;  // PropagationStats; cpu: 0
  bool exact_start = false;                 // PropagationStats: the solve started at u0
  std::uint64_t device_bytes = 0;           // OpenCL: the device canvas's buffers; cpu: 0
  double bytes_per_voxel = 0.0;             // device_bytes / active voxels

  // Incremental insertion (inserted_seeds > 0): mean and largest seconds of one insertion (of
  // insert_batch seeds) of a VoronoiSession (the chain of insertions a mesh generator runs: no
  // check of a caller's field, rvor/voronoi_session.h), or of Propagator::insert with
  // checked_insert, the read-back included; and the mean as a fraction of the solve.
  std::optional<double> insert_mean_seconds, insert_max_seconds, insert_fraction;
  std::size_t insertions = 0;  // calls timed: inserted_seeds / insert_batch, rounded up
  // Of the mean insertion, the seconds in its rounds of relaxations (PropagationStats::
  // round_seconds); the rest is the seeds' and the field's preparation and the read-back.
  std::optional<double> insert_mean_round_seconds;
  // Rounds per insertion (PropagationStats::iterations): on a GPU each waits for the device.
  std::optional<double> insert_mean_rounds;
  // Whether every insertion started its new seeds' voxels at their exact distance
  // (PropagationStats::exact_start: the OpenCL engine under a uniform diagonal metric).
  std::optional<bool> insert_exact_start;

  // OpenVDB FastSweeping: only sweep() is timed (initExt separately), 1 iteration of 8 sweeps.
  std::optional<double> fastsweeping_seconds, fastsweeping_init_seconds;
  std::optional<double> fastsweeping_voxels_per_second;
  std::optional<double> fastsweeping_ratio;  // voxels_per_second / FastSweeping's
  // Fraction of active voxels whose engine label equals FastSweeping's (meaningful when the
  // metric is isotropic; differences sit on bisectors).
  std::optional<double> fastsweeping_label_agreement;

  std::optional<double> reference_seconds, cpu_reference_voxels_per_second;
  std::optional<double> reference_ratio;  // voxels_per_second / the reference's
  // Largest |d - d_ref| / d_ref over reached voxels, and labels that differ from the reference.
  std::optional<double> reference_max_relative_difference;
  std::optional<std::size_t> reference_label_mismatches;
};

// Builds the canvas, draws the seeds, runs and times the engine, then FastSweeping and the
// reference as asked. `progress` (optional) receives one line per stage. Throws rvor::Error on
// bad specs and unusable devices.
BenchResult run_benchmark_case(const BenchCase& bench_case,
                               const std::function<void(const std::string&)>& progress = {});

}  // namespace rvor
