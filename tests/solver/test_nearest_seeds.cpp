// The exact start's per-brick seed lists (rvor/nearest_seeds.h) against brute force: every seed of
// least u0 at every voxel is listed for the voxel's brick; and where the exact start applies.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "rvor/nearest_seeds.h"
#include "rvor/propagation.h"
#include "solver_fixtures.h"

namespace rvor::test {
namespace {

const Vec3 kLo(-1, -1, -1), kHi(1, 1, 1);

// `count` points uniform in the box scaled by `spread` around `centre` (z = 0 in 2D).
std::vector<Vec3> points_around(const Vec3& centre, double spread, int dimension, int count,
                                unsigned rng_seed) {
  std::mt19937 rng(rng_seed);
  std::uniform_real_distribution<double> unit(-0.95, 0.95);
  std::vector<Vec3> points;
  for (int n = 0; n < count; ++n) {
    Vec3 p = centre + spread * Vec3(unit(rng), unit(rng), unit(rng));
    if (dimension == 2) p.z() = 0;
    points.push_back(p);
  }
  return points;
}

// For every active voxel, each seed whose u0 is the least (to a relative 1e-12) is in the list of
// the voxel's brick. Returns the mean list length; `tied_voxels`, when given, counts the voxels
// with more than one such seed.
double expect_lists_hold_nearest_seeds(const Canvas& canvas, const std::vector<Vec3>& seeds,
                                       std::size_t* tied_voxels = nullptr) {
  const BrickSeedLists lists = nearest_seed_candidates(canvas, seeds);
  EXPECT_EQ(lists.begin.size(), canvas.brick_count() + 1);
  const Mat3 G = canvas.metric_at(0);
  std::vector<double> u0(seeds.size());
  for (std::size_t slot = 0; slot < canvas.slot_count(); ++slot) {
    if (!canvas.active[slot]) continue;
    const Vec3 x = canvas.world_of(slot);
    for (std::size_t s = 0; s < seeds.size(); ++s)
      u0[s] = std::sqrt((x - seeds[s]).dot(G * (x - seeds[s])));
    const double least = *std::min_element(u0.begin(), u0.end());
    if (tied_voxels)
      *tied_voxels += std::count_if(u0.begin(), u0.end(),
                                    [&](double d) { return d <= least * (1 + 1e-12); }) > 1;
    const std::size_t brick = slot / canvas.brick_volume();
    const auto first = lists.seeds.begin() + lists.begin[brick];
    const auto last = lists.seeds.begin() + lists.begin[brick + 1];
    for (std::size_t s = 0; s < seeds.size(); ++s)
      if (u0[s] <= least * (1 + 1e-12) &&
          !std::binary_search(first, last, static_cast<std::int32_t>(s))) {
        ADD_FAILURE() << "seed " << s << " is nearest to slot " << slot
                      << " but not listed for its brick";
        return 0.0;
      }
  }
  return static_cast<double>(lists.seeds.size()) / static_cast<double>(canvas.brick_count());
}

TEST(NearestSeeds, ListsHoldEveryVoxelsNearestSeeds) {
  const Mat3 diagonal = Vec3(1.0, 9.0, 4.0).asDiagonal();
  for (const int dimension : {2, 3})
    for (const Mat3& G : {Mat3(Mat3::Identity()), diagonal, Mat3(Vec3(100, 1, 1).asDiagonal())}) {
      const Canvas canvas =
          make_uniform_box_canvas(dimension, kLo, kHi, dimension == 3 ? 40 : 160, G);
      const Vec3 corner(-0.8, 0.7, dimension == 3 ? -0.6 : 0.0);
      for (const std::vector<Vec3>& seeds :
           {points_around(Vec3::Zero(), 1.0, dimension, 1, 3),
            points_around(Vec3::Zero(), 1.0, dimension, 300, 5),
            points_around(corner, 0.1, dimension, 40, 7)}) {  // far bricks need far seeds
        SCOPED_TRACE(std::to_string(dimension) + "D, " + std::to_string(seeds.size()) + " seeds");
        const double mean = expect_lists_hold_nearest_seeds(canvas, seeds);
        std::printf("[ measured ] %dD, diag(%g, %g, %g), %zu seeds: %.1f seeds listed per brick\n",
                    dimension, G(0, 0), G(1, 1), G(2, 2), seeds.size(), mean);
        // Spread seeds are cut to those near each brick (every seed listed would pass above).
        if (seeds.size() == 300) {
          EXPECT_LT(mean, 150.0);
        }
      }
    }
}

// bricks_seeds_may_lower against brute force: with the old seeds' least u0 as the solved field,
// every brick where a new seed's u0 lies below it at some voxel is found, and one new seed among
// many finds a small part of the canvas.
TEST(NearestSeeds, InsertionsFindEveryBrickANewSeedLowers) {
  for (const int dimension : {2, 3})
    for (const Mat3& G : {Mat3(Mat3::Identity()), Mat3(Vec3(1.0, 9.0, 4.0).asDiagonal())}) {
      const Canvas canvas =
          make_uniform_box_canvas(dimension, kLo, kHi, dimension == 3 ? 40 : 160, G);
      const std::vector<Vec3> old_seeds = points_around(Vec3::Zero(), 1.0, dimension, 300, 5);
      // The voxel centres of a 2D canvas lie at z = kLo.z; its seeds at z = 0.
      const auto u0 = [&](Vec3 x, const Vec3& s) {
        if (dimension == 2) x.z() = 0.0;
        return std::sqrt((x - s).dot(G * (x - s)));
      };
      std::vector<float> distance(canvas.slot_count(), std::numeric_limits<float>::infinity());
      for (std::size_t slot = 0; slot < canvas.slot_count(); ++slot) {
        if (!canvas.active[slot]) continue;
        double least = std::numeric_limits<double>::infinity();
        for (const Vec3& s : old_seeds) least = std::min(least, u0(canvas.world_of(slot), s));
        distance[slot] = static_cast<float>(least);
      }
      for (const int count : {1, 30}) {
        SCOPED_TRACE(std::to_string(dimension) + "D, diag(" + std::to_string(G(1, 1)) + "), " +
                     std::to_string(count) + " new seeds");
        const std::vector<Vec3> new_seeds = points_around(Vec3::Zero(), 1.0, dimension, count, 11);
        const std::vector<std::uint8_t> found = bricks_seeds_may_lower(canvas, new_seeds, distance);
        ASSERT_EQ(found.size(), canvas.brick_count());
        std::size_t lowered = 0;
        for (std::size_t slot = 0; slot < canvas.slot_count(); ++slot) {
          if (!canvas.active[slot]) continue;
          double least = std::numeric_limits<double>::infinity();
          for (const Vec3& s : new_seeds) least = std::min(least, u0(canvas.world_of(slot), s));
          if (!(least < distance[slot])) continue;
          ++lowered;
          const std::size_t brick = slot / canvas.brick_volume();
          ASSERT_TRUE(found[brick])
              << "slot " << slot << " is lowered but brick " << brick << " was not found";
        }
        const auto bricks = static_cast<std::size_t>(std::count(found.begin(), found.end(), 1));
        std::printf("[ measured ] %zu voxels lowered, %zu of %zu bricks found\n", lowered, bricks,
                    canvas.brick_count());
        EXPECT_GT(lowered, 0u);
        if (count == 1) {
          EXPECT_LT(bricks * 10, canvas.brick_count());
        }
      }
    }
}

TEST(NearestSeeds, TiesAreAllListed) {
  // Two seeds mirrored about the plane x = 0: voxels at x = 0 have two nearest seeds.
  const Canvas canvas = make_uniform_box_canvas(3, kLo, kHi, 33, Mat3::Identity());
  std::size_t tied = 0;
  expect_lists_hold_nearest_seeds(canvas, {Vec3(-0.5, 0.1, 0.2), Vec3(0.5, 0.1, 0.2)}, &tied);
  EXPECT_EQ(tied, 33u * 33u);  // the voxel plane x = 0
}

TEST(NearestSeeds, TheExactStartNeedsAUniformDiagonalMetricAndReachesEveryBrickOfAConvexDomain) {
  for (const int dimension : {2, 3}) {
    const Canvas box = make_uniform_box_canvas(dimension, kLo, kHi, 16, Mat3::Identity());
    EXPECT_EQ(exact_start_reach(box), ExactStartReach::every_brick);
    EXPECT_EQ(exact_start_reach(make_uniform_box_canvas(dimension, kLo, kHi, 16,
                                                        Vec3(1.0, 100.0, 4.0).asDiagonal())),
              ExactStartReach::every_brick);
    EXPECT_EQ(exact_start_reach(make_uniform_box_canvas(
                  dimension, kLo, kHi, 16, uniform_anisotropic_metric(Vec3(1, 1, 0), 3))),
              ExactStartReach::none);
    const Canvas varying = make_box_canvas(dimension, kLo, kHi, 16, [](const Vec3& p) {
      return Mat3(Vec3(1.0 + p.x() * p.x(), 1.0, 1.0).asDiagonal());
    });
    EXPECT_EQ(exact_start_reach(varying), ExactStartReach::none);
    Canvas holed = box;
    holed.active[holed.slot_of(8, 8, dimension == 3 ? 8 : 0)] = 0;
    --holed.active_voxel_count;
    EXPECT_FALSE(fills_index_box(holed));
    EXPECT_EQ(exact_start_reach(holed), ExactStartReach::quarters_that_see_their_seeds);
    // The builder's word that the domain is convex is trusted (the voxels still make one piece).
    holed.convex_domain = true;
    EXPECT_EQ(exact_start_reach(holed), ExactStartReach::every_brick);
    EXPECT_EQ(exact_start_reach(two_bands_claimed_convex()),
              ExactStartReach::quarters_that_see_their_seeds);
  }
}

// Where a quarter's bit is set, the straight segment from each of its voxels to the seed crosses
// active voxels only (sampled every 1/4 voxel), and the quarter has an active voxel.
struct SeenBits {
  std::size_t set = 0;          // (entry, quarter) bits set
  std::size_t possible = 0;     // of them in quarters with active voxels
  std::size_t set_partial = 0;  // bits set in quarters with inactive voxels too
};
SeenBits expect_seen_quarters_see(const Canvas& canvas, const std::vector<Vec3>& seeds,
                                  const BrickSeedLists& lists) {
  const int half = Canvas::kBrickEdge / 2, quarters = canvas.dimension == 3 ? 8 : 4;
  SeenBits bits;
  for (std::size_t brick = 0; brick < canvas.brick_count(); ++brick)
    for (std::uint32_t c = lists.begin[brick]; c < lists.begin[brick + 1]; ++c)
      for (int q = 0; q < quarters; ++q) {
        const VoxelIndex& o = canvas.brick_origins[brick];
        const VoxelIndex offset = quarter_origin(q);
        const VoxelIndex corner{o.i + offset.i, o.j + offset.j, o.k + offset.k};
        bool any_active = false, all_active = true, all_seen = true;
        for (int k = 0; k < (quarters == 8 ? half : 1); ++k)
          for (int j = 0; j < half; ++j)
            for (int i = 0; i < half; ++i) {
              const std::int64_t slot = canvas.slot_of(corner.i + i, corner.j + j, corner.k + k);
              any_active = any_active || slot >= 0;
              all_active = all_active && slot >= 0;
              const Vec3 from =
                  slot >= 0 ? canvas.world_of(static_cast<std::size_t>(slot)) : Vec3(Vec3::Zero());
              const Vec3 to = seeds[lists.seeds[c]];
              const double steps = std::max(1.0, 4.0 * (to - from).norm() / canvas.voxel_size);
              for (int n = 0; slot >= 0 && all_seen && n <= steps; ++n)
                all_seen =
                    canvas.slot_of(canvas.voxel_containing(from + (to - from) * (n / steps))) >= 0;
            }
        bits.possible += any_active ? 1 : 0;
        if (!(lists.seen[c] >> q & 1)) continue;
        ++bits.set;
        bits.set_partial += all_active ? 0 : 1;
        EXPECT_TRUE(all_seen && any_active)
            << "brick " << brick << ", quarter " << q << ", seed " << lists.seeds[c];
      }
  return bits;
}

// mark_where_seeds_are_seen against segments sampled voxel by voxel: a set bit is always right,
// every bit of a box stays set, and behind a wall bits are cleared but not all of them (with seeds
// in quarters that the wall cuts, which no quarter sees).
TEST(NearestSeeds, QuartersSeeTheirSeedsThroughActiveVoxelsOnly) {
  for (const int dimension : {2, 3}) {
    SCOPED_TRACE(std::to_string(dimension) + "D");
    const std::vector<Vec3> seeds = points_around(Vec3::Zero(), 1.0, dimension, 12, 11);
    const int resolution = dimension == 3 ? 32 : 64;
    const Canvas box = make_uniform_box_canvas(dimension, kLo, kHi, resolution, Mat3::Identity());
    BrickSeedLists lists = nearest_seed_candidates(box, seeds);
    mark_where_seeds_are_seen(box, seeds, lists);
    const SeenBits box_bits = expect_seen_quarters_see(box, seeds, lists);
    EXPECT_EQ(box_bits.set, box_bits.possible);

    const Canvas walled = box_with_a_wall(dimension, resolution);
    // Two seeds next to the wall's faces (in 2D both in quarters that the wall cuts; in 3D the
    // left one, the right face lying on a quarter boundary).
    std::vector<Vec3> outside_the_wall{Vec3(-0.22, 0.3, dimension == 3 ? 0.1 : 0.0),
                                       Vec3(0.05, -0.1, dimension == 3 ? -0.4 : 0.0)};
    for (const Vec3& seed : seeds)
      if (walled.slot_of(walled.voxel_containing(seed)) >= 0) outside_the_wall.push_back(seed);
    lists = nearest_seed_candidates(walled, outside_the_wall);
    mark_where_seeds_are_seen(walled, outside_the_wall, lists);
    const SeenBits bits = expect_seen_quarters_see(walled, outside_the_wall, lists);
    std::printf(
        "[ measured ] %dD, box with a wall, %zu seeds: %zu of %zu quarter bits set, %zu of them "
        "in quarters the wall cuts\n",
        dimension, outside_the_wall.size(), bits.set, bits.possible, bits.set_partial);
    EXPECT_GT(bits.set, bits.possible / 2);
    EXPECT_LT(bits.set, bits.possible);
    EXPECT_EQ(bits.set_partial, 0u);  // a quarter that sees must be full
  }
}

// Face-connected pieces, across brick faces (at 8) and within bricks; voxels that share only an
// edge or a corner are apart, as the axis stencils that the exact start serves read faces only.
TEST(NearestSeeds, FaceConnectivity) {
  for (const int dimension : {2, 3}) {
    const int z = dimension == 3 ? 5 : 0;
    // slot_of finds active voxels only: slots are looked up in the full canvas.
    const Canvas full = make_uniform_box_canvas(dimension, kLo, kHi, 16, Mat3::Identity());
    EXPECT_TRUE(is_face_connected(full));
    Canvas canvas = full;
    for (const int cut : {8, 5}) {  // a wall across x: at a brick face, then inside a brick
      Canvas cut_canvas = canvas;
      for (std::size_t slot = 0; slot < cut_canvas.slot_count(); ++slot)
        if (cut_canvas.voxel_of(slot).i == cut) cut_canvas.active[slot] = 0;
      cut_canvas.finalize();
      EXPECT_FALSE(is_face_connected(cut_canvas)) << "wall at " << cut;
      cut_canvas.active[full.slot_of(cut, 3, z)] = 1;  // a door in the wall
      cut_canvas.finalize();
      EXPECT_TRUE(is_face_connected(cut_canvas)) << "door at " << cut;
    }
    std::fill(canvas.active.begin(), canvas.active.end(), 0);
    canvas.active[full.slot_of(7, 7, z)] = canvas.active[full.slot_of(8, 8, z)] = 1;
    canvas.finalize();
    EXPECT_FALSE(is_face_connected(canvas)) << "an edge is no face";
    if (dimension == 3) {
      std::fill(canvas.active.begin(), canvas.active.end(), 0);
      canvas.active[full.slot_of(7, 7, 5)] = canvas.active[full.slot_of(8, 8, 6)] = 1;
      canvas.finalize();
      EXPECT_FALSE(is_face_connected(canvas)) << "a corner is no face";
    }
  }
}

// Two bands of a box claimed convex, with seeds in one only: the reference, started at u0, would
// raise the other band's voxels a step past each other without end (its pop limit); no quarter of
// that band sees a seed, so it starts from +inf and stays unreached (the OpenCL engine:
// OpenCLExactStart.DisconnectedPiecesStartFromInfinity).
TEST(NearestSeeds, TheReferenceStartsDisconnectedPiecesFromInfinity) {
  const Canvas canvas = two_bands_claimed_convex();
  VoronoiField field;
  const PropagationStats stats =
      make_reference_propagator(true)->solve(canvas, left_band_seeds(), field);
  EXPECT_TRUE(stats.exact_start);  // in the quarters that see the seeds
  expect_only_left_labelled(count_band_labels(canvas, field.label));
}

// The reference reads a voxel's own quarter bit (OpenCLExactStart.AVoxelReadsItsOwnQuartersBit for
// the kernel): a wall one voxel thick cuts a quarter whose lower neighbour sees the seeds.
TEST(NearestSeeds, TheReferenceReadsAVoxelsOwnQuartersBit) {
  for (const int dimension : {2, 3})
    for (int axis = 0; axis < dimension; ++axis) {
      SCOPED_TRACE(std::to_string(dimension) + "D, axis " + std::to_string(axis));
      const Canvas canvas = split_inside_a_quarter(dimension, axis);
      VoronoiField field;
      EXPECT_TRUE(make_reference_propagator(true)
                      ->solve(canvas, lower_piece_seeds(dimension, axis), field)
                      .exact_start);
      expect_only_left_labelled(count_piece_labels(canvas, axis, 20, field.label));
    }
}

}  // namespace
}  // namespace rvor::test
