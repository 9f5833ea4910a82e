// pack_stencils (host/src/opencl/device_canvas.h): every active slot's record gives back the
// Selling stencil of its metric, through a table that holds each offset set once.
#include <gtest/gtest.h>

#include <memory>
#include <set>
#include <vector>

#include <Eigen/LU>

#include "device_canvas.h"
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

// Compares each active slot with a Selling decomposition computed here, independently of the
// packer's caches and threads.
void expect_packed_stencils(const Canvas& canvas, const PackedStencils& packed) {
  const double h2 = canvas.voxel_size * canvas.voxel_size;
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
  const PackedStencils packed = pack_stencils(canvas);
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
  const PackedStencils packed = pack_stencils(canvas);
  ASSERT_TRUE(packed.uniform);
  EXPECT_EQ(packed.records.size(), std::size_t{kStencilRecord});
  EXPECT_EQ(packed.shape_count(), 1u);
  expect_packed_stencils(canvas, packed);
}

}  // namespace
}  // namespace rvor::opencl
