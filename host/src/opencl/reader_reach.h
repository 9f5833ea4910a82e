#pragma once
// Per brick, how far the stencils that read its voxels reach: what lets a relaxed brick make
// pending only the bricks around that read what it changed (kernels/brick_layout.clh,
// brick_news), instead of every brick within the canvas's stencil reach.
#include <cstdint>
#include <vector>

#include "device_canvas.h"
#include "rvor/canvas.h"

namespace rvor::opencl {

// Per brick, the longest offset per axis of the stencils of the active voxels that can read one
// of its voxels (its own and those of the bricks around whose offsets are long enough to reach
// into it), as bytes x, y, z of a word (at most 255; z is 0 in 2D).
std::vector<std::uint32_t> reader_reach(const Canvas& canvas, const PackedStencils& stencils);

}  // namespace rvor::opencl
