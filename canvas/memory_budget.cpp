#include "rvor/memory_budget.h"

#include <unistd.h>

#include <cstdio>
#include <fstream>
#include <limits>

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

std::uint64_t default_memory_budget() {
  const long pages = sysconf(_SC_PHYS_PAGES);
  const long page_size = sysconf(_SC_PAGE_SIZE);
  if (pages <= 0 || page_size <= 0) return std::uint64_t{8} << 30;  // unknown: assume 8 GiB
  return static_cast<std::uint64_t>(0.75 * static_cast<double>(pages) * page_size);
}

std::uint64_t available_memory() {
  std::ifstream meminfo("/proc/meminfo");
  std::string key;
  std::uint64_t kilobytes = 0;
  while (meminfo >> key >> kilobytes) {
    if (key == "MemAvailable:") return kilobytes * 1024;
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
