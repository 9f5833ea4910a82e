#pragma once
// Compute devices rvor can run propagations on: the CPU reference and every OpenCL device.
// Device names (the --device option, the RVOR_DEVICE environment variable):
//   "cpu"       the sequential CPU reference solver
//   "auto"      the first OpenCL GPU, else the first OpenCL CPU device
//   "opencl"    the first OpenCL device; "opencl:N" the N-th in list_opencl_devices() order
//   "pocl"      the first device of the Portable Computing Language platform
#include <cstdint>
#include <string>
#include <vector>

#include "rvor/error.h"

namespace rvor {

struct OpenCLDeviceInfo {
  int index = 0;         // N of "opencl:N"
  std::string platform;  // platform name, e.g. "Portable Computing Language"
  std::string name;      // device name
  std::string version;   // CL_DEVICE_VERSION
  std::string driver;    // CL_DRIVER_VERSION
  bool is_gpu = false;
  bool is_cpu = false;
  unsigned compute_units = 0;
  std::uint64_t global_memory_bytes = 0;
  std::uint64_t largest_buffer_bytes = 0;  // CL_DEVICE_MAX_MEM_ALLOC_SIZE: one buffer at most
  std::string missing_requirement;         // empty when rvor's kernels can run on it
};

// Every device of every OpenCL platform (empty when there is no OpenCL runtime or platform).
std::vector<OpenCLDeviceInfo> list_opencl_devices();

// The directory PoCL keeps its compiled kernels in: $POCL_CACHE_DIR, else
// $XDG_CACHE_HOME/pocl/kcache, else $HOME/.cache/pocl/kcache, else /tmp/pocl/kcache. Named in
// errors, since a damaged one fails (or aborts) runs that its removal mends.
std::string pocl_kernel_cache_directory();
// Why PoCL cannot use that directory (not a directory, not writable: every kernel build fails),
// or "" where it can. Creates the directory where it is missing, as PoCL would.
std::string pocl_kernel_cache_problem();

// The device name for library users: $RVOR_DEVICE when set and non-empty, else "auto".
std::string default_device_name();
// Whether default_device_name() is $RVOR_DEVICE's value.
bool device_name_from_environment();

// use(default_device_name()); an rvor::Error from it about a name taken from $RVOR_DEVICE leaves
// with "RVOR_DEVICE=<name>: " before its message, so that the user knows where the name came from
// (make_default_propagator, and `rvor` without --device).
template <typename Use>
auto with_default_device(Use&& use) -> decltype(use(std::string())) {
  const std::string name = default_device_name();
  if (!device_name_from_environment()) return use(name);
  try {
    return use(name);
  } catch (const Error& error) {
    throw Error("RVOR_DEVICE=" + name + ": " + error.what());
  }
}

// Throws rvor::Error unless `name` has one of the forms above.
void check_device_name(const std::string& name);
// Throws the rvor::Error a propagator for `name` would (a malformed name, no matching OpenCL
// device, a device that cannot run the kernels), without building one.
void require_device(const std::string& name);

}  // namespace rvor
