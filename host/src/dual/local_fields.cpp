// Per-seed local distance fields (local_fields.h): star boxes from the nerve, one single-source
// reference solve per seed on a cropped canvas.
#include "rvor/local_fields.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>
#include <string>

#include "parallel_for.h"
#include "reference_solver.h"
#include "rvor/error.h"

namespace rvor {

namespace {

struct IndexBox {
  std::array<int, 3> lo{std::numeric_limits<int>::max(), std::numeric_limits<int>::max(),
                        std::numeric_limits<int>::max()};
  std::array<int, 3> hi{std::numeric_limits<int>::min(), std::numeric_limits<int>::min(),
                        std::numeric_limits<int>::min()};  // inclusive

  void add(const VoxelIndex& v) { add(IndexBox{{v.i, v.j, v.k}, {v.i, v.j, v.k}}); }
  void add(const IndexBox& b) {
    for (int a = 0; a < 3; ++a) {
      lo[a] = std::min(lo[a], b.lo[a]);
      hi[a] = std::max(hi[a], b.hi[a]);
    }
  }
  bool empty() const { return lo[0] > hi[0]; }
};

// The star box of every seed: the bounding box of its voxel and its nerve neighbours' voxels
// (the star's Delaunay simplices, where a uniform metric's geodesics run), grown on each axis by
// the margin plus a fraction of its extent (room for geodesics that bend), clipped to the canvas.
std::vector<IndexBox> star_boxes(const Canvas& canvas, const Nerve& nerve,
                                 const std::vector<Vec3>& seeds, const LocalFieldOptions& options) {
  std::vector<VoxelIndex> voxels;
  for (const Vec3& s : seeds) voxels.push_back(canvas.voxel_containing(s));
  std::vector<IndexBox> stars(seeds.size());
  for (std::size_t s = 0; s < seeds.size(); ++s) stars[s].add(voxels[s]);
  for (const NerveSimplex& e : nerve.edges) {
    const auto a = static_cast<std::size_t>(e.seeds[0]), b = static_cast<std::size_t>(e.seeds[1]);
    stars[a].add(voxels[b]);
    stars[b].add(voxels[a]);
  }
  for (IndexBox& box : stars)
    for (int a = 0; a < canvas.dimension; ++a) {
      const int grow =
          options.margin +
          static_cast<int>(std::ceil(options.relative_margin * (box.hi[a] - box.lo[a])));
      box.lo[a] = std::max(0, box.lo[a] - grow);
      box.hi[a] = std::min(canvas.dims[a] - 1, box.hi[a] + grow);
    }
  return stars;
}

// A copy of the canvas restricted to the box (same voxel size; its voxel (0,0,0) is the box's
// lowest voxel), every brick of the box allocated.
Canvas crop(const Canvas& canvas, const IndexBox& box) {
  std::array<int, 3> dims{};
  for (int a = 0; a < 3; ++a) dims[a] = box.hi[a] - box.lo[a] + 1;
  const int ez = canvas.brick_edge_z(), e = Canvas::kBrickEdge;
  std::vector<VoxelIndex> origins;
  for (int k = 0; k < dims[2]; k += ez)
    for (int j = 0; j < dims[1]; j += e)
      for (int i = 0; i < dims[0]; i += e) origins.push_back({i, j, k});
  Canvas out;
  out.allocate(canvas.dimension, canvas.voxel_size,
               canvas.world_of(VoxelIndex{box.lo[0], box.lo[1], box.lo[2]}), dims, origins);
  for (std::size_t slot = 0; slot < out.slot_count(); ++slot) {
    const VoxelIndex v = out.voxel_of(slot);
    if (v.i >= dims[0] || v.j >= dims[1] || v.k >= dims[2]) continue;  // brick padding
    const int64_t source = canvas.slot_of(v.i + box.lo[0], v.j + box.lo[1], v.k + box.lo[2]);
    if (source < 0) continue;
    out.active[slot] = 1;
    std::memcpy(&out.metric[6 * slot], &canvas.metric[6 * static_cast<std::size_t>(source)],
                6 * sizeof(float));
  }
  out.finalize();
  return out;
}

LocalField solve_local(const Canvas& canvas, const IndexBox& box, const Vec3& seed) {
  const Canvas cropped = crop(canvas, box);
  detail::ReferenceSolver solver(cropped);
  detail::ExactField exact;
  solver.solve(cropped, {seed}, exact);
  LocalField local;
  local.lo = box.lo;
  for (int a = 0; a < 3; ++a) local.dims[a] = cropped.dims[a];
  local.distance.assign(static_cast<std::size_t>(local.dims[0]) * local.dims[1] * local.dims[2],
                        std::numeric_limits<float>::infinity());
  for (std::size_t slot = 0; slot < cropped.slot_count(); ++slot) {
    if (!cropped.active[slot]) continue;
    const VoxelIndex v = cropped.voxel_of(slot);
    local.distance[static_cast<std::size_t>(v.i) +
                   static_cast<std::size_t>(local.dims[0]) *
                       (static_cast<std::size_t>(v.j) +
                        static_cast<std::size_t>(local.dims[1]) * v.k)] =
        static_cast<float>(exact.distance[slot]);
  }
  return local;
}

}  // namespace

LocalFields compute_local_fields(const Canvas& canvas, const Nerve& nerve,
                                 const std::vector<Vec3>& seeds, const LocalFieldOptions& options) {
  const auto t0 = std::chrono::steady_clock::now();
  if (nerve.seed_count != seeds.size())
    throw Error("local fields: the nerve has " + std::to_string(nerve.seed_count) + " seeds, " +
                std::to_string(seeds.size()) + " given");
  const std::vector<IndexBox> boxes = star_boxes(canvas, nerve, seeds, options);

  LocalFields out;
  out.fields.resize(seeds.size());
  // One seed per task: solves are independent and each is large enough to amortise a thread.
  detail::parallel_for(seeds.size(), 1, [&](std::size_t s) {
    out.fields[s] = solve_local(canvas, boxes[s], seeds[s]);
  });
  for (const LocalField& f : out.fields) out.voxels += f.distance.size();
  out.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return out;
}

}  // namespace rvor
