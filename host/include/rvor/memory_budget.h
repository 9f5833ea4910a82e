#pragma once
// The memory budget of a job (--memory-budget): what the up-front estimates of the canvas builder,
// the VDB metric loader and the curved dual's local fields are checked against.
#include <cstdint>
#include <string>

namespace rvor {

// Bytes per active voxel that a canvas, its field and a propagation by the OpenCL engine (the
// default; on PoCL its buffers are host memory) need at `rvor voronoi`'s peak, with the canvas's
// tensors stored per slot or once (`uniform_metric`, Canvas::uniform_metric): the up-front
// estimates. The CPU reference needs more and checks its own (make_reference_propagator).
std::uint64_t estimated_bytes_per_active_voxel(bool uniform_metric);
// Bytes per active voxel of a canvas and a float field alone (1 B of activity, 24 B of tensors
// unless stored once, 8 B of field): what the curved dual's local fields share the budget with
// once the propagation's buffers are freed, as `rvor voronoi` frees them.
std::uint64_t canvas_and_field_bytes_per_active_voxel(bool uniform_metric);
// 75% of physical memory, or of the process's limit where that is lower: its control group's
// (a container's memory.max or memory.limit_in_bytes), its address space's (RLIMIT_AS). Past those
// the system kills the process, or an allocation fails, whatever the RAM.
std::uint64_t default_memory_budget();
// Memory the system can give now without swapping (MemAvailable of /proc/meminfo, at most the
// process's limit above; where that cannot be read, default_memory_budget()).
std::uint64_t available_memory();
// Throws rvor::Error "<what> needs ~X, over the memory budget of Y (--memory-budget)<advice>"
// when `needed` passes `budget`; for budget 0, "<what> needs ~X, more than the Y of memory
// available<advice>" when it passes available_memory().
void require_memory_for(const std::string& what, double needed, std::uint64_t budget,
                        const std::string& advice);
// `budget`, or default_memory_budget() for 0 (the meaning of 0 in every budget option).
std::uint64_t resolved_memory_budget(std::uint64_t budget);
// "1.2 GiB", "120 TiB": binary units (as --memory-budget's suffixes), three significant digits.
std::string format_bytes(double bytes);

}  // namespace rvor
