// The CPU reference's memory: what a solve allocates is estimated before it starts, and a canvas
// whose solve would not fit in the memory available is refused with the sizes instead of being
// killed by the system halfway.
#include <gtest/gtest.h>

#include <cstdint>
#include <fstream>
#include <string>

#include "reference_solver.h"
#include "rvor/error.h"
#include "rvor/memory_budget.h"
#include "rvor/propagation.h"
#include "support/box_canvas.h"

namespace rvor {
namespace {

std::uint64_t resident_bytes() {
  std::ifstream status("/proc/self/status");
  std::string key;
  std::uint64_t kilobytes = 0;
  while (status >> key) {
    if (key == "VmRSS:" && status >> kilobytes) return kilobytes * 1024;
  }
  return 0;
}

// A tensor per voxel, each one different: a stencil per voxel, the reference's largest array.
Canvas varying_canvas(int resolution) {
  return test::make_box_canvas(3, Vec3(-1, -1, -1), Vec3(1, 1, 1), resolution, [](const Vec3& p) {
    Mat3 G = Mat3::Identity();
    G(0, 0) = 2 + p.x();
    G(0, 1) = G(1, 0) = 0.3 * p.y();
    G(2, 2) = 1.5 + 0.4 * p.z();
    return G;
  });
}

TEST(ReferenceMemory, TheEstimateBoundsWhatASolveTakes) {
  const Canvas canvas = varying_canvas(64);
  const double estimate = detail::ReferenceSolver::estimated_bytes(canvas);
  const std::uint64_t before = resident_bytes();
  ASSERT_GT(before, 0u) << "no VmRSS in /proc/self/status";
  const std::unique_ptr<Propagator> reference = make_reference_propagator();
  VoronoiField field;
  reference->solve(canvas, {Vec3(0, 0, 0), Vec3(0.5, 0.2, -0.3)}, field);
  const double taken = static_cast<double>(resident_bytes() - before);
  std::printf("reference solve of %zu voxels: %.1f B per voxel taken, %.1f estimated\n",
              canvas.active_voxel_count, taken / canvas.active_voxel_count,
              estimate / canvas.active_voxel_count);
  EXPECT_LE(taken, estimate);
}

// The stencils are most of it where tensors vary; a canvas storing one tensor has one stencil.
TEST(ReferenceMemory, OneTensorOneStencil) {
  const Canvas per_slot = varying_canvas(32);
  Canvas uniform;
  uniform.allocate(3, per_slot.voxel_size, per_slot.origin, per_slot.dims, per_slot.brick_origins,
                   Mat3::Identity());
  uniform.active = per_slot.active;
  uniform.finalize();
  const double difference = detail::ReferenceSolver::estimated_bytes(per_slot) -
                            detail::ReferenceSolver::estimated_bytes(uniform);
  EXPECT_NEAR(difference / static_cast<double>(per_slot.active_voxel_count - 1),
              sizeof(detail::VoxelStencil), 1e-9);
}

TEST(ReferenceMemory, ASolveOverTheMemoryAvailableIsAClearError) {
  EXPECT_NO_THROW(require_available_memory("a solve", 1e6, 2000000, ": advice"));
  try {
    require_available_memory("the CPU reference's solve of 5 active voxels", 3e9, 2000000000,
                             ": use an OpenCL device");
    FAIL() << "no error";
  } catch (const Error& error) {
    EXPECT_STREQ(error.what(),
                 "the CPU reference's solve of 5 active voxels needs ~3 GB, more than the 2 GB of "
                 "memory available: use an OpenCL device");
  }
  EXPECT_GT(available_memory(), 0u);
}

}  // namespace
}  // namespace rvor
