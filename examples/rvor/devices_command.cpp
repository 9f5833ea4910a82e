// `rvor devices`: the compute devices rvor can use, in the order "opencl:N" counts them.
#include <algorithm>
#include <iostream>

#include "commands.h"
#include "rvor/devices.h"
#include "rvor/error.h"
#include "rvor/spec_text.h"

namespace rvor::cli {

namespace {

// PoCL's kernel cache, where a PoCL device is listed: one it cannot write fails every kernel build,
// which the list alone would not show (the device looks usable).
void print_pocl_cache(const std::vector<OpenCLDeviceInfo>& devices) {
  const bool pocl = std::any_of(devices.begin(), devices.end(), [](const OpenCLDeviceInfo& d) {
    return d.platform.find("Portable Computing Language") != std::string::npos;
  });
  if (!pocl) return;
  const std::string problem = pocl_kernel_cache_problem();
  std::cout << "PoCL kernel cache: " << printable_text(pocl_kernel_cache_directory())
            << (problem.empty() ? "" : " (unusable: " + printable_text(problem) + ")") << "\n";
}

void print_devices() {
  std::cout << "cpu        CPU reference solver (sequential, double precision)\n";
  const std::vector<OpenCLDeviceInfo> devices = list_opencl_devices();
  for (const OpenCLDeviceInfo& d : devices) {
    std::cout << "opencl:" << d.index << "   " << d.name << " ["
              << (d.is_gpu   ? "GPU"
                  : d.is_cpu ? "CPU"
                             : "other")
              << ", " << d.compute_units << " compute units, " << (d.global_memory_bytes >> 20)
              << " MiB, buffers up to " << (d.largest_buffer_bytes >> 20) << " MiB] " << d.platform
              << ", " << d.version << ", driver " << d.driver;
    if (!d.missing_requirement.empty()) std::cout << " (unusable: " << d.missing_requirement << ")";
    std::cout << "\n";
  }
  if (devices.empty()) std::cout << "(no OpenCL device found: use --device cpu)\n";
  print_pocl_cache(devices);
  const std::string chosen = default_device_name();
  std::cout << "default: " << printable_text(chosen) << " (set RVOR_DEVICE to change it)";
  try {
    require_device(chosen);
  } catch (const Error& error) {
    std::cout << ", but it cannot be used: " << printable_text(error.what());
  }
  std::cout << "\n";
}

}  // namespace

void add_devices_command(CLI::App& app) {
  CLI::App* command = app.add_subcommand("devices", "List the compute devices rvor can use");
  command->footer(
      "Prints one line per device: cpu (the reference solver), then opencl:N for every OpenCL\n"
      "device (name, kind, compute units, memory, largest buffer, platform, driver; why it cannot\n"
      "run the kernels, if so), PoCL's kernel cache where a PoCL device is listed (and why PoCL\n"
      "cannot use it, if so), and the default (--device of voronoi and bench: $RVOR_DEVICE,\n"
      "else auto).\n"
      "Example:\n"
      "  rvor devices && RVOR_DEVICE=opencl:1 rvor voronoi --domain rect:-1,-1,1,1 "
      "--random-seeds 10");
  command->callback(print_devices);
}

}  // namespace rvor::cli
