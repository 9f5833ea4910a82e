// Device buffers on transparent huge pages (host/src/opencl/host_pages.h, internal): they hold
// what they were given, the device reads and writes them, their pages go when the buffer goes,
// and an engine whose per-voxel buffers take that path (4 MiB and more) matches the reference.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdint>
#include <cstdlib>
#include <fstream>
#include <numeric>
#include <optional>
#include <string>
#include <vector>

#include "device_canvas.h"
#include "host_pages.h"
#include "opencl/opencl_test_support.h"
#include "opencl_runtime.h"

namespace rvor {
namespace {

long resident_bytes() {
  std::ifstream statm("/proc/self/statm");
  long size = 0, resident = 0;
  statm >> size >> resident;
  return resident * sysconf(_SC_PAGESIZE);
}

// The PoCL device, or none and why.
std::optional<opencl::Device> pocl_device(std::string& why) {
  try {
    return opencl::select_device("pocl");
  } catch (const Error& e) {
    why = e.what();
    return std::nullopt;
  }
}

// The PoCL device's context and a queue on it; the test is skipped without one.
class HugePageBuffers : public ::testing::Test {
 protected:
  void SetUp() override {
    std::string why;
    const std::optional<opencl::Device> device = pocl_device(why);
    if (!device) GTEST_SKIP() << "no usable OpenCL device: " << why;
    context = opencl::context_for(*device);
    ASSERT_TRUE(opencl::device_uses_host_memory(context));
    queue = cl::CommandQueue(context, device->device);
  }

  cl::Context context;
  cl::CommandQueue queue;
};

TEST_F(HugePageBuffers, HoldTheirDataTakeDeviceWritesAndReleaseTheirPages) {
  const std::size_t count = (std::size_t{32} << 20) / sizeof(cl_uint);
  const std::size_t bytes = count * sizeof(cl_uint);
  std::vector<cl_uint> data(count), back(count);
  std::iota(data.begin(), data.end(), 1u);
  const long before = resident_bytes();
  for (int round = 0; round < 16; ++round) {  // 512 MiB in all if the pages were kept
    cl::Buffer buffer = opencl::huge_page_buffer(context, CL_MEM_READ_WRITE, bytes, data.data());
    queue.enqueueReadBuffer(buffer, CL_TRUE, 0, bytes, back.data());
    ASSERT_EQ(back, data) << "round " << round;
    queue.enqueueFillBuffer(buffer, cl_uint(7), 0, bytes);
    queue.enqueueReadBuffer(buffer, CL_TRUE, 0, bytes, back.data());
    ASSERT_EQ(back, std::vector<cl_uint>(count, 7u)) << "round " << round;
    cl::Buffer zeros = opencl::huge_page_buffer(context, CL_MEM_READ_ONLY, bytes, nullptr);
    queue.enqueueReadBuffer(zeros, CL_TRUE, 0, bytes, back.data());
    ASSERT_EQ(back, std::vector<cl_uint>(count, 0u)) << "round " << round;
  }
  EXPECT_LT(resident_bytes() - before, long{128} << 20) << "the pages of released buffers stay";
}

// A vector filled on huge pages (HugePageAllocator) becomes a buffer without a copy: the device
// reads it and writes into its very memory, and the pages go when the buffer goes, not with the
// moved-from vector.
TEST_F(HugePageBuffers, AnAdoptedVectorIsTheBufferAndLeavesWithIt) {
  const std::size_t count = (std::size_t{32} << 20) / sizeof(cl_uint);
  std::vector<cl_uint> expected(count), back(count);
  std::iota(expected.begin(), expected.end(), 1u);
  const long before = resident_bytes();
  for (int round = 0; round < 16; ++round) {  // 512 MiB in all if the pages were kept
    opencl::HugePageVector<cl_uint> data(expected.begin(), expected.end());
    const cl_uint* memory = data.data();
    ASSERT_EQ(reinterpret_cast<std::uintptr_t>(memory) % (std::uintptr_t{2} << 20), 0u);
    const cl::Buffer buffer = opencl::adopting_buffer(context, CL_MEM_READ_WRITE, std::move(data));
    queue.enqueueReadBuffer(buffer, CL_TRUE, 0, count * sizeof(cl_uint), back.data());
    ASSERT_EQ(back, expected) << "round " << round;
    queue.enqueueFillBuffer(buffer, cl_uint(0xC0FFEE), 0, count * sizeof(cl_uint));
    queue.finish();
    ASSERT_EQ(std::vector<cl_uint>(memory, memory + count), std::vector<cl_uint>(count, 0xC0FFEE))
        << "round " << round << ": the device wrote elsewhere";
  }
  EXPECT_LT(resident_bytes() - before, long{128} << 20) << "the pages of released buffers stay";
}

// 84^3 slots: the state buffer (8 B per slot) is above 4 MiB; radial_shock_3d at 64^3: its
// per-voxel stencil weights (24 B per slot) and offsets (18 B) are.
TEST_F(HugePageBuffers, EnginesOnThemMatchTheReference) {
  REQUIRE_ENGINE_WITH(OpenCLOptions{});
  const Canvas uniform = test::domain_canvas("box:-1,-1,-1,1,1,1", "euclidean", 84);
  ASSERT_GE(uniform.slot_count() * sizeof(cl_ulong), std::size_t{4} << 20);
  test::expect_matches_reference(*engine, uniform, test::seeds_in(uniform, 40, 5));
  const Canvas varying = test::domain_canvas("box:1,1,1,11,11,11", "radial_shock_3d", 64);
  ASSERT_GE(varying.slot_count() * 6 * sizeof(float), std::size_t{4} << 20);
  test::expect_matches_reference(*engine, varying, test::seeds_in(varying, 40, 5));
}

// RVOR_POISON_DEVICE_BUFFERS=1 (test_opencl_poisoned_buffers) fills new working buffers, small
// and on huge pages alike, with 0xA5 bytes; the buffers uploaded from the canvas keep its data.
class PoisonedBuffers : public HugePageBuffers {};

TEST_F(PoisonedBuffers, NewWorkingBuffersHoldThePattern) {
  const Canvas canvas = test::domain_canvas("box:-1,-1,-1,1,1,1", "euclidean", 84);
  ASSERT_EQ(setenv("RVOR_POISON_DEVICE_BUFFERS", "1", 1), 0);
  const opencl::DeviceCanvas d = opencl::upload_canvas(context, canvas, 8);
  unsetenv("RVOR_POISON_DEVICE_BUFFERS");
  ASSERT_GE(canvas.slot_count() * sizeof(cl_ulong), std::size_t{4} << 20);  // on huge pages
  std::vector<cl_ulong> state(canvas.slot_count());
  std::vector<cl_uint> changed(canvas.slot_count()), counts(2);
  queue.enqueueReadBuffer(d.state, CL_TRUE, 0, state.size() * sizeof(cl_ulong), state.data());
  queue.enqueueReadBuffer(d.changed, CL_TRUE, 0, changed.size() * sizeof(cl_uint), changed.data());
  queue.enqueueReadBuffer(d.round_counts, CL_TRUE, 0, 2 * sizeof(cl_uint), counts.data());
  EXPECT_EQ(state, std::vector<cl_ulong>(state.size(), 0xA5A5A5A5A5A5A5A5ull));
  EXPECT_EQ(changed, std::vector<cl_uint>(changed.size(), 0xA5A5A5A5u));
  EXPECT_EQ(counts, std::vector<cl_uint>(2, 0xA5A5A5A5u));
  std::vector<cl_uint> activity(1);
  queue.enqueueReadBuffer(d.activity, CL_TRUE, 0, sizeof(cl_uint), activity.data());
  EXPECT_EQ(activity[0], 0xFFFFFFFFu);  // the canvas's first 32 slots, all active
}

}  // namespace
}  // namespace rvor
