// The CPU reference's memory: what a solve allocates is estimated before it starts, and a canvas
// whose solve would not fit the budget (or, without one, the memory available) is refused with
// the sizes instead of being killed by the system halfway.
#include <gtest/gtest.h>

#include <sys/resource.h>
#include <unistd.h>

#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <fstream>
#include <functional>
#include <string>

#include "reference_solver.h"
#include "rvor/error.h"
#include "rvor/memory_budget.h"
#include "rvor/propagation.h"
#include "rvor/seeds.h"
#include "slot_ranges.h"
#include "support/box_canvas.h"
#include "support/error_of.h"
#include "support/limited_child.h"

namespace rvor {
namespace {

using test::exit_code_in_a_child;

// A field of /proc/self/status in bytes (0 when absent).
std::uint64_t status_bytes(const std::string& field) {
  std::ifstream status("/proc/self/status");
  std::string key;
  std::uint64_t kilobytes = 0;
  while (status >> key)
    if (key == field + ":" && status >> kilobytes) return kilobytes * 1024;
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

// The same voxels in the uniform form (one tensor, so one stencil).
Canvas uniform_canvas(const Canvas& like) {
  Canvas uniform;
  uniform.allocate(3, like.voxel_size, like.origin, like.dims, like.brick_origins,
                   Mat3::Identity());
  uniform.active = like.active;
  uniform.finalize();
  return uniform;
}

// The peak of the solve (VmHWM, reset to the resident size first), with many seeds: the queue
// then holds stale entries of many label changes. Where tensors vary the stencils are most of it;
// a canvas in the uniform form has one, and its estimate is about half (161 B per voxel against
// 305).
TEST(ReferenceMemory, TheEstimateCoversTheSolvesPeak) {
  const Canvas varying = varying_canvas(64);
  const Canvas uniform = uniform_canvas(varying);
  const std::vector<Vec3> seeds = random_seeds(varying, 2000, 1);
  for (const Canvas* canvas : {&varying, &uniform}) {
    const double estimate = detail::ReferenceSolver::estimated_bytes(*canvas);
    std::ofstream("/proc/self/clear_refs") << "5";  // VmHWM := VmRSS
    const std::uint64_t before = status_bytes("VmRSS");
    ASSERT_GT(before, 0u) << "no VmRSS in /proc/self/status";
    const std::unique_ptr<Propagator> reference = make_reference_propagator();
    VoronoiField field;
    reference->solve(*canvas, seeds, field);
    const std::uint64_t peak = status_bytes("VmHWM");
    ASSERT_GE(peak, before) << "VmHWM was not reset (no /proc/self/clear_refs?)";
    const double taken = static_cast<double>(peak - before);
    const double voxels = static_cast<double>(canvas->active_voxel_count);
    std::printf(
        "reference solve of %zu voxels (%s), %zu seeds: peak %.1f B per voxel, %.1f "
        "estimated\n",
        canvas->active_voxel_count, canvas == &uniform ? "one tensor" : "tensors per slot",
        seeds.size(), taken / voxels, estimate / voxels);
    EXPECT_LE(taken, estimate);
  }
}

TEST(ReferenceMemory, ASolveOverTheBudgetIsRefusedBeforeItAllocates) {
  const Canvas canvas = varying_canvas(32);
  const std::unique_ptr<Propagator> reference = make_reference_propagator();
  reference->set_memory_budget(1000000);
  VoronoiField field;
  const std::string message =
      test::error_of([&] { reference->solve(canvas, {Vec3(0, 0, 0)}, field); });
  EXPECT_NE(message.find("the CPU reference's solve of 32768 active voxels needs ~"),
            std::string::npos)
      << message;
  EXPECT_NE(message.find("over the memory budget of 977 KiB (--memory-budget)"), std::string::npos)
      << message;
  reference->set_memory_budget(0);  // the memory available
  EXPECT_NO_THROW(reference->solve(canvas, {Vec3(0, 0, 0)}, field));
  EXPECT_GT(available_memory(), 0u);
}

// Threads that cannot start (here: no address space left for their stacks) leave their ranges to
// the calling thread; a std::vector of std::thread called std::terminate, and the process died.
TEST(SlotRanges, ThreadsThatCannotStartLeaveTheirWorkToTheCaller) {
  // 2 MiB above what the process maps now: no 8 MiB thread stack fits.
  EXPECT_EQ(exit_code_in_a_child(
                rlim_t{2} << 20,
                [] {
                  std::vector<int> visited(100000, 0);
                  for_slot_ranges(visited.size(), 8,
                                  [&](unsigned, std::size_t begin, std::size_t end) {
                                    for (std::size_t s = begin; s < end; ++s) ++visited[s];
                                  });
                  return std::all_of(visited.begin(), visited.end(), [](int v) { return v == 1; });
                }),
            0)
      << "1: a range left undone or done twice; 134: aborted";
}

// What the budget cannot foresee (here: a budget set far above what the process may map) fails as
// rvor::Error naming what ran out, not as a bare std::bad_alloc past the library boundary.
TEST(ReferenceMemory, AnAllocationTheBudgetPassedFailsAsANamedError) {
  const Canvas canvas = varying_canvas(96);  // ~270 MB of stencils and queue
  const std::vector<Vec3> seeds = random_seeds(canvas, 100, 1);
  EXPECT_EQ(exit_code_in_a_child(rlim_t{16} << 20,
                                 [&] {
                                   const std::unique_ptr<Propagator> reference =
                                       make_reference_propagator();
                                   reference->set_memory_budget(std::uint64_t{1} << 40);
                                   VoronoiField field;
                                   try {
                                     reference->solve(canvas, seeds, field);
                                   } catch (const Error& error) {
                                     return std::string(error.what())
                                                .find(
                                                    "out of memory solving on the CPU reference "
                                                    "(std::bad_alloc)") == 0;
                                   }
                                   return false;
                                 }),
            0)
      << "1: solved, or another message; 2: a std::bad_alloc (or another exception) left solve()";
}

// The default budget follows a limit on the process below its RAM (here RLIMIT_AS; a container's
// control group likewise): with 75% of RAM it passed canvases the limit then failed (bad_alloc).
TEST(MemoryBudget, TheDefaultFollowsTheProcesssLimit) {
  EXPECT_EQ(exit_code_in_a_child(rlim_t{4} << 30,
                                 [] {
                                   rlimit limit{};
                                   getrlimit(RLIMIT_AS, &limit);
                                   const auto bytes = static_cast<double>(limit.rlim_cur);
                                   return static_cast<double>(default_memory_budget()) <=
                                              0.75 * bytes + 1 &&
                                          static_cast<double>(available_memory()) <= bytes;
                                 }),
            0);
}

// Sizes in the budget's binary units, three digits, and whole from 1000 of a unit on ("1000M" was
// shown as "1e+03 MiB").
TEST(MemoryBudget, SizesAreShownInBinaryUnits) {
  EXPECT_EQ(format_bytes(512), "512 B");
  EXPECT_EQ(format_bytes(1000), "1000 B");
  EXPECT_EQ(format_bytes(1024), "1 KiB");
  EXPECT_EQ(format_bytes(200.0 * (1 << 20)), "200 MiB");
  EXPECT_EQ(format_bytes(1000.0 * (1 << 20)), "1000 MiB");
  EXPECT_EQ(format_bytes(1023.4 * (1 << 20)), "1023 MiB");
  EXPECT_EQ(format_bytes(1.5 * (1 << 30)), "1.5 GiB");
}

}  // namespace
}  // namespace rvor
