#include "opencl_runtime.h"

#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cstdlib>
#include <filesystem>
#include <functional>
#include <map>
#include <mutex>
#include <tuple>
#include <utility>

#include "rvor/devices.h"
#include "rvor/error.h"

namespace rvor::opencl {

namespace {

constexpr const char* kFallbackHint = " (use --device cpu for the CPU reference solver)";

bool has_extension(const cl::Device& device, const std::string& extension) {
  const std::string extensions = device.getInfo<CL_DEVICE_EXTENSIONS>();
  return (" " + extensions + " ").find(" " + extension + " ") != std::string::npos;
}

// What the kernels need: 64-bit atomics (packed (distance, label) words, update counters).
std::string missing_requirement(const cl::Device& device) {
  for (const char* extension : {"cl_khr_int64_base_atomics", "cl_khr_int64_extended_atomics"})
    if (!has_extension(device, extension)) return std::string("no ") + extension;
  return {};
}

OpenCLDeviceInfo describe(const cl::Platform& platform, const cl::Device& device, int index) {
  OpenCLDeviceInfo info;
  info.index = index;
  info.platform = platform.getInfo<CL_PLATFORM_NAME>();
  info.name = device.getInfo<CL_DEVICE_NAME>();
  info.version = device.getInfo<CL_DEVICE_VERSION>();
  info.driver = device.getInfo<CL_DRIVER_VERSION>();
  const cl_device_type type = device.getInfo<CL_DEVICE_TYPE>();
  info.is_gpu = (type & CL_DEVICE_TYPE_GPU) != 0;
  info.is_cpu = (type & CL_DEVICE_TYPE_CPU) != 0;
  info.compute_units = device.getInfo<CL_DEVICE_MAX_COMPUTE_UNITS>();
  info.global_memory_bytes = device.getInfo<CL_DEVICE_GLOBAL_MEM_SIZE>();
  info.largest_buffer_bytes = device.getInfo<CL_DEVICE_MAX_MEM_ALLOC_SIZE>();
  info.missing_requirement = missing_requirement(device);
  return info;
}

// PoCL keeps compiled kernels in POCL_CACHE_DIR (else under $XDG_CACHE_HOME or ~/.cache). It
// aborts the process on an empty value, lists no device when it cannot create the directory, and
// fails every program build when the path is a file: empty is refused before the ICD loader
// starts PoCL, the others are named in the errors they cause (pocl_cache_problem).
void refuse_empty_pocl_cache_dir() {
  const char* value = std::getenv("POCL_CACHE_DIR");
  if (value && !*value)
    throw Error(
        "POCL_CACHE_DIR is set but empty (PoCL would abort): unset it, or set it to a "
        "writable directory for PoCL's compiled kernels");
}

// PoCL 3.1's pthread device sizes its thread pool by POCL_MAX_PTHREAD_COUNT, read as a C integer:
// a negative count crashes it (SIGSEGV) while it starts, before any OpenCL call returns.
void refuse_negative_pocl_thread_count() {
  const char* value = std::getenv("POCL_MAX_PTHREAD_COUNT");
  if (!value || std::strtol(value, nullptr, 0) >= 0) return;
  throw Error(std::string("POCL_MAX_PTHREAD_COUNT=") + value +
              " is negative (PoCL would crash): unset it, or set it to the number of threads "
              "PoCL's CPU device may use");
}

// The directory PoCL keeps its compiled kernels in, and what chose it (PoCL 3.1's
// pocl_cache_init_topdir): POCL_CACHE_DIR, else $XDG_CACHE_HOME/pocl/kcache, else
// $HOME/.cache/pocl/kcache, else /tmp/pocl/kcache. A service account's home (/nonexistent) or a
// /tmp/pocl another user made leaves PoCL with no device, as a bad POCL_CACHE_DIR does.
std::pair<std::string, std::string> pocl_cache_dir() {
  if (const char* value = std::getenv("POCL_CACHE_DIR"); value && *value)
    return {value, "POCL_CACHE_DIR=" + std::string(value)};
  if (const char* xdg = std::getenv("XDG_CACHE_HOME"); xdg && *xdg)
    return {std::string(xdg) + "/pocl/kcache",
            "PoCL's kernel cache " + std::string(xdg) + "/pocl/kcache (from XDG_CACHE_HOME)"};
  if (const char* home = std::getenv("HOME"))
    return {std::string(home) + "/.cache/pocl/kcache",
            "PoCL's kernel cache " + std::string(home) + "/.cache/pocl/kcache (from HOME)"};
  return {"/tmp/pocl/kcache", "PoCL's kernel cache /tmp/pocl/kcache (HOME is unset)"};
}

// "POCL_CACHE_DIR=... is not a writable directory ..." when PoCL's cache directory (set or its
// default) is one it cannot use, else "". Called once something failed, or by `rvor devices`: a
// missing directory is created, as PoCL would have.
std::string pocl_cache_problem() {
  const auto [path, named] = pocl_cache_dir();
  std::error_code error;
  std::filesystem::create_directories(path, error);
  if (std::filesystem::is_directory(path, error) && access(path.c_str(), W_OK | X_OK) == 0)
    return "";
  const bool set = named.rfind("POCL_CACHE_DIR=", 0) == 0;
  return named + " is not a writable directory, and PoCL needs one for its compiled kernels" +
         (set ? "" : " (set POCL_CACHE_DIR to a writable directory)");
}

// pocl_cache_problem() as a clause of an error message ("; ..."), or "".
std::string pocl_cache_clause() {
  const std::string problem = pocl_cache_problem();
  return problem.empty() ? "" : "; " + problem;
}

// "; set in the environment: POCL_DEVICES=basic, ..." for the variables that steer which
// platforms and devices the ICD loader and PoCL offer, where no device was found: a stale one
// empties the list with no other sign.
std::string discovery_variables() {
  std::string text;
  for (const char* name :
       {"OCL_ICD_VENDORS", "OCL_ICD_FILENAMES", "OPENCL_VENDOR_PATH", "POCL_DEVICES"})
    if (const char* value = std::getenv(name))
      text += std::string(text.empty() ? "; set in the environment: " : ", ") + name + "=" + value;
  return text;
}

std::vector<cl::Platform> platforms_or_none() {
  refuse_empty_pocl_cache_dir();
  refuse_negative_pocl_thread_count();
  std::vector<cl::Platform> platforms;
  try {
    cl::Platform::get(&platforms);
  } catch (const cl::Error& e) {
    // The ICD loader reports "no platform" as an error; that is an empty list to us.
    if (e.err() == CL_PLATFORM_NOT_FOUND_KHR) return {};
    throw_opencl_error(e, "listing OpenCL platforms");
  }
  return platforms;
}

std::string list_for_message(const std::vector<Device>& devices) {
  std::string text;
  for (const Device& d : devices)
    text += std::string(text.empty() ? " " : "; ") + "opencl:" + std::to_string(d.info.index) +
            " " + d.info.name + " (" + d.info.platform + ")";
  return text.empty() ? " none" : text;
}

const Device* find_device(const std::vector<Device>& devices, const std::string& name) {
  auto first = [&](const std::function<bool(const Device&)>& predicate) -> const Device* {
    for (const Device& d : devices)
      if (predicate(d)) return &d;
    return nullptr;
  };
  if (name == "auto") {
    if (const Device* gpu = first([](const Device& d) { return d.info.is_gpu; })) return gpu;
    return first([](const Device& d) { return d.info.is_cpu; });
  }
  if (name == "opencl") return first([](const Device&) { return true; });
  if (name == "pocl")
    return first([](const Device& d) { return d.info.platform == "Portable Computing Language"; });
  if (name.rfind("opencl:", 0) != 0)
    throw Error("'" + name + "' is not an OpenCL device (\"cpu\" is the CPU reference solver)");
  const long index = std::stol(name.substr(7));  // "opencl:N", N digits
  return first([index](const Device& d) { return d.info.index == index; });
}

}  // namespace

std::vector<Device> enumerate_devices() {
  std::vector<Device> devices;
  try {
    for (const cl::Platform& platform : platforms_or_none()) {
      std::vector<cl::Device> platform_devices;
      try {
        platform.getDevices(CL_DEVICE_TYPE_ALL, &platform_devices);
      } catch (const cl::Error& e) {
        if (e.err() == CL_DEVICE_NOT_FOUND) continue;
        throw;
      }
      for (const cl::Device& device : platform_devices)
        devices.push_back(
            {platform, device, describe(platform, device, static_cast<int>(devices.size()))});
    }
  } catch (const cl::Error& e) {
    throw_opencl_error(e, "listing OpenCL devices");
  }
  return devices;
}

Device select_device(const std::string& name) {
  check_device_name(name);  // a misspelt name fails before the platforms start
  const std::vector<Device> devices = enumerate_devices();
  const Device* device = find_device(devices, name);
  if (!device)
    throw Error("no OpenCL device matches '" + name + "'" + kFallbackHint +
                "; OpenCL devices found:" + list_for_message(devices) +
                (devices.empty() ? discovery_variables() : "") + pocl_cache_clause());
  if (!device->info.missing_requirement.empty())
    throw Error("OpenCL device '" + device->info.name +
                "' cannot run rvor's kernels: " + device->info.missing_requirement + kFallbackHint);
  return *device;
}

cl::Context context_for(const Device& device) {
  static std::mutex mutex;
  static std::map<cl_device_id, cl::Context> contexts;
  const std::lock_guard<std::mutex> lock(mutex);
  auto found = contexts.find(device.device());
  if (found != contexts.end()) return found->second;
  try {
    cl::Context context(device.device);
    contexts.emplace(device.device(), context);
    return context;
  } catch (const cl::Error& e) {
    throw_opencl_error(e, "creating a context on " + device.info.name);
  }
}

namespace {

// "; the build log holds no compiler message ..." where it has no "error" (PoCL's log then says
// only that the build failed: what failed was not the source, and was seen with its kernel cache
// unwritable, by a full disk or a file size limit), else "".
std::string without_diagnostics(const std::string& log) {
  std::string lower = log;
  std::transform(lower.begin(), lower.end(), lower.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  if (lower.find("error") != std::string::npos) return "";
  return "; the build log holds no compiler message: the device's compiler may have failed to "
         "write its files (PoCL: POCL_CACHE_DIR, else ~/.cache/pocl; a full disk, a quota or a "
         "file size limit)";
}

}  // namespace

cl::Program build_program(const cl::Context& context, const cl::Device& device,
                          const std::string& source, const std::string& options) {
  using Key = std::tuple<cl_context, cl_device_id, std::size_t, std::string, std::string>;
  static std::mutex mutex;
  static std::map<Key, cl::Program> cache;
  const std::lock_guard<std::mutex> lock(mutex);
  // The full source is part of the key (hash collisions would be silent wrong kernels).
  const Key key{context(), device(), std::hash<std::string>{}(source), source, options};
  auto found = cache.find(key);
  if (found != cache.end()) return found->second;
  cl::Program program;
  try {
    program = cl::Program(context, source);
  } catch (const cl::Error& e) {
    throw_opencl_error(e, "creating a program");
  }
  try {
    program.build({device}, options.c_str());
  } catch (const cl::Error& e) {
    std::string log;
    try {
      log = program.getBuildInfo<CL_PROGRAM_BUILD_LOG>(device);
    } catch (const cl::Error&) {
      log = "(no build log)";
    }
    throw Error("OpenCL program build failed (" + status_name(e.err()) + ", options '" + options +
                "'" + pocl_cache_clause() + without_diagnostics(log) + "); build log:\n" + log);
  }
  cache.emplace(key, program);
  return program;
}

std::string status_name(cl_int status) {
  static const std::map<cl_int, const char*> names = {
      {CL_DEVICE_NOT_FOUND, "CL_DEVICE_NOT_FOUND"},
      {CL_DEVICE_NOT_AVAILABLE, "CL_DEVICE_NOT_AVAILABLE"},
      {CL_COMPILER_NOT_AVAILABLE, "CL_COMPILER_NOT_AVAILABLE"},
      {CL_MEM_OBJECT_ALLOCATION_FAILURE, "CL_MEM_OBJECT_ALLOCATION_FAILURE"},
      {CL_OUT_OF_RESOURCES, "CL_OUT_OF_RESOURCES"},
      {CL_OUT_OF_HOST_MEMORY, "CL_OUT_OF_HOST_MEMORY"},
      {CL_BUILD_PROGRAM_FAILURE, "CL_BUILD_PROGRAM_FAILURE"},
      {CL_INVALID_VALUE, "CL_INVALID_VALUE"},
      {CL_INVALID_DEVICE, "CL_INVALID_DEVICE"},
      {CL_INVALID_CONTEXT, "CL_INVALID_CONTEXT"},
      {CL_INVALID_BUFFER_SIZE, "CL_INVALID_BUFFER_SIZE"},
      {CL_INVALID_PROGRAM_EXECUTABLE, "CL_INVALID_PROGRAM_EXECUTABLE"},
      {CL_INVALID_KERNEL_NAME, "CL_INVALID_KERNEL_NAME"},
      {CL_INVALID_KERNEL_ARGS, "CL_INVALID_KERNEL_ARGS"},
      {CL_INVALID_ARG_INDEX, "CL_INVALID_ARG_INDEX"},
      {CL_INVALID_ARG_SIZE, "CL_INVALID_ARG_SIZE"},
      {CL_INVALID_WORK_GROUP_SIZE, "CL_INVALID_WORK_GROUP_SIZE"},
      {CL_INVALID_WORK_ITEM_SIZE, "CL_INVALID_WORK_ITEM_SIZE"},
      {CL_INVALID_GLOBAL_WORK_SIZE, "CL_INVALID_GLOBAL_WORK_SIZE"},
      {CL_INVALID_MEM_OBJECT, "CL_INVALID_MEM_OBJECT"},
      {CL_INVALID_COMMAND_QUEUE, "CL_INVALID_COMMAND_QUEUE"},
      {CL_PLATFORM_NOT_FOUND_KHR, "CL_PLATFORM_NOT_FOUND_KHR"},
  };
  auto found = names.find(status);
  return found != names.end() ? found->second : "OpenCL status " + std::to_string(status);
}

namespace {

// A program that built yet lacks its kernels, or whose binary is unusable, comes from a damaged
// kernel cache (PoCL reads a truncated program.bc back as a program without kernels): the source
// is embedded in rvor, so its kernel names are right.
std::string damaged_cache_hint(cl_int status) {
  if (status != CL_INVALID_KERNEL_NAME && status != CL_INVALID_PROGRAM_EXECUTABLE) return "";
  return "; the compiled program lacks rvor's kernels, as one read back from a damaged kernel "
         "cache does: remove PoCL's, " +
         pocl_cache_dir().first + ", and run again";
}

}  // namespace

void throw_opencl_error(const cl::Error& error, const std::string& doing) {
  throw Error(std::string("OpenCL call ") + error.what() + " failed: " + status_name(error.err()) +
              " (" + std::to_string(error.err()) + ") while " + doing +
              damaged_cache_hint(error.err()));
}

}  // namespace rvor::opencl

namespace rvor {

void check_device_name(const std::string& name) {
  if (name == "auto" || name == "cpu" || name == "opencl" || name == "pocl") return;
  if (name.rfind("opencl:", 0) == 0) {
    const std::string number = name.substr(7);
    const bool digits = !number.empty() && number.size() <= 9 &&
                        number.find_first_not_of("0123456789") == std::string::npos;
    if (digits) return;
    throw Error("bad device name '" + name + "': expected opencl:N with N a device number");
  }
  throw Error("unknown device '" + name + "': use auto, cpu, opencl, opencl:N or pocl");
}

void require_device(const std::string& name) {
  if (name != "cpu") opencl::select_device(name);
}

std::string pocl_kernel_cache_directory() {
  return opencl::pocl_cache_dir().first;
}

std::string pocl_kernel_cache_problem() {
  return opencl::pocl_cache_problem();
}

std::vector<OpenCLDeviceInfo> list_opencl_devices() {
  std::vector<OpenCLDeviceInfo> infos;
  for (const opencl::Device& device : opencl::enumerate_devices()) infos.push_back(device.info);
  return infos;
}

}  // namespace rvor
