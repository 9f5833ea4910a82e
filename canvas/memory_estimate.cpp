#include "memory_estimate.h"

#include <unistd.h>

#include <cstdio>

#include "rvor/canvas_builder.h"
#include "rvor/error.h"

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

double estimated_canvas_bytes(double active_voxels, double brick_table_cells) {
  return active_voxels * static_cast<double>(estimated_bytes_per_active_voxel()) +
         brick_table_cells * sizeof(std::int32_t);
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

std::uint64_t resolved_memory_budget(std::uint64_t budget) {
  return budget != 0 ? budget : default_memory_budget();
}

void check_memory_budget(double active_voxels, double brick_table_cells, std::uint64_t budget,
                         std::uint64_t held_bytes) {
  budget = resolved_memory_budget(budget);
  const double needed = estimated_canvas_bytes(active_voxels, brick_table_cells);
  const double held = static_cast<double>(held_bytes);
  if (needed + held <= static_cast<double>(budget)) return;
  char voxels[32];
  std::snprintf(voxels, sizeof voxels, "%.2g", active_voxels);
  const std::string held_text =
      held_bytes != 0 ? ", with the metric field's " + format_bytes(held) + " already held" : "";
  throw Error("canvas of ~" + std::string(voxels) + " active voxels needs ~" +
              format_bytes(needed) + held_text + ", over the memory budget of " +
              format_bytes(static_cast<double>(budget)) + " (--memory-budget)");
}

}  // namespace rvor
