// pack_stencils (host/src/opencl/device_canvas.h): every active slot's record gives back the
// Selling stencil of its metric, through a table that holds each offset set once. reader_reach
// (reader_reach.h): every brick's reach covers every stencil that reads one of its voxels.
#include <gtest/gtest.h>

#include <memory>
#include <set>
#include <string>
#include <vector>

#include <Eigen/LU>

#include "device_canvas.h"
#include "reader_reach.h"
#include "rvor/canvas_builder.h"
#include "rvor/domain.h"
#include "rvor/metric_field.h"
#include "rvor/selling.h"

namespace rvor::opencl {
namespace {

Canvas make_canvas(const std::string& domain, const std::string& metric, int resolution) {
  const DomainSpec spec = parse_domain(domain);
  const std::unique_ptr<MetricField> field = make_analytic_metric(metric, spec.dimension());
  CanvasOptions options;
  options.resolution = resolution;
  return build_canvas(spec, *field, options);
}

// The stencils as the engine packs them: weights in its length unit.
PackedStencils engine_stencils(const Canvas& canvas) {
  return pack_stencils(canvas, device_length_unit(canvas));
}

// Compares each active slot with a Selling decomposition computed here, independently of the
// packer's caches and threads.
void expect_packed_stencils(const Canvas& canvas, const PackedStencils& packed) {
  const double unit = device_length_unit(canvas);
  const double h2 = canvas.voxel_size * canvas.voxel_size / (unit * unit);
  std::size_t compared = 0;
  for (std::size_t slot = 0; slot < canvas.slot_count(); ++slot) {
    if (!canvas.active[slot]) continue;
    const std::size_t record = packed.uniform ? 0 : slot;
    const SellingStencil expected =
        selling_decomposition(canvas.metric_at(slot).inverse(), canvas.dimension);
    ASSERT_LT(packed.shape_of(record), packed.shape_count()) << "slot " << slot;
    for (int i = 0; i < kStencilTerms; ++i) {
      const float weight = packed.records[kStencilRecord * record + static_cast<std::size_t>(i)];
      if (i >= expected.size) {
        EXPECT_EQ(weight, 0.0f) << "slot " << slot << " term " << i;
        continue;
      }
      EXPECT_EQ(weight, static_cast<float>(expected.weight[static_cast<std::size_t>(i)] / h2))
          << "slot " << slot << " term " << i;
      for (int a = 0; a < 3; ++a)
        ASSERT_EQ(packed.offset(record, i, a),
                  expected.offset[static_cast<std::size_t>(i)][static_cast<std::size_t>(a)])
            << "slot " << slot << " term " << i << " axis " << a;
    }
    ++compared;
  }
  EXPECT_EQ(compared, canvas.active_voxel_count);
}

std::size_t distinct_shapes(const PackedStencils& packed) {
  const std::size_t size = 3 * kStencilTerms;
  std::set<std::vector<std::int8_t>> shapes;
  for (std::size_t s = 0; s < packed.shape_count(); ++s)
    shapes.emplace(packed.shapes.begin() + static_cast<std::ptrdiff_t>(s * size),
                   packed.shapes.begin() + static_cast<std::ptrdiff_t>((s + 1) * size));
  return shapes.size();
}

// A varying field: every slot checked, and the packers (slot ranges in parallel) merge their
// tables without duplicates. Returns the shape count.
std::size_t expect_varying_packing(const Canvas& canvas) {
  const PackedStencils packed = engine_stencils(canvas);
  EXPECT_FALSE(packed.uniform);
  expect_packed_stencils(canvas, packed);
  EXPECT_EQ(distinct_shapes(packed), packed.shape_count());
  return packed.shape_count();
}

TEST(StencilPacking, VaryingMetricRecordsGiveBackEachSlotsStencil) {
  const Canvas canvas = make_canvas("box:1,1,1,11,11,11", "radial_shock_3d", 40);
  const std::size_t shapes = expect_varying_packing(canvas);
  EXPECT_GT(shapes, 10u);  // the field's stencils do change across the canvas
  EXPECT_LT(shapes, canvas.active_voxel_count / 4);
}

TEST(StencilPacking, TwoDimensionalFieldOnACurvedDomain) {
  expect_varying_packing(make_canvas("implicit:disk", "swirl", 96));
}

TEST(StencilPacking, UniformMetricHasOneRecordAndOneShape) {
  const Canvas canvas = make_canvas("box:-1,-1,-1,1,1,1", "uniform:10,3,5,2,1,4", 24);
  const PackedStencils packed = engine_stencils(canvas);
  ASSERT_TRUE(packed.uniform);
  EXPECT_EQ(packed.records.size(), std::size_t{kStencilRecord});
  EXPECT_EQ(packed.shape_count(), 1u);
  expect_packed_stencils(canvas, packed);
}

int unpacked_reach(std::uint32_t packed, int axis) {
  return static_cast<int>((packed >> (8 * axis)) & 255u);
}

// Every stencil read, found by brute force: voxel y reads y +- e_i for each of its terms; the
// brick holding the read voxel must have a reader reach of at least |e_i| on every axis, and may
// claim axis readers only when e_i lies along an axis. Returns how many bricks have a reach below
// the canvas's largest on some axis.
std::size_t expect_reach_covers_every_read(const Canvas& canvas) {
  const PackedStencils packed = engine_stencils(canvas);
  const std::vector<std::uint32_t> reach = reader_reach(canvas, packed);
  EXPECT_EQ(reach.size(), canvas.brick_count());
  const std::size_t volume = static_cast<std::size_t>(canvas.brick_volume());
  std::size_t reads = 0, uncovered = 0;
  std::string first_uncovered;
  for (std::size_t slot = 0; slot < canvas.slot_count(); ++slot) {
    if (!canvas.active[slot]) continue;
    const std::size_t record = packed.uniform ? 0 : slot;
    const VoxelIndex y = canvas.voxel_of(slot);
    for (int i = 0; i < kStencilTerms; ++i) {
      if (packed.records[kStencilRecord * record + static_cast<std::size_t>(i)] == 0.0f) continue;
      const int e[3] = {packed.offset(record, i, 0), packed.offset(record, i, 1),
                        packed.offset(record, i, 2)};
      for (int sign = -1; sign <= 1; sign += 2) {
        const int64_t read =
            canvas.slot_of(VoxelIndex{y.i + sign * e[0], y.j + sign * e[1], y.k + sign * e[2]});
        if (read < 0 || !canvas.active[static_cast<std::size_t>(read)]) continue;
        ++reads;
        const std::uint32_t brick_reach = reach[static_cast<std::size_t>(read) / volume];
        bool covered =
            (brick_reach & kAxisReaders) == 0 || (e[0] != 0) + (e[1] != 0) + (e[2] != 0) <= 1;
        for (int a = 0; a < 3; ++a)
          covered = covered && unpacked_reach(brick_reach, a) >= std::abs(e[a]);
        if (!covered && uncovered++ == 0)
          first_uncovered = "voxel slot " + std::to_string(slot) + " reads slot " +
                            std::to_string(read) + " with term " + std::to_string(i);
      }
    }
  }
  EXPECT_EQ(uncovered, 0u) << "first: " << first_uncovered;
  EXPECT_GT(reads, canvas.active_voxel_count);
  std::size_t shorter = 0;
  for (std::uint32_t r : reach)
    for (int a = 0; a < 3; ++a)
      if (unpacked_reach(r, a) < packed.reach[static_cast<std::size_t>(a)]) {
        ++shorter;
        break;
      }
  return shorter;
}

TEST(ReaderReach, CoversEveryReadOfAVaryingField) {
  // radial_shock_3d: long offsets (up to 8 voxels at 64^3) near the shock sphere only.
  const std::size_t shorter =
      expect_reach_covers_every_read(make_canvas("box:1,1,1,11,11,11", "radial_shock_3d", 64));
  EXPECT_GT(shorter, 0u);  // bricks away from the shock are read by short stencils only
}

TEST(ReaderReach, CoversEveryReadInTwoDimensionsOnACurvedDomain) {
  expect_reach_covers_every_read(make_canvas("implicit:disk", "swirl", 96));
}

TEST(ReaderReach, DiagonalMetricsAreReadAlongAxesOnly) {
  for (const char* metric : {"euclidean", "uniform:4,0,1,0,0,9"}) {
    const Canvas canvas = make_canvas("box:-1,-1,-1,1,1,1", metric, 24);
    expect_reach_covers_every_read(canvas);
    for (std::uint32_t r : reader_reach(canvas, engine_stencils(canvas)))
      ASSERT_NE(r & kAxisReaders, 0u) << metric;
  }
}

TEST(ReaderReach, UniformMetricReachesAsFarEverywhere) {
  EXPECT_EQ(
      expect_reach_covers_every_read(make_canvas("box:-1,-1,-1,1,1,1", "uniform:10,3,5,2,1,4", 24)),
      0u);
}

}  // namespace
}  // namespace rvor::opencl
