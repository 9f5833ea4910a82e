#pragma once
#include <cstddef>
// The OpenCL propagation engine (docs/scheme.md as kernels, block Fast Iterative Method on bricks).
#include <memory>
#include <string>

#include "rvor/propagation.h"

namespace rvor {

// The most seeds an OpenCL solve takes: labels stay below the kernels' TENTATIVE_LABEL bit, 2^30
// (kernels/state_word.clh).
constexpr std::size_t kMostOpenCLSeeds = (std::size_t{1} << 30) - 1;

enum class RelaxationVariant {
  automatic,     // brick_lanes on CPU devices, voxel_phases on GPUs
  brick_sweep,   // a work-item sweeps a whole brick Gauss-Seidel (CPU-friendly)
  brick_lanes,   // brick_sweep on 8 bricks at once, one per SIMD lane (CPU default)
  voxel_phases,  // a work-group per brick, 2^d phases by voxel parity, a work-item per voxel
                 // of the phase, in local memory (GPU)
};

// The shortest front step (OpenCLOptions::front_step, voxel lengths) the engine takes: shorter
// steps multiply the rounds (1e-30 took 360 times the rounds).
constexpr double kSmallestFrontStep = 0.25;

// The most sweeps (max_sweeps) or iterations (phase_iterations, insertion_phase_iterations) one
// relaxation of a brick may take: they bound its evaluation stamps (kernels/propagation.cl, work
// avoidance).
constexpr int kMostVisitsPerRelaxation = 64;

struct OpenCLOptions {
  RelaxationVariant variant = RelaxationVariant::automatic;
  // brick_sweep and brick_lanes: most sweeps per brick and round, in [1, 64], or 0: automatic, 4
  // for a uniform metric with axis offsets (the isotropic case) and 2 for any other stencil
  // (1000 seeds, 256^3 euclidean: 7.79 -> 5.09 relaxations per brick, 3.48 -> 3.21 s from 2 to 4
  // sweeps, means of three alternating runs; 128^3 radial_shock_3d: 10.6 -> 14.7 updates per
  // voxel, 3.1 -> 3.9 s; docs/scheme.md, "Sweeps per relaxation").
  // make_opencl_propagator throws outside [0, 64].
  int max_sweeps = 0;
  int phase_iterations = 8;  // voxel_phases: most iterations (all phases) per round (at least 1)
  // voxel_phases insertions: most iterations per round, in [1, 64]. An insertion relaxes a few
  // bricks a round, so a round lasts as long as one work-group's iterations, each 8 phases apart
  // by barriers: fewer iterations, more but shorter rounds. One insertion into 1000 seeds at 256^3
  // on an NVIDIA H200 (docs/scheme.md, "Iterations per insertion round"; `rvor bench
  // --insertion-phase-iterations N`): 2 / 4 / 8 / 16 iterations 4.65 / 4.39 / 5.04 / 6.08 ms
  // (euclidean), 4 / 8 12.1 / 17.9 ms (radial_shock_3d).
  int insertion_phase_iterations = 4;
  // Solves relax one brick colour (parities of the brick coordinates, 2^d colours) per round, so
  // that a brick reads its neighbours' fresh values (insertions relax every pending brick each
  // round while they fit the scratch, docs/scheme.md, "Insertion on the device"). `rvor bench
  // --resolution 96 --seeds 1000 --repeat 2`, without -> with: euclidean 12.49 -> 10.13 updates per
  // voxel, radial_shock_3d 20.32 -> 13.53 (and 1.6 -> 1.2-1.5 s, 5.7-6.4 -> 4.1-4.2 s).
  bool brick_colouring = true;
  // brick_lanes with per-voxel stencils, on a device that compiles with AVX2 (PoCL on x86): the
  // lanes whose neighbours lie in their tiles take their stencils and neighbours by x86 gathers
  // (radial_shock_3d 128^3: 1.85 -> 1.58 s, docs/scheme.md, "Gathers in the general form");
  // false: one lane at a time, as every other device does.
  bool x86_gathers = true;
  // brick_lanes solves (not insertions): front stepping, in voxel lengths (docs/scheme.md, "Front
  // stepping"): evaluations above a threshold stay tentative, hidden from their neighbours, until
  // the threshold, moved this far past the least tentative distance once per colour cycle, passes
  // them. 0: off; negative: automatic, 3 for stencils with non-axis offsets and Voronoi cells at
  // least 50 voxels across, else off (swirl 1024^2, 10 seeds: 5.5 -> 3.1 s; radial_shock_3d
  // 128^3, 10 seeds: 4.7 -> 3.5 s; off for the standard bench cases). make_opencl_propagator
  // throws for NaN, infinities and steps in (0, 0.25), whose rounds would multiply. A solve that
  // takes the exact start (below) steps no front, whatever this says.
  double front_step = -1.0;
  // Solves under a uniform diagonal metric start voxels at their nearest seed's exact distance
  // (every voxel of a convex domain, elsewhere those whose quarter brick sees the seed:
  // rvor/nearest_seeds.h), which the relaxations then verify and repair next to bisectors
  // (docs/scheme.md, "Initialisation"); false: from +inf, as for any other metric. Insertions
  // likewise lower the voxels a new seed's exact distance lies below to it (insertion_start_lists);
  // false: they start from the solved field alone.
  bool exact_start = true;
};

// device: "auto", "opencl", "opencl:N" or "pocl" (see devices.h). Throws rvor::Error when the
// device does not exist or lacks what the kernels need (the message suggests --device cpu).
std::unique_ptr<Propagator> make_opencl_propagator(const std::string& device,
                                                   const OpenCLOptions& options = {});

// Builds an OpenCL C program on the device (through the program cache). Throws rvor::Error with
// the build log when it does not compile. Exposed for tests and tools.
void build_opencl_program(const std::string& device, const std::string& source,
                          const std::string& build_options = "");

}  // namespace rvor
