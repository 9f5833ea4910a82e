// The multi-label bricks found by the OpenCL kernel (kernels/nerve.cl) against the host scan
// (find_multi_label_bricks), and the nerve extracted from them against the full scan: boxes and
// domains with holes, 2D and 3D, fields the engine returned and fields it did not.
#include <gtest/gtest.h>

#include <vector>

#include "opencl/opencl_test_support.h"
#include "rvor/canvas_builder.h"
#include "rvor/domain.h"
#include "rvor/metric_field.h"
#include "rvor/nerve.h"
#include "support/box_canvas.h"

namespace rvor {
namespace {

void expect_same_simplices(const std::vector<NerveSimplex>& expected,
                           const std::vector<NerveSimplex>& actual) {
  ASSERT_EQ(expected.size(), actual.size());
  for (std::size_t n = 0; n < expected.size(); ++n) {
    EXPECT_EQ(expected[n].seeds, actual[n].seeds);
    EXPECT_EQ(expected[n].witness_count, actual[n].witness_count);
    EXPECT_EQ(expected[n].farthest.slot, actual[n].farthest.slot);
    EXPECT_EQ(expected[n].nearest.slot, actual[n].nearest.slot);
  }
}

// The kernel's flags equal the host's; the nerve from the flagged bricks equals the full scan.
void expect_kernel_matches_host(Propagator& engine, const Canvas& canvas,
                                const std::vector<Vec3>& seeds, const VoronoiField& field) {
  const std::vector<std::uint8_t> flags = engine.multi_label_bricks(canvas, field);
  ASSERT_EQ(flags, find_multi_label_bricks(canvas, field));
  std::size_t flagged = 0;
  for (const std::uint8_t f : flags) flagged += f;
  EXPECT_GT(flagged, 0u);
  EXPECT_LT(flagged, flags.size());  // the cases are chosen so that some bricks are uniform
  const Nerve all = extract_nerve(canvas, field, seeds.size());
  const Nerve visited = extract_nerve(canvas, field, seeds.size(), flags);
  expect_same_simplices(all.edges, visited.edges);
  expect_same_simplices(all.triangles, visited.triangles);
  expect_same_simplices(all.tetrahedra, visited.tetrahedra);
  EXPECT_EQ(all.degenerate_witness_count, visited.degenerate_witness_count);
}

struct NerveCase {
  const char* name;
  const char* domain;
  const char* metric;
  int resolution;
  int seeds;
};

class MultiLabelBricks : public ::testing::TestWithParam<NerveCase> {};

TEST_P(MultiLabelBricks, KernelMatchesHostOnTheFieldTheEngineReturned) {
  REQUIRE_ENGINE(RelaxationVariant::automatic);
  const Canvas canvas =
      test::domain_canvas(GetParam().domain, GetParam().metric, GetParam().resolution);
  const std::vector<Vec3> seeds = test::seeds_in(canvas, GetParam().seeds, 3);
  VoronoiField field;
  engine->solve(canvas, seeds, field);
  expect_kernel_matches_host(*engine, canvas, seeds, field);
}

const NerveCase kCases[] = {
    {"Box3D", "box:-1,-1,-1,1,1,1", "uniform:4,1,2,0,0.5,1", 48, 40},
    {"Torus3D", "implicit:torus:R=0.6,r=0.25", "uniform:1,0,1,0,0,1", 64, 30},
    {"Rectangle2D", "rect:-1,-1,1,1", "uniform:9,2,1", 160, 60},
    {"Disk2D", "implicit:disk:r=1", "uniform:1,0,4", 160, 40},
};

INSTANTIATE_TEST_SUITE_P(Domains, MultiLabelBricks, ::testing::ValuesIn(kCases),
                         [](const auto& info) { return std::string(info.param.name); });

// A field the engine did not return (the CPU reference's) is uploaded; inserting into it
// afterwards still equals solving with all seeds at once.
TEST(MultiLabelBricksUpload, FieldFromTheReferenceThenInsertion) {
  REQUIRE_ENGINE(RelaxationVariant::automatic);
  const Canvas canvas = test::domain_canvas("box:-1,-1,-1,1,1,1", "uniform:4,1,2,0,0.5,1", 32);
  const std::vector<Vec3> seeds = test::seeds_in(canvas, 12, 5);
  const std::vector<Vec3> first(seeds.begin(), seeds.end() - 1);
  VoronoiField expected, other, field;
  engine->solve(canvas, seeds, expected);
  make_reference_propagator()->solve(canvas, first, field);
  engine->solve(canvas, {seeds.front()}, other);  // the device now holds another field
  expect_kernel_matches_host(*engine, canvas, first, field);
  engine->insert(canvas, seeds, first.size(), field);
  test::expect_same_field(canvas, expected, field);
}

TEST(MultiLabelBricksUpload, MismatchedFieldsAndFlagsAreErrors) {
  REQUIRE_ENGINE(RelaxationVariant::automatic);
  const Canvas canvas = test::domain_canvas("rect:-1,-1,1,1", "uniform:1,0,1", 32);
  VoronoiField field;
  engine->solve(canvas, {Vec3(0.1, 0.2, 0.0), Vec3(-0.5, 0.3, 0.0)}, field);
  VoronoiField truncated = field;
  truncated.label.pop_back();
  truncated.distance.pop_back();
  EXPECT_THROW(engine->multi_label_bricks(canvas, truncated), Error);
  EXPECT_THROW(find_multi_label_bricks(canvas, truncated), Error);
  EXPECT_THROW(extract_nerve(canvas, field, 2, std::vector<std::uint8_t>(1, 1)), Error);
}

}  // namespace
}  // namespace rvor
