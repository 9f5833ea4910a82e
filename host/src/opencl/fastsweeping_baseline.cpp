// OpenVDB FastSweeping as the isotropic baseline (fastsweeping_baseline.h). The only translation
// unit that includes tools/FastSweeping.h, which takes long to compile.
#include "fastsweeping_baseline.h"

#include <openvdb/openvdb.h>
#include <openvdb/tools/FastSweeping.h>

#include <chrono>
#include <cmath>
#include <limits>

#include "rvor/error.h"

namespace rvor::baseline {

namespace {

using Clock = std::chrono::steady_clock;

// Voxels around a seed whose signed distance to its sphere is set exactly: the zero crossings
// (at one voxel from the seed) must lie between voxels with exact values on both sides.
constexpr int kSeedReach = 2;

double seconds_since(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

openvdb::Coord coord_of(const VoxelIndex& v) {
  return openvdb::Coord(v.i, v.j, v.k);
}

openvdb::math::Transform::Ptr canvas_transform(const Canvas& canvas) {
  auto transform = openvdb::math::Transform::createLinearTransform(canvas.voxel_size);
  transform->postTranslate(openvdb::Vec3d(canvas.origin.x(), canvas.origin.y(), canvas.origin.z()));
  return transform;
}

// Every active canvas voxel, outside every seed sphere (positive) until the seeds are stamped.
openvdb::FloatGrid::Ptr canvas_topology_grid(const Canvas& canvas, float outside) {
  openvdb::FloatGrid::Ptr grid = openvdb::FloatGrid::create(outside);
  grid->setTransform(canvas_transform(canvas));
  grid->setGridClass(openvdb::GRID_LEVEL_SET);
  openvdb::FloatGrid::Accessor accessor = grid->getAccessor();
  for (std::size_t slot = 0; slot < canvas.slot_count(); ++slot)
    if (canvas.active[slot]) accessor.setValueOn(coord_of(canvas.voxel_of(slot)), outside);
  return grid;
}

// Writes the signed distance to the union of the seed spheres near each seed and records which
// seed owns each of those voxels (the label the extension starts from).
void stamp_seed_spheres(const Canvas& canvas, const std::vector<Vec3>& seeds, double radius,
                        openvdb::FloatGrid& grid, std::vector<int32_t>& owner) {
  openvdb::FloatGrid::Accessor accessor = grid.getAccessor();
  for (std::size_t s = 0; s < seeds.size(); ++s) {
    const VoxelIndex centre = canvas.voxel_containing(seeds[s]);
    for (int dk = -kSeedReach; dk <= kSeedReach; ++dk)
      for (int dj = -kSeedReach; dj <= kSeedReach; ++dj)
        for (int di = -kSeedReach; di <= kSeedReach; ++di) {
          const VoxelIndex v{centre.i + di, centre.j + dj, centre.k + dk};
          const int64_t slot = canvas.slot_of(v);
          if (slot < 0) continue;
          const float value = static_cast<float>((canvas.world_of(v) - seeds[s]).norm() - radius);
          if (value >= accessor.getValue(coord_of(v))) continue;
          accessor.setValueOnly(coord_of(v), value);
          owner[static_cast<std::size_t>(slot)] = static_cast<int32_t>(s);
        }
  }
}

// The extension functor: the label of the seed sphere a zero crossing lies on. OpenVDB 10 gives
// it index-space positions (its extension grid keeps the identity transform, upstream issue
// #1640); the crossing lies next to a stamped voxel, so the nearest voxel has an owner.
class SphereOwnerLabel {
 public:
  SphereOwnerLabel(const Canvas& canvas, const std::vector<int32_t>& owner)
      : canvas_(&canvas), owner_(&owner) {}
  int operator()(const openvdb::Vec3d& index) const {
    const int64_t slot = canvas_->slot_of(static_cast<int>(std::lround(index[0])),
                                          static_cast<int>(std::lround(index[1])),
                                          static_cast<int>(std::lround(index[2])));
    return slot < 0 ? -1 : (*owner_)[static_cast<std::size_t>(slot)];
  }

 private:
  const Canvas* canvas_;
  const std::vector<int32_t>* owner_;
};

VoronoiField read_field(const Canvas& canvas, const openvdb::FloatGrid& distance,
                        const openvdb::Int32Grid& label, double radius) {
  VoronoiField field;
  field.distance.assign(canvas.slot_count(), std::numeric_limits<float>::infinity());
  field.label.assign(canvas.slot_count(), -1);
  const auto distances = distance.getConstAccessor();
  const auto labels = label.getConstAccessor();
  // FastSweeping leaves voxels it could not reach at +max float.
  const float unreached = 0.5f * std::numeric_limits<float>::max();
  for (std::size_t slot = 0; slot < canvas.slot_count(); ++slot) {
    if (!canvas.active[slot]) continue;
    const openvdb::Coord ijk = coord_of(canvas.voxel_of(slot));
    const float value = distances.getValue(ijk);
    if (value >= unreached) continue;
    field.distance[slot] = static_cast<float>(value + radius);
    field.label[slot] = labels.getValue(ijk);
  }
  return field;
}

}  // namespace

FastSweepingRun fast_sweeping_voronoi(const Canvas& canvas, const std::vector<Vec3>& seeds) {
  if (canvas.dimension != 3) throw Error("the FastSweeping baseline needs a 3D canvas");
  openvdb::initialize();
  const double radius = canvas.voxel_size;
  const float outside = static_cast<float>(1e3 * canvas.voxel_size * canvas.dims[0]);
  openvdb::FloatGrid::Ptr sdf = canvas_topology_grid(canvas, outside);
  std::vector<int32_t> owner(canvas.slot_count(), -1);
  stamp_seed_spheres(canvas, seeds, radius, *sdf, owner);

  FastSweepingRun run;
  openvdb::tools::FastSweeping<openvdb::FloatGrid, int> sweeper;
  auto start = Clock::now();
  if (!sweeper.initExt(*sdf, SphereOwnerLabel(canvas, owner), -1, 0.0f, /*isInputSdf=*/true))
    throw Error(
        "OpenVDB FastSweeping could not be initialised from the seeds (it needs room "
        "around them: a coarser canvas than about 4 voxels across can leave it none; "
        "--no-fastsweeping skips the baseline)");
  run.init_seconds = seconds_since(start);
  run.swept_voxels = sweeper.sweepingVoxelCount();
  start = Clock::now();
  sweeper.sweep(1);
  run.sweep_seconds = seconds_since(start);
  run.field = read_field(canvas, *sweeper.sdfGrid(), *sweeper.extGrid(), radius);
  return run;
}

}  // namespace rvor::baseline
