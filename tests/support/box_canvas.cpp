#include "support/box_canvas.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

namespace rvor::test {

Canvas make_box_canvas(int dimension, const Vec3& lo, const Vec3& hi, int resolution,
                       const MetricFunction& metric) {
  const Vec3 extent = hi - lo;
  const double longest = dimension == 3 ? extent.maxCoeff() : std::max(extent.x(), extent.y());
  const double h = longest / resolution;
  std::array<int, 3> dims{};
  for (int a = 0; a < 3; ++a) dims[a] = std::max(1, static_cast<int>(std::lround(extent[a] / h)));
  if (dimension == 2) dims[2] = 1;
  const Vec3 origin = lo + 0.5 * h * Vec3(1, 1, dimension == 3 ? 1 : 0);

  const int ez = dimension == 3 ? Canvas::kBrickEdge : 1;
  std::vector<VoxelIndex> bricks;
  for (int k = 0; k < dims[2]; k += ez)
    for (int j = 0; j < dims[1]; j += Canvas::kBrickEdge)
      for (int i = 0; i < dims[0]; i += Canvas::kBrickEdge) bricks.push_back({i, j, k});

  Canvas canvas;
  canvas.allocate(dimension, h, origin, dims, bricks);
  for (std::size_t slot = 0; slot < canvas.slot_count(); ++slot) {
    const VoxelIndex v = canvas.voxel_of(slot);
    if (v.i >= dims[0] || v.j >= dims[1] || v.k >= dims[2]) continue;
    canvas.set_active(slot, metric(canvas.world_of(v)));
  }
  canvas.finalize();
  canvas.description = "test box canvas";
  return canvas;
}

Canvas make_uniform_box_canvas(int dimension, const Vec3& lo, const Vec3& hi, int resolution,
                               const Mat3& G) {
  return make_box_canvas(dimension, lo, hi, resolution, [&G](const Vec3&) { return G; });
}

VoronoiField constant_field(const Canvas& canvas, float distance, int label) {
  VoronoiField field;
  field.distance.assign(canvas.slot_count(), distance);
  field.label.assign(canvas.slot_count(), label);
  return field;
}

Canvas box_with_a_wall(int dimension, int resolution) {
  Canvas canvas = make_uniform_box_canvas(dimension, Vec3(-1, -1, -1), Vec3(1, 1, 1), resolution,
                                          Mat3::Identity());
  for (std::size_t slot = 0; slot < canvas.slot_count(); ++slot) {
    const Vec3 p = canvas.world_of(slot);
    if (p.x() >= -0.2 && p.x() < 0.03 && p.y() >= -0.5) canvas.active[slot] = 0;
  }
  canvas.finalize();
  return canvas;
}

Canvas split_inside_a_quarter(int dimension, int axis) {
  Canvas canvas = make_uniform_box_canvas(dimension, Vec3(-1, -1, -1), Vec3(1, 1, 1),
                                          dimension == 3 ? 32 : 64, Mat3::Identity());
  for (std::size_t slot = 0; slot < canvas.slot_count(); ++slot) {
    const VoxelIndex v = canvas.voxel_of(slot);
    if ((axis == 0 ? v.i : axis == 1 ? v.j : v.k) == 20) canvas.active[slot] = 0;
  }
  canvas.finalize();
  return canvas;
}

std::vector<Vec3> lower_piece_seeds(int dimension, int axis) {
  std::vector<Vec3> seeds{Vec3(0.1, 0.2, 0.3), Vec3(-0.3, 0.1, -0.2)};
  const double h = 2.0 / (dimension == 3 ? 32 : 64);
  for (std::size_t n = 0; n < seeds.size(); ++n) {
    seeds[n][axis] = -1.0 + (5.5 + 6 * n) * h;  // voxels 5 and 11 along the axis
    if (dimension == 2) seeds[n].z() = 0.0;
  }
  return seeds;
}

BandCounts count_piece_labels(const Canvas& canvas, int axis, int first_right,
                              const std::vector<int32_t>& labels) {
  BandCounts counts;
  for (std::size_t slot = 0; slot < canvas.slot_count(); ++slot) {
    if (!canvas.active[slot]) continue;
    const VoxelIndex v = canvas.voxel_of(slot);
    const bool lower = (axis == 0 ? v.i : axis == 1 ? v.j : v.k) < first_right;
    const bool labelled = labels[slot] >= 0;
    (lower ? counts.left_voxels : counts.right_voxels) += 1;
    (lower ? counts.left_labelled : counts.right_labelled) += labelled ? 1 : 0;
  }
  return counts;
}

Canvas two_bands_claimed_convex() {
  Canvas canvas = make_uniform_box_canvas(2, Vec3(-1, -1, 0), Vec3(1, 1, 0), 64, Mat3::Identity());
  for (std::size_t slot = 0; slot < canvas.slot_count(); ++slot)
    if (canvas.voxel_of(slot).i >= 28 && canvas.voxel_of(slot).i < 36) canvas.active[slot] = 0;
  canvas.finalize();
  canvas.convex_domain = true;
  return canvas;
}

std::vector<Vec3> left_band_seeds() {
  return {Vec3(-0.7, 0.2, 0), Vec3(-0.5, -0.6, 0)};
}

BandCounts count_band_labels(const Canvas& canvas, const std::vector<int32_t>& labels) {
  return count_piece_labels(canvas, 0, 28, labels);
}

void expect_only_left_labelled(const BandCounts& counts) {
  EXPECT_EQ(counts.left_labelled, counts.left_voxels);
  EXPECT_EQ(counts.right_labelled, 0u);
  EXPECT_GT(counts.right_voxels, 0u);
}

void slow_down_a_brick_between_sampled_slots(Canvas& canvas) {
  const std::size_t sample_step = std::max<std::size_t>(1, canvas.slot_count() / 4096);
  const std::size_t brick = canvas.brick_count() / 2, volume = canvas.brick_volume();
  for (std::size_t slot = brick * volume; slot < (brick + 1) * volume; ++slot)
    if (slot % sample_step != 0) canvas.set_active(slot, 25.0 * Mat3::Identity());
  canvas.finalize();
}

}  // namespace rvor::test
