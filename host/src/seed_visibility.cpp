// Which quarter bricks see their listed seeds through active voxels (rvor/nearest_seeds.h,
// mark_where_seeds_are_seen).
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdlib>
#include <limits>

#include "rvor/nearest_seeds.h"
#include "slot_ranges.h"

namespace rvor {

namespace {

using Cell = std::array<int, 3>;

// Cells of `edge`^3 voxels (edge^2 x 1 in 2D) aligned with the bricks, and which of them hold
// active voxels only: the quarter bricks, or the bricks (whose quarters are all full).
class FullCells {
 public:
  // The quarter bricks, found from the voxels (the bricks split over threads).
  explicit FullCells(const Canvas& canvas) : FullCells(canvas, Canvas::kBrickEdge / 2) {
    for_slot_ranges(canvas.brick_count(), slot_threads(),
                    [&](unsigned, std::size_t first, std::size_t end) {
                      for (std::size_t brick = first; brick < end; ++brick)
                        for_each_quarter(canvas, brick, [&](const Cell& corner, const Cell& cell) {
                          full_[index(cell)] = all_active(canvas, brick, corner) ? 1 : 0;
                        });
                    });
  }

  // The bricks, from their quarters.
  FullCells(const Canvas& canvas, const FullCells& quarters)
      : FullCells(canvas, Canvas::kBrickEdge) {
    for (std::size_t brick = 0; brick < canvas.brick_count(); ++brick) {
      bool full = true;
      quarters.for_each_quarter(canvas, brick, [&](const Cell&, const Cell& cell) {
        full = full && quarters.full(cell);
      });
      full_[index(cell_of(canvas.brick_origins[brick]))] = full ? 1 : 0;
    }
  }

  int edge() const { return edge_; }
  int edge_z() const { return edge_z_; }
  Cell cell_of(const VoxelIndex& v) const { return {v.i / edge_, v.j / edge_, v.k / edge_z_}; }

  bool full(const Cell& c) const {
    for (int a = 0; a < 3; ++a)
      if (c[a] < 0 || c[a] >= dims_[a]) return false;
    return full_[index(c)] != 0;
  }

 private:
  FullCells(const Canvas& canvas, int edge)
      : edge_(edge), edge_z_(canvas.dimension == 3 ? edge : 1) {
    const int per_brick = Canvas::kBrickEdge / edge;
    dims_ = {canvas.brick_grid_dims[0] * per_brick, canvas.brick_grid_dims[1] * per_brick,
             canvas.dimension == 3 ? canvas.brick_grid_dims[2] * per_brick : 1};
    full_.assign(static_cast<std::size_t>(dims_[0]) * dims_[1] * dims_[2], 0);
  }

  // visit(corner in brick coordinates, cell) for each quarter of the brick (quarter cells only).
  template <typename Visit>
  void for_each_quarter(const Canvas& canvas, std::size_t brick, Visit&& visit) const {
    const VoxelIndex& o = canvas.brick_origins[brick];
    for (int k = 0; k < canvas.brick_edge_z(); k += edge_z_)
      for (int j = 0; j < Canvas::kBrickEdge; j += edge_)
        for (int i = 0; i < Canvas::kBrickEdge; i += edge_)
          visit(Cell{i, j, k}, cell_of({o.i + i, o.j + j, o.k + k}));
  }

  bool all_active(const Canvas& canvas, std::size_t brick, const Cell& corner) const {
    const int e = Canvas::kBrickEdge;
    const std::size_t first = brick * canvas.brick_volume();
    for (int k = corner[2]; k < corner[2] + edge_z_; ++k)
      for (int j = corner[1]; j < corner[1] + edge_; ++j)
        for (int i = corner[0]; i < corner[0] + edge_; ++i)
          if (!canvas.active[first + (static_cast<std::size_t>(k) * e + j) * e + i]) return false;
    return true;
  }

  std::size_t index(const Cell& c) const {
    return (static_cast<std::size_t>(c[2]) * dims_[1] + c[1]) * dims_[0] + c[0];
  }

  int edge_, edge_z_;
  std::array<int, 3> dims_{};
  std::vector<std::uint8_t> full_;
};

// Walks the cells from `from` (in cell `cell`) to `to` (in cell `last`) one face at a time, in the
// order in which the segment between the points crosses the cells' faces (a DDA that takes
// exactly the |last - cell|_1 steps, so rounding cannot make it wander or loop), and says whether
// every cell it enters is full.
bool walk_through_full_cells(const FullCells& cells, const Vec3& from, const Vec3& to, Cell cell,
                             const Cell& last) {
  if (!cells.full(cell)) return false;
  std::array<int, 3> step{}, remaining{};
  std::array<double, 3> next_crossing{}, crossing_gap{};
  for (int a = 0; a < 3; ++a) {
    const double edge = a == 2 ? cells.edge_z() : cells.edge();
    remaining[a] = std::abs(last[a] - cell[a]);
    step[a] = last[a] > cell[a] ? 1 : -1;
    const double span = to[a] - from[a];
    if (remaining[a] == 0 || span == 0.0) {
      next_crossing[a] = crossing_gap[a] = std::numeric_limits<double>::infinity();
      continue;
    }
    // Cell c spans the voxel-centre coordinates [c * edge - 0.5, (c + 1) * edge - 0.5).
    const double face = (step[a] > 0 ? cell[a] + 1 : cell[a]) * edge - 0.5;
    next_crossing[a] = std::max(0.0, (face - from[a]) / span);
    crossing_gap[a] = edge / std::abs(span);
  }
  for (;;) {
    int axis = -1;
    for (int a = 0; a < 3; ++a)
      if (remaining[a] > 0 && (axis < 0 || next_crossing[a] < next_crossing[axis])) axis = a;
    if (axis < 0) return true;
    cell[axis] += step[axis];
    --remaining[axis];
    next_crossing[axis] += crossing_gap[axis];
    if (!cells.full(cell)) return false;
  }
}

struct Target {
  Vec3 point;  // index coordinates (z = 0 in 2D)
  VoxelIndex voxel;
};

// Whether the convex hull of the voxel centres of the cell-sized block at `origin` and the target
// lies in full cells. It does when the segments from the block's corners do: a cross-section of
// the hull is the block shrunk towards the target, no wider than a cell, and a box no wider than
// a cell meets only cells that hold one of its corners.
bool block_sees(const FullCells& cells, const VoxelIndex& origin, const Target& target) {
  const int reach = cells.edge() - 1, reach_z = cells.edge_z() - 1;
  const Cell first = cells.cell_of(origin), last = cells.cell_of(target.voxel);
  const int corners = reach_z > 0 ? 8 : 4;
  for (int corner = 0; corner < corners; ++corner) {
    const Vec3 from(origin.i + (corner & 1) * reach, origin.j + ((corner >> 1) & 1) * reach,
                    origin.k + ((corner >> 2) & 1) * reach_z);
    if (!walk_through_full_cells(cells, from, target.point, first, last)) return false;
  }
  return true;
}

// Of the quarters in `quarters` (a bit per quarter, rvor/nearest_seeds.h), those that see the
// target: all of them when the whole brick and its hull lie in full bricks, else quarter by
// quarter.
std::uint8_t quarters_seeing(const FullCells& bricks, const FullCells& quarter_cells,
                             const VoxelIndex& origin, const Target& target,
                             std::uint8_t quarters) {
  if (quarters == 0 || block_sees(bricks, origin, target)) return quarters;
  std::uint8_t seen = 0;
  for (int q = 0; q < (quarter_cells.edge_z() > 1 ? 8 : 4); ++q) {
    if (!(quarters >> q & 1)) continue;
    const VoxelIndex offset = quarter_origin(q);
    const VoxelIndex corner{origin.i + offset.i, origin.j + offset.j, origin.k + offset.k};
    if (block_sees(quarter_cells, corner, target)) seen |= static_cast<std::uint8_t>(1u << q);
  }
  return seen;
}

}  // namespace

void mark_where_seeds_are_seen(const Canvas& canvas, const std::vector<Vec3>& seeds,
                               BrickSeedLists& lists) {
  const FullCells quarters(canvas);
  const FullCells bricks(canvas, quarters);
  std::vector<Target> targets;
  targets.reserve(seeds.size());
  for (const Vec3& seed : seeds) {
    Target t{seed_index_point(canvas, seed), canvas.voxel_containing(seed)};
    if (canvas.dimension == 2) t.voxel.k = 0;
    targets.push_back(t);
  }
  for_slot_ranges(
      canvas.brick_count(), slot_threads(), [&](unsigned, std::size_t first, std::size_t end) {
        for (std::size_t brick = first; brick < end; ++brick)
          for (std::uint32_t c = lists.begin[brick]; c < lists.begin[brick + 1]; ++c)
            lists.seen[c] = quarters_seeing(bricks, quarters, canvas.brick_origins[brick],
                                            targets[lists.seeds[c]], lists.seen[c]);
      });
}

}  // namespace rvor
