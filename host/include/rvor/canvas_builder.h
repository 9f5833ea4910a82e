#pragma once
// Builds a Canvas from a domain and a metric field on OpenVDB: the domain becomes the active
// topology of a sparse grid, the metric is sampled and validated at every active voxel, and the
// active leaves are packed into bricks.
#include <cstddef>
#include <cstdint>

#include "rvor/canvas.h"
#include "rvor/domain.h"
#include "rvor/memory_budget.h"
#include "rvor/metric_field.h"

namespace rvor {

// The resolutions a canvas takes (voxels along the longest side).
inline constexpr int kLeastCanvasResolution = 2;
inline constexpr int kMostCanvasResolution = 65536;

struct CanvasOptions {
  int resolution = 128;  // voxels along the longest side of the domain's bounding box
  // Bytes; 0: default_memory_budget(), 75% of physical memory or of the process's limit (a
  // container's, RLIMIT_AS) where that is lower.
  std::uint64_t memory_budget = 0;
};

// Throws rvor::Error when the resolution is not in [2, 65536], the domain is empty, the estimate
// and the metric's resident_bytes() together exceed the budget (the message gives the estimate,
// what the metric holds, and the budget), or the metric is not SPD
// somewhere (the message gives the position), or when a 2D metric meets a 3D domain. A 3D metric
// on a 2D domain is sampled on the plane z = 0 and restricted to it (its upper 2x2 block).
Canvas build_canvas(const DomainSpec& domain, const MetricField& metric,
                    const CanvasOptions& options);

}  // namespace rvor
