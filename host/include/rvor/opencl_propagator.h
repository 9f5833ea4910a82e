#pragma once
// The OpenCL propagation engine (docs/scheme.md as kernels, block Fast Iterative Method on bricks).
#include <memory>
#include <string>

#include "rvor/propagation.h"

namespace rvor {

enum class RelaxationVariant {
  automatic,     // brick_sweep on CPU devices, voxel_jacobi on GPUs
  brick_sweep,   // a work-item sweeps a whole brick Gauss-Seidel (CPU-friendly)
  voxel_jacobi,  // a work-group per brick, a work-item per voxel, Jacobi in local memory (GPU)
};

struct OpenCLOptions {
  RelaxationVariant variant = RelaxationVariant::automatic;
  int max_sweeps = 4;  // brick_sweep: sweeps per brick and round (of 1/2/4/64, 4 measured best)
  int jacobi_iterations = 8;  // voxel_jacobi: inner iterations per round
  // Front ordering: each round relaxes only the pending bricks whose key (smallest changed value
  // that made them pending) is within front_band brick crossings (8 voxels along the cheapest
  // metric direction, median over the canvas) of the smallest key. 0: relax every pending brick.
  // (Measured before brick colouring, 192^3, 1000 seeds, euclidean: 16.3 updates per voxel without,
  // 13.5 with 0.5.)
  double front_band = 0.5;
  // Relax one brick colour (parities of the brick coordinates, 2^d colours) per round, so that a
  // brick reads its neighbours' fresh values (96^3, 1000 seeds: euclidean 12.4 -> 10.1 updates per
  // voxel, radial_shock_3d 20.5 -> 13.7).
  bool brick_colouring = true;
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
