#include "rvor/memory_budget.h"

#include <sys/resource.h>
#include <unistd.h>

#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <fstream>
#include <limits>
#include <optional>
#include <string>

#include "rvor/error.h"

namespace rvor {

// Measured, not summed: peak resident memory of `rvor voronoi` with 100 seeds at 160^3 less that
// at 96^3, over the added voxels (docs/measurements/peak_bytes_per_voxel.sh, PoCL, 2026-12-05):
// 26.7 B per voxel for euclidean on box:-1,-1,-1,1,1,1 (the canvas's uniform form: activity, float
// field, device state 17.7 B), 78 B for radial_shock_3d on its box (24 B of tensors per slot,
// 45.7 B of device stencils and state). The margin leaves room for the outputs (42 B per voxel
// with --vtu) and for a denser stencil.
std::uint64_t estimated_bytes_per_active_voxel(bool uniform_metric) {
  return uniform_metric ? 48 : 128;
}

std::uint64_t canvas_and_field_bytes_per_active_voxel(bool uniform_metric) {
  return 1 + (uniform_metric ? 0 : 24) + 8;
}

namespace {

// A number in the file at `path` ("max", a missing or unreadable file: none).
std::optional<std::uint64_t> number_in(const std::string& path) {
  std::ifstream in(path);
  std::uint64_t value = 0;
  if (!(in >> value)) return std::nullopt;
  return value;
}

// The memory limit of this process's control group (v2 memory.max, v1 memory.limit_in_bytes; a
// container's), where one is set: past it the system kills the process, whatever RAM it has.
std::optional<std::uint64_t> control_group_limit() {
  std::ifstream groups("/proc/self/cgroup");
  std::optional<std::uint64_t> least;
  for (std::string line; std::getline(groups, line);) {
    // "0::/path" (v2) or "N:memory:/path" (v1, controllers listed with commas).
    const std::size_t first = line.find(':'), second = line.find(':', first + 1);
    if (first == std::string::npos || second == std::string::npos) continue;
    const std::string controllers = line.substr(first + 1, second - first - 1);
    const std::string path = line.substr(second + 1);
    std::optional<std::uint64_t> limit;
    if (controllers.empty())
      limit = number_in("/sys/fs/cgroup" + path + "/memory.max");
    else if (("," + controllers + ",").find(",memory,") != std::string::npos)
      limit = number_in("/sys/fs/cgroup/memory" + path + "/memory.limit_in_bytes");
    if (limit && (!least || *limit < *least)) least = limit;
  }
  return least;
}

// The least of the limits on this process's memory beside RAM: its control group's, and its
// address space's (RLIMIT_AS).
std::optional<std::uint64_t> process_memory_limit() {
  std::optional<std::uint64_t> least = control_group_limit();
  rlimit address_space{};
  if (getrlimit(RLIMIT_AS, &address_space) == 0 && address_space.rlim_cur != RLIM_INFINITY) {
    const auto limit = static_cast<std::uint64_t>(address_space.rlim_cur);
    if (!least || limit < *least) least = limit;
  }
  return least;
}

}  // namespace

std::uint64_t default_memory_budget() {
  const long pages = sysconf(_SC_PHYS_PAGES);
  const long page_size = sysconf(_SC_PAGE_SIZE);
  double memory = pages > 0 && page_size > 0 ? static_cast<double>(pages) * page_size
                                             : static_cast<double>(std::uint64_t{8} << 30);
  if (const std::optional<std::uint64_t> limit = process_memory_limit())
    memory = std::min(memory, static_cast<double>(*limit));
  return static_cast<std::uint64_t>(0.75 * memory);
}

std::uint64_t available_memory() {
  std::ifstream meminfo("/proc/meminfo");
  std::string key;
  std::uint64_t kilobytes = 0;
  const std::optional<std::uint64_t> limit = process_memory_limit();
  while (meminfo >> key >> kilobytes) {
    if (key == "MemAvailable:") return std::min(kilobytes * 1024, limit.value_or(UINT64_MAX));
    meminfo.ignore(std::numeric_limits<std::streamsize>::max(), '\n');
  }
  return default_memory_budget();
}

void require_memory_for(const std::string& what, double needed, std::uint64_t budget,
                        const std::string& advice) {
  const double limit = static_cast<double>(budget != 0 ? budget : available_memory());
  if (needed <= limit) return;
  const std::string over =
      budget != 0 ? ", over the memory budget of " + format_bytes(limit) + " (--memory-budget)"
                  : ", more than the " + format_bytes(limit) + " of memory available";
  throw Error(what + " needs ~" + format_bytes(needed) + over + advice);
}

std::uint64_t resolved_memory_budget(std::uint64_t budget) {
  return budget != 0 ? budget : default_memory_budget();
}

std::string format_bytes(double bytes) {
  // Binary units, as --memory-budget's suffixes: "200M" shows as 200 MiB, not "210 MB".
  static const char* const units[] = {"B", "KiB", "MiB", "GiB", "TiB", "PiB", "EiB", "ZiB", "YiB"};
  int unit = 0;
  while (bytes >= 1024.0 && unit < 8) {
    bytes /= 1024.0;
    ++unit;
  }
  char text[32];
  // 1000 to 1023 of a unit are whole ("1000 MiB"): "%.3g" gave "1e+03 MiB".
  std::snprintf(text, sizeof text, bytes >= 999.5 ? "%.0f %s" : "%.3g %s", bytes, units[unit]);
  return text;
}

}  // namespace rvor
