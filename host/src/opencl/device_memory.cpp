#include "device_memory.h"

#include "rvor/error.h"

namespace rvor::opencl {
namespace {

// In MiB, as `rvor devices` lists the devices' memory.
std::string mebibytes(std::uint64_t bytes) {
  return std::to_string((bytes + (1u << 20) - 1) >> 20) + " MiB";
}

}  // namespace

DeviceMemory device_memory(const cl::Context& context) {
  const cl::Device device = context.getInfo<CL_CONTEXT_DEVICES>().at(0);
  return {device.getInfo<CL_DEVICE_NAME>(), device.getInfo<CL_DEVICE_GLOBAL_MEM_SIZE>(),
          device.getInfo<CL_DEVICE_MAX_MEM_ALLOC_SIZE>()};
}

void require_room_for_buffer(const DeviceMemory& memory, std::uint64_t allocated,
                             std::uint64_t size) {
  const std::string advice =
      ": use a coarser resolution, a smaller domain, a device with more memory (`rvor devices` "
      "lists them) or --device cpu (the CPU reference solver, in host memory)";
  if (size > memory.largest_buffer_bytes)
    throw Error("the canvas needs a device buffer of " + mebibytes(size) +
                ", over the largest one OpenCL device '" + memory.device + "' allocates (" +
                mebibytes(memory.largest_buffer_bytes) + ")" + advice);
  if (allocated + size > memory.global_bytes)
    throw Error("the canvas needs over " + mebibytes(allocated + size) +
                " of device memory, more than OpenCL device '" + memory.device + "' has (" +
                mebibytes(memory.global_bytes) + ")" + advice);
}

}  // namespace rvor::opencl
