// The check of a canvas's device buffers against what the device holds (a private header of
// host/src/opencl): no device needed.
#include <gtest/gtest.h>

#include <string>

#include "device_memory.h"
#include "rvor/error.h"

namespace rvor::opencl {
namespace {

constexpr std::uint64_t kMiB = 1 << 20;
const DeviceMemory kSmallGpu{"Small GPU", 8192 * kMiB, 2048 * kMiB};

std::string refusal(std::uint64_t allocated, std::uint64_t size) {
  try {
    require_room_for_buffer(kSmallGpu, allocated, size);
  } catch (const Error& error) {
    return error.what();
  }
  return "";
}

TEST(DeviceMemory, BuffersThatFitPass) {
  EXPECT_EQ(refusal(0, 2048 * kMiB), "");
  EXPECT_EQ(refusal(6144 * kMiB, 2048 * kMiB), "");
}

TEST(DeviceMemory, ABufferOverTheLargestAllocationIsRefusedWithItsSize) {
  const std::string message = refusal(0, 3529 * kMiB);
  EXPECT_NE(message.find("a device buffer of 3529 MiB"), std::string::npos) << message;
  EXPECT_NE(message.find("'Small GPU' allocates (2048 MiB)"), std::string::npos) << message;
}

TEST(DeviceMemory, BuffersOverTheGlobalMemoryAreRefusedWithTheTotal) {
  const std::string message = refusal(7000 * kMiB, 1500 * kMiB);
  EXPECT_NE(message.find("over 8500 MiB of device memory"), std::string::npos) << message;
  EXPECT_NE(message.find("'Small GPU' has (8192 MiB)"), std::string::npos) << message;
}

}  // namespace
}  // namespace rvor::opencl
