#pragma once
// OpenCL runtime of rvor (internal): device discovery and selection, one context per device, a
// program cache, and the translation of every OpenCL failure into rvor::Error naming the call.
#define CL_HPP_ENABLE_EXCEPTIONS
#include <CL/opencl.hpp>

#include <string>
#include <vector>

#include "rvor/devices.h"

namespace rvor::opencl {

struct Device {
  cl::Platform platform;
  cl::Device device;
  OpenCLDeviceInfo info;
};

std::vector<Device> enumerate_devices();

// Resolves "auto", "opencl", "opencl:N", "pocl". Throws rvor::Error for other names, for a
// missing device, and for a device lacking the kernels' requirements.
Device select_device(const std::string& name);

// One context per device, shared by every propagator on it.
cl::Context context_for(const Device& device);

// Builds (once per context, device, source and options) and returns the program; throws
// rvor::Error with the build log when compilation fails.
cl::Program build_program(const cl::Context& context, const cl::Device& device,
                          const std::string& source, const std::string& options);

// "CL_OUT_OF_RESOURCES" etc.
std::string status_name(cl_int status);

// Turns an OpenCL exception into rvor::Error: "OpenCL call clXxx failed: CL_... (code) while
// <doing>".
[[noreturn]] void throw_opencl_error(const cl::Error& error, const std::string& doing);

}  // namespace rvor::opencl
