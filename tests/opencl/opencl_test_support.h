#pragma once
// Shared by the OpenCL engine tests: comparison against the CPU reference (docs/scheme.md:
// distances to a relative 1e-4, labels identical except at ties) and random seeds.
#include <gtest/gtest.h>

#include <memory>
#include <string>
#include <vector>

#include "rvor/canvas.h"
#include "rvor/error.h"
#include "rvor/opencl_propagator.h"
#include "rvor/propagation.h"

namespace rvor::test {

constexpr double kRelativeTolerance = 1e-4;
constexpr int kTieReach = 3;  // voxels: one step of a tie-broken label's effect on values

// The device the engine tests run on: $RVOR_TEST_DEVICE (e.g. opencl:1 for a GPU, the names of
// --device), else PoCL, which CI has.
std::string engine_device();
// Whether $RVOR_TEST_DEVICE names it: then a missing device fails the tests instead of skipping
// them, so that a run meant for a GPU cannot pass by testing nothing.
bool engine_device_requested();

// Declares `engine` on engine_device() with the default options but `variant`, or skips the test
// (with the reason) when that device is not there.
#define REQUIRE_ENGINE(variant) REQUIRE_ENGINE_WITH(test::with_variant(variant))
#define REQUIRE_ENGINE_WITH(options)                                                 \
  std::unique_ptr<Propagator> engine;                                                \
  try {                                                                              \
    engine = make_opencl_propagator(test::engine_device(), options);                 \
  } catch (const Error& e) {                                                         \
    if (test::engine_device_requested()) FAIL() << "RVOR_TEST_DEVICE: " << e.what(); \
    GTEST_SKIP() << "no usable OpenCL device: " << e.what();                         \
  }

inline OpenCLOptions with_variant(RelaxationVariant variant) {
  OpenCLOptions options;
  options.variant = variant;
  return options;
}

// The variants devices choose by default (voxel_phases on GPUs, brick_lanes on CPUs), the GPU's
// first: on a GPU test device brick_lanes crawls (a work-item per 8 bricks), and a run with a
// time limit there should have checked the GPU's own variant before it.
constexpr RelaxationVariant kDefaultVariants[] = {RelaxationVariant::voxel_phases,
                                                  RelaxationVariant::brick_lanes};

// The canvas of a parse_domain() spec with an analytic metric (make_analytic_metric spec).
Canvas domain_canvas(const std::string& domain, const std::string& metric, int resolution);

// `count` random seeds inside the canvas's active voxels (fewer if the domain is too thin).
std::vector<Vec3> seeds_in(const Canvas& canvas, int count, unsigned rng_seed);

// Uniformly random points in the box shrunk by 5% per side (z = 0 in 2D).
std::vector<Vec3> random_points(const Vec3& lo, const Vec3& hi, int dimension, int count,
                                unsigned rng_seed);

// Distances agree to kRelativeTolerance (relative, or against one voxel's metric length for
// distances below it) except downstream of a voxel the two fields label differently: reached from
// it by steps of at most kTieReach voxels through voxels that differ. Label differences (ties) and
// such voxels must be rare.
void expect_same_field(const Canvas& canvas, const VoronoiField& expected,
                       const VoronoiField& actual);

// Solves with seeds[0], then inserts the others one at a time.
VoronoiField insert_one_by_one(Propagator& engine, const Canvas& canvas,
                               const std::vector<Vec3>& seeds);

// Solves with the engine and with the CPU reference and compares the fields.
void expect_matches_reference(Propagator& engine, const Canvas& canvas,
                              const std::vector<Vec3>& seeds);

}  // namespace rvor::test
