#include "rvor/memory_budget.h"

#include <unistd.h>

#include <cstdio>

namespace rvor {

// Measured, not summed: peak resident memory of `rvor voronoi` on box:-1,-1,-1,1,1,1 with 100
// seeds, 128^3 minus 64^3 divided by the added voxels (/usr/bin/time -f %M), was 99 B per voxel
// with the CPU reference (canvas, float and double fields, per-voxel state and the reverse stencil
// graph) and 107 B with PoCL (whose device buffers live in host memory, next to the host canvas).
// 128 B leaves room for the outputs written afterwards.
std::uint64_t estimated_bytes_per_active_voxel() {
  return 128;
}

std::uint64_t default_memory_budget() {
  const long pages = sysconf(_SC_PHYS_PAGES);
  const long page_size = sysconf(_SC_PAGE_SIZE);
  if (pages <= 0 || page_size <= 0) return std::uint64_t{8} << 30;  // unknown: assume 8 GiB
  return static_cast<std::uint64_t>(0.75 * static_cast<double>(pages) * page_size);
}

std::uint64_t resolved_memory_budget(std::uint64_t budget) {
  return budget != 0 ? budget : default_memory_budget();
}

std::string format_bytes(double bytes) {
  static const char* const units[] = {"B", "kB", "MB", "GB", "TB", "PB", "EB", "ZB", "YB"};
  int unit = 0;
  while (bytes >= 1000.0 && unit < 8) {
    bytes /= 1000.0;
    ++unit;
  }
  char text[32];
  std::snprintf(text, sizeof text, "%.3g %s", bytes, units[unit]);
  return text;
}

}  // namespace rvor
