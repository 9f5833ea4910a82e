// The seed blocks' claims (rvor/seed_blocks.h) against brute force: at every voxel of every seed's
// block, the seed of least u0 over all seeds (ties: the smaller index), listed exactly where it
// does not own the voxel. Dense seeds, so that blocks overlap, bounds prune most pairs, and the
// blocks are split over threads.
#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include "rvor/metric.h"
#include "rvor/seed_blocks.h"
#include "rvor/seeds.h"
#include "solver_fixtures.h"

namespace rvor::test {
namespace {

using VoxelKey = std::tuple<int, int, int>;

struct BruteForceSeed {
  Vec3 centre;
  VoxelIndex voxel;
  Mat3 G;
};

std::vector<BruteForceSeed> brute_force_seeds(const Canvas& canvas,
                                              const std::vector<Vec3>& seeds) {
  std::vector<BruteForceSeed> result;
  for (const Vec3& p : seeds) {
    BruteForceSeed s{canvas.index_coordinates(p), canvas.voxel_containing(p), Mat3::Identity()};
    if (canvas.dimension == 2) s.centre.z() = 0, s.voxel.k = 0;
    s.G = canvas.metric_at(static_cast<std::size_t>(canvas.slot_of(s.voxel)));
    result.push_back(s);
  }
  return result;
}

bool in_block(const VoxelIndex& centre, const VoxelIndex& x) {
  return std::abs(x.i - centre.i) <= kSeedBlockRadius &&
         std::abs(x.j - centre.j) <= kSeedBlockRadius &&
         std::abs(x.k - centre.k) <= kSeedBlockRadius;
}

std::map<VoxelKey, int> brute_force_claims(const Canvas& canvas, const std::vector<Vec3>& points) {
  const std::vector<BruteForceSeed> seeds = brute_force_seeds(canvas, points);
  std::map<VoxelKey, int> claims;
  for (const BruteForceSeed& owner : seeds)
    for_each_seed_block_voxel(owner.voxel, canvas.dimension, [&](const VoxelIndex& x) {
      if (canvas.slot_of(x) < 0) return;
      std::pair<double, int> best{INFINITY, -1};
      for (int t = 0; t < static_cast<int>(seeds.size()); ++t)
        best =
            std::min(best, {metric_length(seeds[t].G, Vec3(x.i, x.j, x.k) - seeds[t].centre), t});
      if (!in_block(seeds[best.second].voxel, x)) claims[{x.i, x.j, x.k}] = best.second;
    });
  return claims;
}

// A varying anisotropic metric: anisotropy 3 along a direction that turns across the box.
Mat3 turning_metric(const Vec3& p, int dimension) {
  const double angle = 1.5 * p.x() + p.y();
  const Vec3 axis(std::cos(angle), std::sin(angle), dimension == 3 ? 0.5 * p.z() : 0.0);
  return uniform_anisotropic_metric(axis, 3.0);
}

std::map<VoxelKey, int> listed_claims(const Canvas& canvas, const std::vector<Vec3>& seeds) {
  std::map<VoxelKey, int> claims;
  for (const SeedClaim& c : foreign_seed_claims(canvas, seeds))
    EXPECT_TRUE(claims.emplace(VoxelKey{c.voxel.i, c.voxel.j, c.voxel.k}, c.label).second)
        << "voxel listed twice";
  return claims;
}

void expect_brute_force_claims(const Canvas& canvas, std::size_t seed_count) {
  const std::vector<Vec3> seeds = random_seeds(canvas, seed_count, 7);
  const std::map<VoxelKey, int> expected = brute_force_claims(canvas, seeds);
  EXPECT_GT(expected.size(), seed_count / 20) << "too few claims to test the bounds";
  EXPECT_EQ(listed_claims(canvas, seeds), expected);
}

// An insertion of seeds[first_new..] lists every claim that a new seed changes (on a new seed's
// block, or by a new seed) and nothing that a solve with all the seeds would not list.
// `all` holds brute_force_claims(canvas, seeds).
// The distances of a field solved for seeds[0..first_new) where the claims may read them, on those
// seeds' blocks (h times the least u0, in float as a field holds it); 0 elsewhere, which no claim
// decision may read.
std::vector<float> solved_block_distances(const Canvas& canvas,
                                          const std::vector<BruteForceSeed>& seeds,
                                          std::size_t first_new) {
  std::vector<float> distance(canvas.slot_count(), 0.0f);
  for (std::size_t owner = 0; owner < first_new; ++owner)
    for_each_seed_block_voxel(seeds[owner].voxel, canvas.dimension, [&](const VoxelIndex& x) {
      const std::int64_t slot = canvas.slot_of(x);
      if (slot < 0) return;
      double least = INFINITY;
      for (std::size_t t = 0; t < first_new; ++t)
        least = std::min(least, metric_length(seeds[t].G, Vec3(x.i, x.j, x.k) - seeds[t].centre));
      distance[static_cast<std::size_t>(slot)] = static_cast<float>(canvas.voxel_size * least);
    });
  return distance;
}

void expect_insertion_claims(const Canvas& canvas, const std::vector<Vec3>& seeds,
                             const std::map<VoxelKey, int>& all, std::size_t first_new) {
  const std::vector<BruteForceSeed> index = brute_force_seeds(canvas, seeds);
  std::map<VoxelKey, int> required;
  for (const auto& [key, label] : all) {
    const VoxelIndex x{std::get<0>(key), std::get<1>(key), std::get<2>(key)};
    bool on_new_block = false;
    for (std::size_t n = first_new; n < seeds.size(); ++n)
      on_new_block = on_new_block || in_block(index[n].voxel, x);
    if (on_new_block || static_cast<std::size_t>(label) >= first_new) required[key] = label;
  }
  // Without the solved field, and with it deciding where it can.
  const std::vector<float> solved = solved_block_distances(canvas, index, first_new);
  for (const std::vector<float>* solved_distance :
       {static_cast<const std::vector<float>*>(nullptr), &solved}) {
    SCOPED_TRACE(solved_distance ? "with the solved field" : "without a field");
    SeedClaimCache cache;
    std::map<VoxelKey, int> listed;
    for (const SeedClaim& c : foreign_seed_claims(canvas, seeds, first_new, cache, solved_distance))
      listed[{c.voxel.i, c.voxel.j, c.voxel.k}] = c.label;
    for (const auto& [key, label] : required) {
      ASSERT_EQ(listed.count(key), 1u) << "a claim the insertion changes is missing";
      EXPECT_EQ(listed.at(key), label);
    }
    for (const auto& [key, label] : listed) {
      ASSERT_EQ(all.count(key), 1u) << "a claim that a solve would not list";
      EXPECT_EQ(all.at(key), label);
    }
  }
}

// A metric whose scale varies 40-fold across the box (the anisotropy of turning_metric on top):
// the blocks' reaches span several levels of the claims' seed grids, and a block of the fine part
// is reachable by coarse seeds from far away, as with radial_shock_3d.
Mat3 scale_varying_metric(const Vec3& p, int dimension) {
  const double scale = std::pow(40.0, 0.5 * (p.x() + 1));  // 1 at x = -1, 40 at x = 1
  return scale * scale * turning_metric(p, dimension);
}

TEST(SeedClaims, DenseSeedsMatchBruteForce3D) {
  const Canvas canvas = make_box_canvas(3, Vec3(-1, -1, -1), Vec3(1, 1, 1), 24,
                                        [](const Vec3& p) { return turning_metric(p, 3); });
  expect_brute_force_claims(canvas, 700);  // ~20 voxels per seed: blocks of 125 overlap
}

TEST(SeedClaims, DenseSeedsMatchBruteForce2D) {
  const Canvas canvas = make_box_canvas(2, Vec3(-1, -1, 0), Vec3(1, 1, 0), 64,
                                        [](const Vec3& p) { return turning_metric(p, 2); });
  expect_brute_force_claims(canvas, 600);
}

TEST(SeedClaims, ScaleVaryingSeedsMatchBruteForce3D) {
  const Canvas canvas = make_box_canvas(3, Vec3(-1, -1, -1), Vec3(1, 1, 1), 24,
                                        [](const Vec3& p) { return scale_varying_metric(p, 3); });
  expect_brute_force_claims(canvas, 700);
}

TEST(SeedClaims, ScaleVaryingSeedsMatchBruteForce2D) {
  const Canvas canvas = make_box_canvas(2, Vec3(-1, -1, 0), Vec3(1, 1, 0), 64,
                                        [](const Vec3& p) { return scale_varying_metric(p, 2); });
  expect_brute_force_claims(canvas, 600);
}

// Insertions of 1, 10 and 200 seeds at once, in both fields, 2D and 3D.
TEST(SeedClaims, InsertionListsTheClaimsThatNewSeedsChange) {
  for (const int dimension : {2, 3})
    for (const bool scale_varying : {false, true}) {
      const auto metric = [&](const Vec3& p) {
        return scale_varying ? scale_varying_metric(p, dimension) : turning_metric(p, dimension);
      };
      const Canvas canvas = dimension == 3
                                ? make_box_canvas(3, Vec3(-1, -1, -1), Vec3(1, 1, 1), 24, metric)
                                : make_box_canvas(2, Vec3(-1, -1, 0), Vec3(1, 1, 0), 64, metric);
      const std::vector<Vec3> seeds = random_seeds(canvas, 600, 11);
      const std::map<VoxelKey, int> all = brute_force_claims(canvas, seeds);
      for (const std::size_t first_new : {599u, 590u, 400u}) {
        SCOPED_TRACE(std::to_string(dimension) + "D, " +
                     (scale_varying ? "scale varying" : "turning") + ", first new " +
                     std::to_string(first_new));
        expect_insertion_claims(canvas, seeds, all, first_new);
      }
    }
}

// Inactive voxels (a wall through the box): blocks that reach into it, seeds on both sides.
TEST(SeedClaims, SeedsBesideAWallMatchBruteForce) {
  expect_brute_force_claims(box_with_a_wall(3, 24), 500);
  expect_brute_force_claims(box_with_a_wall(2, 64), 500);
}

TEST(SeedClaims, UniformIsotropicSeedsMatchBruteForce) {
  // Isotropic: the lower bounds are exact, the tightest case for their rounding margin.
  const Canvas canvas =
      make_uniform_box_canvas(3, Vec3(-1, -1, -1), Vec3(1, 1, 1), 20, Mat3::Identity());
  expect_brute_force_claims(canvas, 500);
}

// An exact tie (u0 = 3 from both seeds, in binary-exact coordinates): voxel (10, 10, 10) lies in
// the block of the seed at (12, 12, 11), not in that of the seed at (13, 10, 10). The smaller
// index takes it: a claim when that is the second seed, none when it is the owner. The bounds
// must not skip the tied seed.
TEST(SeedClaims, AnExactTieGoesToTheSmallerIndex) {
  const Canvas canvas = make_uniform_box_canvas(3, Vec3(-1, -1, -1), Vec3(1, 1, 1), 32,
                                                Mat3::Identity());  // h = 1/16
  const auto at = [&](int i, int j, int k) { return canvas.world_of(VoxelIndex{i, j, k}); };
  const Vec3 owner = at(12, 12, 11), other = at(13, 10, 10);
  const VoxelKey tied{10, 10, 10};
  const std::vector<Vec3> other_first{other, owner}, owner_first{owner, other};
  const std::map<VoxelKey, int> claimed = listed_claims(canvas, other_first);
  ASSERT_EQ(claimed.count(tied), 1u);
  EXPECT_EQ(claimed.at(tied), 0);
  EXPECT_EQ(claimed, brute_force_claims(canvas, other_first));
  EXPECT_EQ(listed_claims(canvas, owner_first).count(tied), 0u);
  EXPECT_EQ(listed_claims(canvas, owner_first), brute_force_claims(canvas, owner_first));
}

// Copies of a seed at the very same position (they tie it everywhere and lose every tie) claim
// nothing and settle no block of their own: the claims are those of a brute force over all
// seeds, copies included. (N copies read each other N^2 times per block voxel before.)
TEST(SeedClaims, CopiesOfASeedMatchBruteForce) {
  const Canvas canvas = make_box_canvas(3, Vec3(-1, -1, -1), Vec3(1, 1, 1), 24,
                                        [](const Vec3& p) { return turning_metric(p, 3); });
  std::vector<Vec3> seeds = random_seeds(canvas, 150, 9);
  for (std::size_t n = 0; n < 150; n += 3) seeds.insert(seeds.begin() + n / 2, seeds[n]);
  seeds.insert(seeds.begin(), seeds.back());  // a copy before its original
  EXPECT_EQ(listed_claims(canvas, seeds), brute_force_claims(canvas, seeds));
}

// Claims as a comparable list.
std::vector<std::tuple<int, int, int, int>> claim_tuples(const std::vector<SeedClaim>& claims) {
  std::vector<std::tuple<int, int, int, int>> tuples;
  for (const SeedClaim& c : claims) tuples.emplace_back(c.voxel.i, c.voxel.j, c.voxel.k, c.label);
  return tuples;
}

// A SeedClaimCache carried through a solve, insertions one by one (past a rebuild of its grids:
// more than 256 seeds added), a changed earlier seed and a shorter list gives what calls without
// one give.
TEST(SeedClaims, ACacheListsWhatFreshCallsList) {
  for (const int dimension : {2, 3}) {
    SCOPED_TRACE(std::to_string(dimension) + "D");
    const auto metric = [&](const Vec3& p) { return scale_varying_metric(p, dimension); };
    const Canvas canvas = dimension == 3
                              ? make_box_canvas(3, Vec3(-1, -1, -1), Vec3(1, 1, 1), 24, metric)
                              : make_box_canvas(2, Vec3(-1, -1, 0), Vec3(1, 1, 0), 64, metric);
    std::vector<Vec3> seeds = random_seeds(canvas, 620, 5);
    SeedClaimCache cache;
    const auto expect_same = [&](const std::vector<Vec3>& listed, std::size_t first_new) {
      EXPECT_EQ(claim_tuples(foreign_seed_claims(canvas, listed, first_new, cache)),
                claim_tuples(foreign_seed_claims(canvas, listed, first_new)))
          << listed.size() << " seeds, first new " << first_new;
    };
    std::vector<Vec3> growing(seeds.begin(), seeds.begin() + 300);
    expect_same(growing, 0);
    for (std::size_t n = 300; n < seeds.size(); ++n) {
      growing.push_back(seeds[n]);
      expect_same(growing, n);
    }
    std::swap(growing[10], growing[600]);  // an earlier seed changes
    expect_same(growing, 615);
    growing.resize(500);  // fewer seeds than the grids hold
    expect_same(growing, 499);
  }
}

}  // namespace
}  // namespace rvor::test
