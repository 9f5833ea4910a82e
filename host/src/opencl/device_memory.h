#pragma once
// What a device can hold, and the check of each buffer a canvas upload makes against it
// (internal): a canvas too big for the device is an error that gives the sizes, not an
// allocation failure at some later command (drivers allocate lazily) or a crash.
#include <cstdint>
#include <string>

#include "opencl_runtime.h"

namespace rvor::opencl {

struct DeviceMemory {
  std::string device;                      // its name, for messages
  std::uint64_t global_bytes = 0;          // CL_DEVICE_GLOBAL_MEM_SIZE
  std::uint64_t largest_buffer_bytes = 0;  // CL_DEVICE_MAX_MEM_ALLOC_SIZE
};

// Of the context's first device (the engine makes a context per device).
DeviceMemory device_memory(const cl::Context& context);

// Throws rvor::Error unless one more buffer of `size` bytes fits the device beside the
// `allocated` bytes of the canvas's earlier buffers.
void require_room_for_buffer(const DeviceMemory& memory, std::uint64_t allocated,
                             std::uint64_t size);

}  // namespace rvor::opencl
