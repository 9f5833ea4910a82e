#include "rvor/seed_blocks.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <tuple>

#include <Eigen/LU>

#include "rvor/metric.h"
#include "slot_ranges.h"

namespace rvor {

namespace {

// A seed as the claims see it, in index units (voxel centres at integers): u0 / h.
struct IndexSeed {
  Vec3 centre;               // continuous index coordinates (z = 0 in 2D)
  VoxelIndex voxel;          // the containing voxel, the centre of its block
  Mat3 G;                    // the metric of that voxel
  double least_scale = 0.0;  // sqrt of G's least eigenvalue: u0(x) >= least_scale |x - centre|
  double block_reach = 0.0;  // at least the largest u0 over its own block
  Vec3 axis_reach = Vec3::Zero();  // sqrt((G^-1)_aa): {q : |q|_G <= r} spans r times it per axis

  double u0(const VoxelIndex& x) const { return metric_length(G, Vec3(x.i, x.j, x.k) - centre); }
  bool owns(const VoxelIndex& x) const {
    return std::abs(x.i - voxel.i) <= kSeedBlockRadius &&
           std::abs(x.j - voxel.j) <= kSeedBlockRadius &&
           std::abs(x.k - voxel.k) <= kSeedBlockRadius;
  }
};

std::vector<IndexSeed> index_seeds(const Canvas& canvas, const std::vector<Vec3>& seeds) {
  std::vector<IndexSeed> result;
  result.reserve(seeds.size());
  for (const Vec3& p : seeds) {
    IndexSeed seed;
    seed.centre = canvas.index_coordinates(p);
    seed.voxel = canvas.voxel_containing(p);
    if (canvas.dimension == 2) seed.centre.z() = 0, seed.voxel.k = 0;
    seed.G = canvas.metric_at(static_cast<std::size_t>(canvas.slot_of(seed.voxel)));
    const int n = canvas.dimension == 3 ? 3 : 2;
    const Eigen::VectorXd eigenvalues = metric_eigenvalues(seed.G, canvas.dimension);
    // The least eigenvalue carries an error of about eps times the largest: less that, so that
    // least_scale stays a lower bound at any anisotropy the canvas accepts.
    const double rounding = 64 * std::numeric_limits<double>::epsilon() * eigenvalues.maxCoeff();
    seed.least_scale = std::sqrt(std::max(0.0, eigenvalues.minCoeff() - rounding));
    // u0 <= sqrt(largest eigenvalue) |q|, |q| at most the block's farthest corner from the seed.
    Vec3 corner = Vec3::Zero();
    const int v[3] = {seed.voxel.i, seed.voxel.j, seed.voxel.k};
    for (int a = 0; a < n; ++a) corner[a] = std::abs(v[a] - seed.centre[a]) + kSeedBlockRadius;
    seed.block_reach = std::sqrt(std::max(0.0, eigenvalues.maxCoeff())) * corner.norm();
    const Mat3 D = seed.G.inverse();
    for (int a = 0; a < n; ++a) seed.axis_reach[a] = std::sqrt(std::max(0.0, D(a, a)));
    result.push_back(seed);
  }
  return result;
}

// Seeds listed per cell of a coarse grid over the canvas, each in every cell that its reach box
// touches: the box around it that holds every x with u0(x) <= reach.
class SeedGrid {
 public:
  SeedGrid(const Canvas& canvas, const std::vector<IndexSeed>& seeds, double reach)
      : dimension_(canvas.dimension) {
    for (int a = 0; a < 3; ++a) dims_[a] = canvas.dims[a];
    // Coarser cells when the boxes are long (strong anisotropy), so that the lists stay small.
    for (cell_ = Canvas::kBrickEdge;
         cell_ < 2 * max_dim() && registrations(seeds, reach) > 64 * seeds.size() + (1u << 22);
         cell_ *= 2) {
    }
    for (int a = 0; a < 3; ++a) cells_[a] = (dims_[a] + cell_ - 1) / cell_;
    lists_.resize(static_cast<std::size_t>(cells_[0]) * cells_[1] * cells_[2]);
    for (std::size_t t = 0; t < seeds.size(); ++t) {
      const auto [lo, hi] = cell_box(seeds[t], reach);
      for (int k = lo[2]; k <= hi[2]; ++k)
        for (int j = lo[1]; j <= hi[1]; ++j)
          for (int i = lo[0]; i <= hi[0]; ++i)
            lists_[cell_index(i, j, k)].push_back(static_cast<std::int32_t>(t));
    }
  }

  // The seeds listed in the cells that the voxel box [centre - r, centre + r] touches, sorted,
  // distinct.
  std::vector<std::int32_t> seeds_near(const VoxelIndex& centre, int r) const {
    const int c[3] = {centre.i, centre.j, centre.k};
    std::array<int, 3> lo{}, hi{};
    for (int a = 0; a < 3; ++a) {
      const int reach = a < dimension_ ? r : 0;
      lo[a] = std::clamp(c[a] - reach, 0, dims_[a] - 1) / cell_;
      hi[a] = std::clamp(c[a] + reach, 0, dims_[a] - 1) / cell_;
    }
    std::vector<std::int32_t> seeds;
    for (int k = lo[2]; k <= hi[2]; ++k)
      for (int j = lo[1]; j <= hi[1]; ++j)
        for (int i = lo[0]; i <= hi[0]; ++i) {
          const std::vector<std::int32_t>& list = lists_[cell_index(i, j, k)];
          seeds.insert(seeds.end(), list.begin(), list.end());
        }
    std::sort(seeds.begin(), seeds.end());
    seeds.erase(std::unique(seeds.begin(), seeds.end()), seeds.end());
    return seeds;
  }

  // The seeds ordered by the cell that holds their voxel: neighbouring blocks one after the other
  // read the same seeds, which then stay in the cache.
  std::vector<std::int32_t> cell_order(const std::vector<IndexSeed>& seeds) const {
    std::vector<std::pair<std::size_t, std::int32_t>> keyed(seeds.size());
    for (std::size_t t = 0; t < seeds.size(); ++t) {
      const VoxelIndex& v = seeds[t].voxel;
      keyed[t] = {cell_index(v.i / cell_, v.j / cell_, v.k / cell_), static_cast<std::int32_t>(t)};
    }
    std::sort(keyed.begin(), keyed.end());
    std::vector<std::int32_t> order(seeds.size());
    for (std::size_t n = 0; n < order.size(); ++n) order[n] = keyed[n].second;
    return order;
  }

 private:
  using CellBox = std::pair<std::array<int, 3>, std::array<int, 3>>;

  int max_dim() const { return std::max({dims_[0], dims_[1], dims_[2]}); }
  std::size_t cell_index(int i, int j, int k) const {
    return static_cast<std::size_t>(i) +
           static_cast<std::size_t>(cells_[0]) * (j + static_cast<std::size_t>(cells_[1]) * k);
  }

  CellBox cell_box(const IndexSeed& seed, double reach) const {
    CellBox box;
    for (int a = 0; a < 3; ++a) {
      const double half = reach * seed.axis_reach[a];  // 0 along z in 2D
      const double lo = std::clamp(seed.centre[a] - half, 0.0, dims_[a] - 1.0);
      const double hi = std::clamp(seed.centre[a] + half, 0.0, dims_[a] - 1.0);
      box.first[a] = static_cast<int>(std::floor(lo)) / cell_;
      box.second[a] = static_cast<int>(std::ceil(hi)) / cell_;
    }
    return box;
  }

  // How many list entries cells of the current size would hold.
  std::size_t registrations(const std::vector<IndexSeed>& seeds, double reach) const {
    std::size_t total = 0;
    for (const IndexSeed& seed : seeds) {
      const auto [lo, hi] = cell_box(seed, reach);
      total +=
          static_cast<std::size_t>(hi[0] - lo[0] + 1) * (hi[1] - lo[1] + 1) * (hi[2] - lo[2] + 1);
    }
    return total;
  }

  int dimension_;
  std::array<int, 3> dims_{};
  std::array<int, 3> cells_{};
  int cell_ = Canvas::kBrickEdge;
  std::vector<std::vector<std::int32_t>> lists_;
};

double largest_block_reach(const std::vector<IndexSeed>& seeds) {
  double largest = 0;
  for (const IndexSeed& seed : seeds) largest = std::max(largest, seed.block_reach);
  return largest;
}

// Rounding allowance of the squared lower bounds below (least_scale itself is lowered by its
// eigenvalue's error): they skip a seed only when it is farther by more than rounding could
// explain, since an exact tie goes to the smaller seed index.
constexpr double kBoundMargin = 1.0 + 1e-8;

// Whether seed t may claim a voxel of `owner`'s block: not certainly farther than the owner
// everywhere on it (u0_t >= least_scale_t |x - t| over the block's box, against the owner's
// largest value there). Squared, as the claims test it for every pair of nearby blocks.
bool may_claim(const IndexSeed& t, const IndexSeed& owner, int dimension) {
  Vec3 gap = Vec3::Zero();  // from t's centre to the block's box
  const int box[3] = {owner.voxel.i, owner.voxel.j, owner.voxel.k};
  for (int a = 0; a < dimension; ++a)
    gap[a] = std::max(
        {0.0, box[a] - kSeedBlockRadius - t.centre[a], t.centre[a] - box[a] - kSeedBlockRadius});
  return t.least_scale * t.least_scale * gap.squaredNorm() <
         owner.block_reach * owner.block_reach * kBoundMargin;
}

// The seeds among `listed` that may claim in `owner`'s block, the owner included.
std::vector<std::int32_t> possible_claimants(const std::vector<IndexSeed>& seeds, std::size_t owner,
                                             const std::vector<std::int32_t>& listed,
                                             int dimension) {
  std::vector<std::int32_t> possible;
  for (const std::int32_t t : listed)
    if (static_cast<std::size_t>(t) == owner || may_claim(seeds[t], seeds[owner], dimension))
      possible.push_back(t);
  return possible;
}

// Whether seed t is certainly farther from x than `best` (its u0 is at least least_scale_t
// |x - t|); most of a block's possible claimants are, at most of its voxels.
bool certainly_farther(const IndexSeed& t, const Vec3& x, double best) {
  return t.least_scale * t.least_scale * (x - t.centre).squaredNorm() > best * best * kBoundMargin;
}

// The claims in `owner`'s block among the seeds `near` (the owner's possible claimants).
void claim_block(const Canvas& canvas, const std::vector<IndexSeed>& seeds, std::size_t owner,
                 const std::vector<std::int32_t>& near, std::vector<SeedClaim>& claims) {
  for_each_seed_block_voxel(seeds[owner].voxel, canvas.dimension, [&](const VoxelIndex& x) {
    if (canvas.slot_of(x) < 0) return;
    const Vec3 position(x.i, x.j, x.k);
    std::pair<double, std::int32_t> best{seeds[owner].u0(x), static_cast<std::int32_t>(owner)};
    for (const std::int32_t t : near)
      if (t != best.second && !certainly_farther(seeds[t], position, best.first))
        best = std::min(best, {seeds[t].u0(x), t});
    if (!seeds[best.second].owns(x)) claims.push_back({x, best.second});
  });
}

// A solve: every block, its candidates from the grid of reach boxes; the blocks are independent,
// so they are split over threads when there are many (thousands of seeds take seconds alone).
void claim_all_blocks(const Canvas& canvas, const std::vector<IndexSeed>& seeds,
                      std::vector<SeedClaim>& claims) {
  const SeedGrid grid(canvas, seeds, largest_block_reach(seeds));
  const std::vector<std::int32_t> order = grid.cell_order(seeds);
  constexpr std::size_t kSeedsPerThread = 256;
  const unsigned threads = static_cast<unsigned>(
      std::min<std::size_t>(slot_threads(), 1 + seeds.size() / kSeedsPerThread));
  std::vector<std::vector<SeedClaim>> parts(threads);
  for_slot_ranges(order.size(), threads, [&](unsigned part, std::size_t begin, std::size_t end) {
    for (std::size_t n = begin; n < end; ++n) {
      const std::size_t s = static_cast<std::size_t>(order[n]);
      claim_block(canvas, seeds, s,
                  possible_claimants(seeds, s, grid.seeds_near(seeds[s].voxel, kSeedBlockRadius),
                                     canvas.dimension),
                  parts[part]);
    }
  });
  for (const std::vector<SeedClaim>& part : parts)
    claims.insert(claims.end(), part.begin(), part.end());
}

// An insertion: the new seeds' blocks and the old blocks a new seed may claim in, each against
// every seed, so that the cost follows the new seeds, not a grid of all of them.
void claim_new_blocks(const Canvas& canvas, const std::vector<IndexSeed>& seeds,
                      std::size_t first_new, std::vector<SeedClaim>& claims) {
  std::vector<std::int32_t> all(seeds.size());
  for (std::size_t t = 0; t < seeds.size(); ++t) all[t] = static_cast<std::int32_t>(t);
  for (std::size_t s = 0; s < seeds.size(); ++s) {
    bool affected = s >= first_new;
    for (std::size_t n = first_new; n < seeds.size() && !affected; ++n)
      affected = may_claim(seeds[n], seeds[s], canvas.dimension);
    if (affected)
      claim_block(canvas, seeds, s, possible_claimants(seeds, s, all, canvas.dimension), claims);
  }
}

}  // namespace

std::vector<SeedClaim> foreign_seed_claims(const Canvas& canvas, const std::vector<Vec3>& seeds,
                                           std::size_t first_new) {
  const std::vector<IndexSeed> index = index_seeds(canvas, seeds);
  std::vector<SeedClaim> claims;
  if (first_new == 0)
    claim_all_blocks(canvas, index, claims);
  else
    claim_new_blocks(canvas, index, first_new, claims);
  const auto key = [](const SeedClaim& c) { return std::tie(c.voxel.k, c.voxel.j, c.voxel.i); };
  std::sort(claims.begin(), claims.end(),
            [&](const SeedClaim& a, const SeedClaim& b) { return key(a) < key(b); });
  claims.erase(
      std::unique(claims.begin(), claims.end(),
                  [&](const SeedClaim& a, const SeedClaim& b) { return key(a) == key(b); }),
      claims.end());
  return claims;
}

}  // namespace rvor
