#include "reader_reach.h"

#include <algorithm>
#include <array>
#include <cstdlib>

namespace rvor::opencl {

namespace {

using Reach = std::array<int, 3>;

Reach largest(const Reach& a, const Reach& b) {
  return {std::max(a[0], b[0]), std::max(a[1], b[1]), std::max(a[2], b[2])};
}

// Per brick, the longest offset per axis of its own active voxels' stencils.
std::vector<Reach> own_reach(const Canvas& canvas, const PackedStencils& stencils) {
  if (stencils.uniform) return std::vector<Reach>(canvas.brick_count(), stencils.reach);
  std::vector<Reach> shape_reach(stencils.shape_count(), Reach{});
  for (std::size_t s = 0; s < shape_reach.size(); ++s)
    for (int i = 0; i < kStencilTerms; ++i)
      for (int a = 0; a < 3; ++a)
        shape_reach[s][a] = std::max(
            shape_reach[s][a], std::abs(int{stencils.shapes[3 * (kStencilTerms * s + i) + a]}));
  std::vector<Reach> own(canvas.brick_count(), Reach{});
  const std::size_t volume = static_cast<std::size_t>(canvas.brick_volume());
  for (std::size_t slot = 0; slot < canvas.slot_count(); ++slot)
    if (canvas.active[slot])
      own[slot / volume] = largest(own[slot / volume], shape_reach[stencils.shape_of(slot)]);
  return own;
}

// Whether a voxel of a brick at brick offset `delta` from another can reach into that one with
// offsets of at most `reach` voxels: across |delta_a| bricks it needs more than the
// edge_a (|delta_a| - 1) voxels of the bricks in between.
bool reaches_across(const Reach& reach, const std::array<int, 3>& delta, const int* edges) {
  for (int a = 0; a < 3; ++a)
    if (delta[a] != 0 && reach[a] <= edges[a] * (std::abs(delta[a]) - 1)) return false;
  return true;
}

std::uint32_t pack(const Reach& reach) {
  std::uint32_t packed = 0;
  for (int a = 0; a < 3; ++a)
    packed |= static_cast<std::uint32_t>(std::min(reach[a], 255)) << (8 * a);
  return packed;
}

}  // namespace

std::vector<std::uint32_t> reader_reach(const Canvas& canvas, const PackedStencils& stencils) {
  const std::vector<Reach> own = own_reach(canvas, stencils);
  const int edges[3] = {Canvas::kBrickEdge, Canvas::kBrickEdge, canvas.brick_edge_z()};
  Reach around{};  // bricks within the canvas's stencil reach, per axis
  for (int a = 0; a < canvas.dimension; ++a)
    around[a] = (stencils.reach[a] + edges[a] - 1) / edges[a];
  const auto& grid = canvas.brick_grid_dims;
  std::vector<std::uint32_t> packed(canvas.brick_count());
  for (std::size_t b = 0; b < canvas.brick_count(); ++b) {
    const VoxelIndex& o = canvas.brick_origins[b];
    const std::array<int, 3> at{o.i / edges[0], o.j / edges[1], o.k / edges[2]};
    Reach readers = own[b];
    for (int dz = -around[2]; dz <= around[2]; ++dz)
      for (int dy = -around[1]; dy <= around[1]; ++dy)
        for (int dx = -around[0]; dx <= around[0]; ++dx) {
          const std::array<int, 3> n{at[0] + dx, at[1] + dy, at[2] + dz};
          if (n[0] < 0 || n[1] < 0 || n[2] < 0 || n[0] >= grid[0] || n[1] >= grid[1] ||
              n[2] >= grid[2])
            continue;
          const int other = canvas.brick_table[static_cast<std::size_t>(
              n[0] + grid[0] * (n[1] + static_cast<std::size_t>(grid[1]) * n[2]))];
          // The bricks around at -delta read into this one when their own offsets reach it.
          if (other >= 0 &&
              reaches_across(own[static_cast<std::size_t>(other)], {dx, dy, dz}, edges))
            readers = largest(readers, own[static_cast<std::size_t>(other)]);
        }
    packed[b] = pack(readers);
  }
  return packed;
}

}  // namespace rvor::opencl
