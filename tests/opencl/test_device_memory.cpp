// The check of a canvas's device buffers against what the device holds (a private header of
// host/src/opencl): no device needed.
#include <gtest/gtest.h>

#include <string>

#include "device_memory.h"
#include "rvor/error.h"

namespace rvor::opencl {
namespace {

const DeviceMemory kSmallGpu{"Small GPU", 8'000'000'000, 2'000'000'000};

std::string refusal(std::uint64_t allocated, std::uint64_t size) {
  try {
    require_room_for_buffer(kSmallGpu, allocated, size);
  } catch (const Error& error) {
    return error.what();
  }
  return "";
}

TEST(DeviceMemory, BuffersThatFitPass) {
  EXPECT_EQ(refusal(0, 2'000'000'000), "");
  EXPECT_EQ(refusal(6'000'000'000, 2'000'000'000), "");
}

TEST(DeviceMemory, ABufferOverTheLargestAllocationIsRefusedWithItsSize) {
  const std::string message = refusal(0, 3'700'000'000);
  EXPECT_NE(message.find("a device buffer of 3.7 GB"), std::string::npos) << message;
  EXPECT_NE(message.find("'Small GPU' allocates (2.0 GB)"), std::string::npos) << message;
}

TEST(DeviceMemory, BuffersOverTheGlobalMemoryAreRefusedWithTheTotal) {
  const std::string message = refusal(7'000'000'000, 1'500'000'000);
  EXPECT_NE(message.find("over 8.5 GB of device memory"), std::string::npos) << message;
  EXPECT_NE(message.find("'Small GPU' has (8.0 GB)"), std::string::npos) << message;
}

}  // namespace
}  // namespace rvor::opencl
