#pragma once
// Per brick, how far the stencils that read its voxels reach: what lets a relaxed brick make
// pending only the bricks around that read what it changed (kernels/brick_layout.clh,
// brick_news), instead of every brick within the canvas's stencil reach.
#include <cstdint>
#include <vector>

#include "device_canvas.h"
#include "rvor/canvas.h"

namespace rvor::opencl {

// Set in a reader reach when every offset reading the brick lies along an axis (AXIS_READERS,
// kernels/brick_layout.clh).
constexpr std::uint32_t kAxisReaders = 1u << 24;

// Per brick, the longest offset per axis of the stencil terms (of non-zero weight) of the active
// voxels that can read one of its voxels (its own and those of the bricks around whose offsets
// are long enough to reach into it), as bytes x, y, z of a word (at most 255; z is 0 in 2D), with
// kAxisReaders when all those offsets lie along an axis.
std::vector<std::uint32_t> reader_reach(const Canvas& canvas, const PackedStencils& stencils);

}  // namespace rvor::opencl
