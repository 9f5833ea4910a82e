// Nerve extraction on hand-made labelings: which Delaunay simplices a labeled canvas witnesses,
// their witnesses, degenerate cells and errors.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "rvor/error.h"
#include "rvor/nerve.h"
#include "rvor/propagation.h"
#include "support/box_canvas.h"

namespace rvor {
namespace {

// Labels every voxel with the nearest of `seeds` (Euclidean), distance = that distance.
VoronoiField nearest_seed_field(const Canvas& canvas, const std::vector<Vec3>& seeds) {
  VoronoiField field = test::constant_field(canvas, std::numeric_limits<float>::infinity(), -1);
  for (std::size_t slot = 0; slot < canvas.slot_count(); ++slot) {
    if (!canvas.active[slot]) continue;
    const Vec3 p = canvas.world_of(slot);
    for (std::size_t s = 0; s < seeds.size(); ++s) {
      const float d = static_cast<float>((p - seeds[s]).norm());
      if (d < field.distance[slot]) {
        field.distance[slot] = d;
        field.label[slot] = static_cast<int32_t>(s);
      }
    }
  }
  return field;
}

TEST(Nerve, FourSeedsIn3DGiveOneTetrahedronWithAllFaces) {
  const Canvas canvas =
      test::make_uniform_box_canvas(3, Vec3(0, 0, 0), Vec3(1, 1, 1), 24, Mat3::Identity());
  const std::vector<Vec3> seeds{
      {0.2, 0.2, 0.2}, {0.8, 0.25, 0.3}, {0.3, 0.75, 0.25}, {0.35, 0.3, 0.8}};
  const Nerve nerve = extract_nerve(canvas, nearest_seed_field(canvas, seeds), seeds.size());
  EXPECT_EQ(nerve.dimension, 3);
  EXPECT_EQ(nerve.edges.size(), 6u);
  EXPECT_EQ(nerve.triangles.size(), 4u);
  ASSERT_EQ(nerve.tetrahedra.size(), 1u);
  const NerveSimplex& tet = nerve.tetrahedra[0];
  EXPECT_EQ(tet.seeds, (std::array<int32_t, 4>{0, 1, 2, 3}));
  EXPECT_EQ(tet.vertex_count, 4);
  EXPECT_GE(tet.witness_count, 1u);
  EXPECT_GE(tet.farthest.distance, tet.nearest.distance);
  // The witness of the tetrahedron is near the Voronoi vertex: equidistant from the four seeds.
  const Vec3 w = tet.farthest.position;
  for (const Vec3& s : seeds)
    EXPECT_NEAR((w - s).norm(), (w - seeds[0]).norm(), 2.5 * canvas.voxel_size);
  EXPECT_NE(nerve.find({3, 1, 0, 2}), nullptr);
  EXPECT_NE(nerve.find({2, 1}), nullptr);
  EXPECT_EQ(nerve.find({0, 1, 2, 4}), nullptr);
  EXPECT_EQ(nerve.degenerate_witness_count, 0u);
}

TEST(Nerve, EdgeNearestWitnessIsTheBisectorPointClosestToTheSeeds) {
  const Canvas canvas =
      test::make_uniform_box_canvas(2, Vec3(0, 0, 0), Vec3(1, 1, 0), 40, Mat3::Identity());
  const std::vector<Vec3> seeds{{0.3, 0.5, 0}, {0.7, 0.5, 0}};
  const Nerve nerve = extract_nerve(canvas, nearest_seed_field(canvas, seeds), seeds.size());
  ASSERT_EQ(nerve.edges.size(), 1u);
  EXPECT_TRUE(nerve.triangles.empty());
  const NerveSimplex& edge = nerve.edges[0];
  EXPECT_NEAR(edge.nearest.position.x(), 0.5, canvas.voxel_size);
  EXPECT_NEAR(edge.nearest.position.y(), 0.5, canvas.voxel_size);
  EXPECT_NEAR(edge.nearest.distance, 0.2, canvas.voxel_size);
  EXPECT_GT(edge.farthest.distance, 0.5);  // the bisector reaches the domain's corners
}

TEST(Nerve, FourCocircularSeedsIn2DAreReportedAsDegenerate) {
  const Canvas canvas =
      test::make_uniform_box_canvas(2, Vec3(0, 0, 0), Vec3(1, 1, 0), 32, Mat3::Identity());
  // On a circle about the centre of a grid cell (0.5, 0.5), rotated so that no voxel is
  // equidistant from two seeds: the four cells meet inside that one square.
  std::vector<Vec3> seeds;
  for (double degrees : {10.0, 100.0, 190.0, 280.0}) {
    const double a = degrees * M_PI / 180.0;
    seeds.emplace_back(0.5 + 0.25 * std::cos(a), 0.5 + 0.25 * std::sin(a), 0.0);
  }
  const Nerve nerve = extract_nerve(canvas, nearest_seed_field(canvas, seeds), seeds.size());
  EXPECT_EQ(nerve.degenerate_witness_count, 1u);
  ASSERT_EQ(nerve.degenerate_witnesses.size(), 1u);
  EXPECT_EQ(nerve.degenerate_witnesses[0].labels, (std::vector<int32_t>{0, 1, 2, 3}));
  EXPECT_EQ(nerve.triangles.size(), 2u);  // one of the two diagonals, picked by the subdivision
}

// A brick is flagged exactly when the nerve of that brick alone is not empty: flagged bricks are
// the ones the nerve needs, and only them.
TEST(Nerve, MultiLabelBricksAreTheBricksThatWitnessSimplices) {
  const Canvas canvas =
      test::make_uniform_box_canvas(3, Vec3(0, 0, 0), Vec3(1, 1, 1), 40, Mat3::Identity());
  const std::vector<Vec3> seeds{
      {0.2, 0.2, 0.2}, {0.8, 0.25, 0.3}, {0.3, 0.75, 0.25}, {0.35, 0.3, 0.8}};
  const VoronoiField field = nearest_seed_field(canvas, seeds);
  const std::vector<std::uint8_t> flags = find_multi_label_bricks(canvas, field);
  ASSERT_EQ(flags.size(), canvas.brick_count());
  std::size_t flagged = 0;
  for (std::size_t b = 0; b < flags.size(); ++b) {
    std::vector<std::uint8_t> only(flags.size(), 0);
    only[b] = 1;
    const Nerve nerve = extract_nerve(canvas, field, seeds.size(), only);
    EXPECT_EQ(flags[b] != 0, !nerve.edges.empty()) << "brick " << b;
    flagged += flags[b];
  }
  EXPECT_GT(flagged, 0u);
  EXPECT_LT(flagged, flags.size());
}

TEST(Nerve, RejectsFieldsThatDoNotMatch) {
  const Canvas canvas =
      test::make_uniform_box_canvas(2, Vec3(0, 0, 0), Vec3(1, 1, 0), 16, Mat3::Identity());
  VoronoiField field = nearest_seed_field(canvas, {{0.2, 0.2, 0}, {0.8, 0.8, 0}});
  EXPECT_THROW(extract_nerve(canvas, field, 1), Error);  // label 1 is not a seed
  field.label.pop_back();
  EXPECT_THROW(extract_nerve(canvas, field, 2), Error);
}

}  // namespace
}  // namespace rvor
