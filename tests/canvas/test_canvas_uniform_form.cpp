// The canvas's uniform form: a metric that is the same everywhere is stored once, not per slot,
// and reads, hashes and changes as the per-slot form of the same tensors does.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstddef>
#include <cstring>
#include <string>

#include "rvor/canvas.h"
#include "rvor/canvas_builder.h"
#include "rvor/domain.h"
#include "rvor/error.h"
#include "rvor/metric_field.h"

namespace rvor {
namespace {

Canvas built(const std::string& domain, const std::string& metric, int resolution) {
  const DomainSpec spec = parse_domain(domain);
  CanvasOptions options;
  options.resolution = resolution;
  return build_canvas(spec, *make_analytic_metric(metric, spec.dimension()), options);
}

std::array<float, 6> floats_of(const Canvas& canvas, std::size_t slot) {
  const float* m = canvas.metric_of(slot);
  return {m[0], m[1], m[2], m[3], m[4], m[5]};
}

// The same canvas in the per-slot form (mutable_metric turns it, writing nothing).
Canvas per_slot_copy(const Canvas& canvas) {
  Canvas copy = canvas;
  copy.mutable_metric(0);
  copy.finalize();
  return copy;
}

// A sphere leaves inactive slots in its bricks, which read as zeros in both forms.
TEST(CanvasUniformForm, TheBuilderStoresAUniformFieldOnce) {
  const Canvas sphere = built("implicit:sphere", "euclidean:scale=1.3", 24);
  ASSERT_TRUE(sphere.uniform_metric().has_value());
  const float m11 = static_cast<float>(1.3 * 1.3);
  const std::array<float, 6> tensor{m11, 0, m11, 0, 0, m11}, none{};
  std::size_t inactive = 0;
  for (std::size_t slot = 0; slot < sphere.slot_count(); ++slot) {
    EXPECT_EQ(floats_of(sphere, slot), sphere.active[slot] ? tensor : none) << slot;
    inactive += !sphere.active[slot];
  }
  EXPECT_GT(inactive, 0u);

  const Canvas planar = built("rect:0,0,2,1", "uniform:5,1,2", 32);
  ASSERT_TRUE(planar.uniform_metric().has_value());
  EXPECT_EQ(floats_of(planar, 0), (std::array<float, 6>{5, 1, 2, 0, 0, 1}));  // z row 0, 0, 1

  EXPECT_FALSE(built("box:-1,-1,-1,1,1,1", "hyperbolic_shock", 16).uniform_metric().has_value());
}

TEST(CanvasUniformForm, BothFormsReadAndHashTheSame) {
  for (const char* domain : {"implicit:sphere", "rect:0,0,2,1"}) {
    const Canvas uniform = built(domain, domain[0] == 'r' ? "uniform:5,1,2" : "euclidean", 24);
    const Canvas per_slot = per_slot_copy(uniform);
    ASSERT_FALSE(per_slot.uniform_metric().has_value());
    for (std::size_t slot = 0; slot < uniform.slot_count(); ++slot)
      ASSERT_EQ(floats_of(per_slot, slot), floats_of(uniform, slot)) << domain << " " << slot;
    ASSERT_TRUE(uniform.content_hash().has_value());
    EXPECT_EQ(per_slot.content_hash(), uniform.content_hash()) << domain;
  }
}

// set_active with another tensor, or a tensor written by hand, turns the canvas into the
// per-slot form, and only that slot changes.
TEST(CanvasUniformForm, AnotherTensorTurnsItIntoThePerSlotForm) {
  const Canvas original = built("box:0,0,0,1,1,1", "euclidean", 16);
  const std::size_t changed_slot = 777;
  Canvas changed = original;
  changed.set_active(changed_slot, 2.0 * Mat3::Identity());
  EXPECT_FALSE(changed.uniform_metric().has_value());
  changed.finalize();
  EXPECT_NE(changed.content_hash(), original.content_hash());
  for (std::size_t slot = 0; slot < original.slot_count(); ++slot) {
    if (slot == changed_slot)
      EXPECT_EQ(floats_of(changed, slot), (std::array<float, 6>{2, 0, 2, 0, 0, 2}));
    else
      ASSERT_EQ(floats_of(changed, slot), floats_of(original, slot)) << slot;
  }

  Canvas same = original;
  same.set_active(changed_slot, Mat3::Identity());  // its own tensor: the form stays
  EXPECT_TRUE(same.uniform_metric().has_value());

  Canvas by_hand = original;
  by_hand.mutable_metric(changed_slot)[2] = 3.0f;
  by_hand.finalize();
  EXPECT_FALSE(by_hand.uniform_metric().has_value());
  EXPECT_EQ(floats_of(by_hand, changed_slot), (std::array<float, 6>{1, 0, 3, 0, 0, 1}));
  EXPECT_NE(by_hand.content_hash(), original.content_hash());
}

// A field of tensors in slabs across x, which may claim to be uniform: odd slabs have an
// off-diagonal 0.25; even ones are the identity, with -0 or 0 off the diagonal in slabs across y
// (equal as numbers, not as stored bits).
class SlabField final : public MetricField {
 public:
  explicit SlabField(bool claims_uniform) : claims_uniform_(claims_uniform) {}
  int dimension() const override { return 3; }
  Mat3 at(const Vec3& p) const override {
    const bool odd = static_cast<int>(std::floor(p.x() * 10.0)) % 2 != 0;
    const bool negative_zero = static_cast<int>(std::floor(p.y() * 10.0)) % 2 != 0;
    Mat3 G = Mat3::Identity();
    if (odd)
      G(0, 1) = G(1, 0) = 0.25;
    else if (negative_zero)
      G(0, 2) = G(2, 0) = -0.0;
    return G;
  }
  std::string description() const override { return "slabs"; }
  bool is_uniform() const override { return claims_uniform_; }

 private:
  bool claims_uniform_;
};

// The builder converts a tensor once for a run of voxels that are given the same one: a field
// that alternates along each row still gets each voxel's own tensor, bit for bit.
TEST(CanvasUniformForm, TheBuilderStoresEachVoxelsOwnTensor) {
  const DomainSpec spec = parse_domain("box:0,0,0,1,1,1");
  CanvasOptions options;
  options.resolution = 20;
  const SlabField field(false);
  const Canvas canvas = build_canvas(spec, field, options);
  ASSERT_FALSE(canvas.uniform_metric().has_value());
  std::size_t odd = 0, negative_zeros = 0;
  for (std::size_t slot = 0; slot < canvas.slot_count(); ++slot) {
    if (!canvas.active[slot]) continue;
    const Mat3 expected = field.at(canvas.world_of(canvas.voxel_of(slot)));
    const std::array<float, 6> stored = floats_of(canvas, slot);
    const std::array<float, 6> own = Canvas::stored_tensor(expected, 3);
    ASSERT_EQ(std::memcmp(stored.data(), own.data(), sizeof stored), 0) << slot;
    negative_zeros += std::signbit(stored[3]) ? 1 : 0;
    odd += expected(0, 1) != 0 ? 1 : 0;
  }
  EXPECT_GT(odd, canvas.active_voxel_count / 4);
  EXPECT_LT(odd, canvas.active_voxel_count * 3 / 4);
  EXPECT_GT(negative_zeros, canvas.active_voxel_count / 8);
}

TEST(CanvasUniformForm, AFieldThatClaimsToBeUniformAndIsNotIsRefused) {
  const DomainSpec spec = parse_domain("box:0,0,0,1,1,1");
  CanvasOptions options;
  options.resolution = 20;
  try {
    build_canvas(spec, SlabField(true), options);
    FAIL() << "built";
  } catch (const Error& error) {
    EXPECT_NE(std::string(error.what()).find("'slabs' claims to be uniform but differs at"),
              std::string::npos)
        << error.what();
  }
}

}  // namespace
}  // namespace rvor
