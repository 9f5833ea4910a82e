#pragma once
// The memory budget of a job (--memory-budget): what the up-front estimates of the canvas builder,
// the VDB metric loader and the curved dual's local fields are checked against.
#include <cstdint>
#include <string>

namespace rvor {

// Bytes the canvas and a propagation over it need per active voxel (packed metric, activity,
// distance, label, solver work arrays), used for the up-front estimates.
std::uint64_t estimated_bytes_per_active_voxel();
std::uint64_t default_memory_budget();  // 75% of physical memory
// `budget`, or default_memory_budget() for 0 (the meaning of 0 in every budget option).
std::uint64_t resolved_memory_budget(std::uint64_t budget);
// "1.2 GB", "120 TB": decimal units, three significant digits.
std::string format_bytes(double bytes);

}  // namespace rvor
