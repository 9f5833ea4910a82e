#include "reader_reach.h"

#include <algorithm>
#include <array>
#include <cstdlib>

#include "../slot_ranges.h"

namespace rvor::opencl {

namespace {

// How far the stencils of a set of voxels reach, and whether all their offsets lie along axes.
struct Readers {
  std::array<int, 3> reach{};
  bool axis_only = true;

  void add(const Readers& other) {
    for (int a = 0; a < 3; ++a) reach[a] = std::max(reach[a], other.reach[a]);
    axis_only = axis_only && other.axis_only;
  }
};

// Each stencil term's offset e as Readers, per shape of the table: index kStencilTerms * shape +
// term. Decoded once per shape, not once per slot.
std::vector<Readers> term_readers(const PackedStencils& stencils) {
  std::vector<Readers> terms(stencils.shapes.size() / 3);
  for (std::size_t t = 0; t < terms.size(); ++t) {
    int axes = 0;
    for (int a = 0; a < 3; ++a) {
      terms[t].reach[a] = std::abs(stencils.shapes[3 * t + static_cast<std::size_t>(a)]);
      axes += terms[t].reach[a] != 0;
    }
    terms[t].axis_only = axes <= 1;
  }
  return terms;
}

// The readers of the stencil in `record`: its terms of non-zero weight (the others are never
// read into a solve).
Readers record_readers(const PackedStencils& stencils, const std::vector<Readers>& terms,
                       std::size_t record) {
  Readers readers;
  const std::size_t first_term = kStencilTerms * std::size_t{stencils.shape_of(record)};
  for (std::size_t i = 0; i < std::size_t{kStencilTerms}; ++i)
    if (stencils.records[kStencilRecord * record + i] > 0.0f) readers.add(terms[first_term + i]);
  return readers;
}

// Per brick, its own active voxels' stencils. A uniform metric has one stencil, whose readers are
// those of every brick with an active voxel.
std::vector<Readers> own_readers(const Canvas& canvas, const PackedStencils& stencils) {
  const std::vector<Readers> terms = term_readers(stencils);
  std::vector<Readers> own(canvas.brick_count());
  const std::size_t volume = static_cast<std::size_t>(canvas.brick_volume());
  const Readers uniform = stencils.uniform ? record_readers(stencils, terms, 0) : Readers{};
  for_slot_ranges(own.size(), slot_threads(), [&](unsigned, std::size_t begin, std::size_t end) {
    for (std::size_t b = begin; b < end; ++b)
      for (std::size_t slot = b * volume; slot < (b + 1) * volume; ++slot) {
        if (!canvas.active[slot]) continue;
        if (stencils.uniform) {
          own[b] = uniform;
          break;
        }
        own[b].add(record_readers(stencils, terms, slot));
      }
  });
  return own;
}

// Whether a voxel of a brick at brick offset `delta` from another can reach into that one with
// offsets of at most `reach` voxels: across |delta_a| bricks it needs more than the
// edge_a (|delta_a| - 1) voxels of the bricks in between.
bool reaches_across(const std::array<int, 3>& reach, const std::array<int, 3>& delta,
                    const int* edges) {
  for (int a = 0; a < 3; ++a)
    if (delta[a] != 0 && reach[a] <= edges[a] * (std::abs(delta[a]) - 1)) return false;
  return true;
}

std::uint32_t pack(const Readers& readers) {
  std::uint32_t packed = readers.axis_only ? kAxisReaders : 0u;
  for (int a = 0; a < 3; ++a)
    packed |= static_cast<std::uint32_t>(std::min(readers.reach[a], 255)) << (8 * a);
  return packed;
}

}  // namespace

std::vector<std::uint32_t> reader_reach(const Canvas& canvas, const PackedStencils& stencils) {
  const std::vector<Readers> own = own_readers(canvas, stencils);
  const int edges[3] = {Canvas::kBrickEdge, Canvas::kBrickEdge, canvas.brick_edge_z()};
  std::array<int, 3> around{};  // bricks within the canvas's stencil reach, per axis
  for (int a = 0; a < canvas.dimension; ++a)
    around[a] = (stencils.reach[a] + edges[a] - 1) / edges[a];
  std::vector<std::uint32_t> packed(canvas.brick_count());
  for (std::size_t b = 0; b < canvas.brick_count(); ++b) {
    const VoxelIndex& o = canvas.brick_origins[b];
    const std::array<int, 3> at{o.i / edges[0], o.j / edges[1], o.k / edges[2]};
    Readers readers = own[b];
    for (int dz = -around[2]; dz <= around[2]; ++dz)
      for (int dy = -around[1]; dy <= around[1]; ++dy)
        for (int dx = -around[0]; dx <= around[0]; ++dx) {
          const int other = canvas.brick_at(at[0] + dx, at[1] + dy, at[2] + dz);
          // The bricks around at -delta read into this one when their own offsets reach it.
          if (other >= 0 &&
              reaches_across(own[static_cast<std::size_t>(other)].reach, {dx, dy, dz}, edges))
            readers.add(own[static_cast<std::size_t>(other)]);
        }
    packed[b] = pack(readers);
  }
  return packed;
}

}  // namespace rvor::opencl
