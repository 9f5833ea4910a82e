#include "rvor/seed_blocks.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <memory>
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

// Appends the IndexSeed of each of seeds[first..] to `result`.
void index_seeds(const Canvas& canvas, const std::vector<Vec3>& seeds, std::size_t first,
                 std::vector<IndexSeed>& result) {
  result.reserve(seeds.size());
  for (std::size_t s = first; s < seeds.size(); ++s) {
    const Vec3& p = seeds[s];
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
}

// Seeds listed per cell of a coarse grid over the canvas, each in every cell that its reach box
// touches: the box around it that holds every x with u0(x) <= reach.
class SeedGrid {
 public:
  // Seeds marked in `repeats` are not listed (repeated_seeds).
  SeedGrid(const Canvas& canvas, const std::vector<IndexSeed>& seeds, double reach,
           const std::vector<std::uint8_t>& repeats)
      : dimension_(canvas.dimension) {
    for (int a = 0; a < 3; ++a) dims_[a] = canvas.dims[a];
    // Coarser cells when the boxes are long (strong anisotropy), so that the lists stay small.
    for (cell_ = Canvas::kBrickEdge;
         cell_ < 2 * max_dim() && registrations(seeds, reach) > 64 * seeds.size() + (1u << 22);
         cell_ *= 2) {
    }
    for (int a = 0; a < 3; ++a) cells_[a] = (dims_[a] + cell_ - 1) / cell_;
    lists_.resize(static_cast<std::size_t>(cells_[0]) * cells_[1] * cells_[2]);
    first_cells_.resize(seeds.size());
    for (std::size_t t = 0; t < seeds.size(); ++t) {
      if (repeats[t]) continue;
      const auto [lo, hi] = cell_box(seeds[t], reach);
      first_cells_[t] = lo;
      for (int k = lo[2]; k <= hi[2]; ++k)
        for (int j = lo[1]; j <= hi[1]; ++j)
          for (int i = lo[0]; i <= hi[0]; ++i)
            lists_[cell_index(i, j, k)].push_back(static_cast<std::int32_t>(t));
    }
  }

  // The seeds listed in the cells that the voxel box [centre - r, centre + r] touches, each once:
  // a seed is taken from the first of those cells that lists it, the one at the larger corner of
  // its own cell box's and the query box's least corners. (Sorting the cells' lists to drop the
  // copies took half of the claims' time with dense seeds: euclidean 128^3 with 100 000 seeds
  // solved in 3.59 / 6.27 s before, 2.15 / 4.93 s after, alternating on a busy machine; with a seed
  // in every voxel of 32^3, 10.5 s before, 7.5 s after; 2026-12-05.)
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
        for (int i = lo[0]; i <= hi[0]; ++i)
          for (const std::int32_t t : lists_[cell_index(i, j, k)]) {
            const std::array<int, 3>& first = first_cells_[static_cast<std::size_t>(t)];
            if (i == std::max(lo[0], first[0]) && j == std::max(lo[1], first[1]) &&
                k == std::max(lo[2], first[2]))
              seeds.push_back(t);
          }
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
  std::vector<std::array<int, 3>> first_cells_;  // per seed, the least corner of its cell box
};

// Rounding allowance of the squared lower bounds below (least_scale itself is lowered by its
// eigenvalue's error): they skip a seed only when it is farther by more than rounding could
// explain, since an exact tie goes to the smaller seed index.
constexpr double kBoundMargin = 1.0 + 1e-8;

// The square of a lower bound of u0_t over `owner`'s block: u0_t >= least_scale_t |x - t|, and
// |x - t| is at least the gap from t's centre to the block's box.
double squared_bound_over_block(const IndexSeed& t, const IndexSeed& owner, int dimension) {
  Vec3 gap = Vec3::Zero();
  const int box[3] = {owner.voxel.i, owner.voxel.j, owner.voxel.k};
  for (int a = 0; a < dimension; ++a)
    gap[a] = std::max(
        {0.0, box[a] - kSeedBlockRadius - t.centre[a], t.centre[a] - box[a] - kSeedBlockRadius});
  return t.least_scale * t.least_scale * gap.squaredNorm();
}

// The owner's largest value over its block, squared, with the bounds' rounding margin: a seed
// whose bound lies at or beyond it claims nothing there.
double squared_block_limit(const IndexSeed& owner) {
  return owner.block_reach * owner.block_reach * kBoundMargin;
}

// Whether seed t may claim a voxel of `owner`'s block: not certainly farther than the owner
// everywhere on it.
bool may_claim(const IndexSeed& t, const IndexSeed& owner, int dimension) {
  return squared_bound_over_block(t, owner, dimension) < squared_block_limit(owner);
}

// A possible claimant of a block, with its squared_bound_over_block.
struct Claimant {
  double squared_bound;
  std::int32_t seed;
  bool operator<(const Claimant& other) const {
    return std::tie(squared_bound, seed) < std::tie(other.squared_bound, other.seed);
  }
};
using Claimants = std::vector<Claimant>;
using ClaimantIt = Claimants::iterator;

// The seeds among `listed` whose bound over `owner`'s block lies below `limit` (squared), the
// owner included, in no particular order.
Claimants claimants_below(const std::vector<IndexSeed>& seeds, std::size_t owner,
                          const std::vector<std::int32_t>& listed, double limit, int dimension) {
  Claimants below;
  for (const std::int32_t t : listed) {
    const double bound = static_cast<std::size_t>(t) == owner
                             ? 0.0
                             : squared_bound_over_block(seeds[t], seeds[owner], dimension);
    if (bound < limit) below.push_back({bound, t});
  }
  return below;
}

// Whether seed t is certainly farther from x than `best` (its u0 is at least least_scale_t
// |x - t|); most of a block's possible claimants are, at most of its voxels.
bool certainly_farther(const IndexSeed& t, const Vec3& x, double best) {
  return t.least_scale * t.least_scale * (x - t.centre).squaredNorm() > best * best * kBoundMargin;
}

// A block voxel's least (u0, seed) pair so far; seed -1 where nothing is to be decided (outside
// the canvas).
using LeastPair = std::pair<double, std::int32_t>;

// The owner's pair at each voxel of its block, as for_each_seed_block_voxel visits them.
std::vector<LeastPair> owner_pairs(const Canvas& canvas, const std::vector<IndexSeed>& seeds,
                                   std::size_t owner) {
  std::vector<LeastPair> best;
  for_each_seed_block_voxel(seeds[owner].voxel, canvas.dimension, [&](const VoxelIndex& x) {
    best.push_back(canvas.slot_of(x) < 0
                       ? LeastPair{0.0, -1}
                       : LeastPair{seeds[owner].u0(x), static_cast<std::int32_t>(owner)});
  });
  return best;
}

double largest_value(const std::vector<LeastPair>& best) {
  double largest = 0.0;
  for (const LeastPair& b : best)
    if (b.second >= 0) largest = std::max(largest, b.first);
  return largest;
}

// Lists no longer than this are read whole rather than sorted (a uniform metric's blocks list a few
// dozen seeds, and sorting them made a 20000-seed euclidean solve slower).
constexpr std::ptrdiff_t kSortedFrom = 64;

// Lowers each voxel's pair of `owner`'s block to the least over the seeds of [begin, end); a long
// list is sorted by bound first, and a voxel stops at the first bound beyond its value. The least
// pair does not depend on the order the seeds are read in, so reading them in several passes, or
// some twice, changes nothing.
void lower_pairs(const Canvas& canvas, const std::vector<IndexSeed>& seeds, std::size_t owner,
                 ClaimantIt begin, ClaimantIt end, std::vector<LeastPair>& best) {
  const bool sorted = end - begin > kSortedFrom;
  if (sorted) std::sort(begin, end);
  std::size_t n = 0;
  for_each_seed_block_voxel(seeds[owner].voxel, canvas.dimension, [&](const VoxelIndex& x) {
    LeastPair& b = best[n++];
    if (b.second < 0) return;
    const Vec3 position(x.i, x.j, x.k);
    for (ClaimantIt c = begin; c != end; ++c) {
      if (sorted && c->squared_bound > b.first * b.first * kBoundMargin) break;
      if (c->seed != b.second && !certainly_farther(seeds[c->seed], position, b.first))
        b = std::min(b, {seeds[c->seed].u0(x), c->seed});
    }
  });
}

// The voxels of `owner`'s block whose least pair is a seed whose own block does not hold them.
void report_claims(const Canvas& canvas, const std::vector<IndexSeed>& seeds, std::size_t owner,
                   const std::vector<LeastPair>& best, std::vector<SeedClaim>& claims) {
  std::size_t n = 0;
  for_each_seed_block_voxel(seeds[owner].voxel, canvas.dimension, [&](const VoxelIndex& x) {
    const LeastPair& b = best[n++];
    if (b.second >= 0 && !seeds[b.second].owns(x)) claims.push_back({x, b.second});
  });
}

// How many seeds a block's first pass reads at most, those of least bound: a list read whole.
// 16 rather than 64 (session 25): euclidean 128^3 with 100 000 seeds solved in 4.09 / 4.17 s ->
// 3.78 / 3.73 s (alternating builds; the block reads ~60 seeds, most of them only to find they
// are farther), radial_shock_3d with 20 000 unchanged (2.64 / 2.82 s -> 2.62 / 2.82 s).
constexpr std::ptrdiff_t kFirstPassSeeds = 16;

// 1 for each seed at the very position of an earlier one: it ties that seed everywhere and loses
// every tie (the smaller label wins), so it claims nothing and its block is the earlier one's.
// Without it, N copies of one seed read each other N^2 times per block voxel (10 000 copies at
// 128^3: 80 s).
std::vector<std::uint8_t> repeated_seeds(const std::vector<IndexSeed>& seeds) {
  std::vector<std::size_t> order(seeds.size());
  for (std::size_t t = 0; t < order.size(); ++t) order[t] = t;
  const auto position = [&](std::size_t t) {
    const Vec3& c = seeds[t].centre;
    return std::make_tuple(c.x(), c.y(), c.z());
  };
  std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
    return std::make_pair(position(a), a) < std::make_pair(position(b), b);
  });
  std::vector<std::uint8_t> repeats(seeds.size(), 0);
  for (std::size_t n = 1; n < order.size(); ++n)
    repeats[order[n]] = position(order[n]) == position(order[n - 1]);
  return repeats;
}

// Grids of reach boxes for reaches r_max / 2^k (r_max the largest block reach), down to the least
// block reach: a block reads the least level whose reach covers what it asks for. One grid at
// r_max listed nearly every seed near every block of a field whose scale varies (radial_shock_3d:
// block reaches 0.34 to 13.5 index units at 128^3); a uniform metric keeps that one grid (its
// block reaches differ by less than half, with the seeds' places in their voxels).
class SeedGridLevels {
 public:
  SeedGridLevels(const Canvas& canvas, const std::vector<IndexSeed>& seeds) {
    double least = std::numeric_limits<double>::infinity();
    for (const IndexSeed& seed : seeds) {
      if (seed.block_reach > 0) least = std::min(least, seed.block_reach);
      largest_ = std::max(largest_, seed.block_reach);
    }
    std::size_t levels = 1;
    // Level 0 is at least the least reach and at most twice it (a degenerate reach stops at 64).
    while (std::isfinite(least) && levels < 64 && reach_of(0, levels) / 2 >= least) ++levels;
    repeats_ = repeated_seeds(seeds);
    for (std::size_t level = 0; level < levels; ++level)
      grids_.push_back(
          std::make_unique<SeedGrid>(canvas, seeds, reach_of(level, levels), repeats_));
  }

  // The least level whose reach is at least `reach` (the top one beyond it).
  std::size_t level_for(double reach) const {
    std::size_t level = 0;
    while (level + 1 < grids_.size() && reach_of(level, grids_.size()) < reach) ++level;
    return level;
  }
  const SeedGrid& grid(std::size_t level) const { return *grids_[level]; }
  // Whether gridded seed t repeats an earlier one's position (repeated_seeds).
  bool repeats(std::size_t t) const { return repeats_[t] != 0; }
  // The reach of the top level: a listing covers no more.
  double top_reach() const { return reach_of(grids_.size() - 1, grids_.size()); }

 private:
  double reach_of(std::size_t level, std::size_t levels) const {
    return std::ldexp(largest_ * kBoundMargin, -static_cast<int>(levels - 1 - level));
  }

  double largest_ = 0.0;
  std::vector<std::uint8_t> repeats_;
  std::vector<std::unique_ptr<SeedGrid>> grids_;
};

// Where a block's possible claimants come from: grids of reach boxes over the seeds before
// `ungridded` (SeedClaimCache keeps them between calls) and, in an insertion, every_seed: those
// after `ungridded` are listed whole, and all of them for a reach beyond the grids' top level.
struct ClaimantSource {
  const SeedGridLevels* grids = nullptr;
  const std::vector<std::int32_t>* every_seed = nullptr;  // null in a solve: the grids hold all
  std::size_t ungridded = 0;

  std::size_t level_for(double reach) const { return grids->level_for(reach); }
  // Whether the grid of level_for(reach) lists every gridded seed that may claim within `reach`.
  bool covers(double reach) const { return !every_seed || reach <= grids->top_reach(); }
  // Every seed whose u0 may be at most `reach` somewhere on the block around `centre` (more too).
  std::vector<std::int32_t> listed(double reach, const VoxelIndex& centre) const {
    if (!covers(reach)) return *every_seed;
    std::vector<std::int32_t> seeds =
        grids->grid(level_for(reach)).seeds_near(centre, kSeedBlockRadius);
    if (every_seed)
      seeds.insert(seeds.end(), every_seed->begin() + static_cast<std::ptrdiff_t>(ungridded),
                   every_seed->end());
    return seeds;
  }
};

// The least pairs over `owner`'s block, in two passes: the few seeds of least bound among those
// listed at level 0 (the least reach) settle most voxels; then only the seeds that can beat the
// largest value left are read, from the same listing when its level covers that value. With dense
// seeds in a field whose scale varies, a block of the fine part may list thousands of coarse seeds
// at its own block reach, most of them far (radial_shock_3d 128^3, 20000 seeds: 18 s of claims with
// one listing at the largest block reach of all seeds, as before 2026-12-04).
void settle_block(const Canvas& canvas, const std::vector<IndexSeed>& seeds, std::size_t owner,
                  const ClaimantSource& source, std::vector<LeastPair>& best) {
  Claimants near = claimants_below(seeds, owner, source.listed(0.0, seeds[owner].voxel),
                                   squared_block_limit(seeds[owner]), canvas.dimension);
  const ClaimantIt first_end =
      near.begin() + std::min(kFirstPassSeeds, static_cast<std::ptrdiff_t>(near.size()));
  std::nth_element(near.begin(), first_end, near.end());
  lower_pairs(canvas, seeds, owner, near.begin(), first_end, best);
  const double largest = largest_value(best);
  const double limit = largest * largest * kBoundMargin;
  const double reach = largest * kBoundMargin;
  if (source.level_for(reach) == 0 && source.covers(reach)) {
    const ClaimantIt end = std::partition(
        first_end, near.end(), [&](const Claimant& c) { return c.squared_bound < limit; });
    lower_pairs(canvas, seeds, owner, first_end, end, best);
  } else {
    near = claimants_below(seeds, owner, source.listed(reach, seeds[owner].voxel), limit,
                           canvas.dimension);
    lower_pairs(canvas, seeds, owner, near.begin(), near.end(), best);
  }
}

// A solve: every block, its candidates from the grids of reach boxes; the blocks are independent,
// so they are split over threads when there are many (thousands of seeds take seconds alone).
void claim_all_blocks(const Canvas& canvas, const std::vector<IndexSeed>& seeds,
                      const SeedGridLevels& grids, std::vector<SeedClaim>& claims) {
  if (seeds.empty()) return;
  const ClaimantSource source{&grids, nullptr, seeds.size()};
  const std::vector<std::int32_t> order = grids.grid(0).cell_order(seeds);
  constexpr std::size_t kSeedsPerThread = 256;
  const unsigned threads = static_cast<unsigned>(
      std::min<std::size_t>(slot_threads(), 1 + seeds.size() / kSeedsPerThread));
  std::vector<std::vector<SeedClaim>> parts(threads);
  for_slot_ranges(order.size(), threads, [&](unsigned part, std::size_t begin, std::size_t end) {
    for (std::size_t n = begin; n < end; ++n) {
      const std::size_t s = static_cast<std::size_t>(order[n]);
      if (grids.repeats(s)) continue;  // its block is the earlier seed's, and settled there
      std::vector<LeastPair> best = owner_pairs(canvas, seeds, s);
      settle_block(canvas, seeds, s, source, best);
      report_claims(canvas, seeds, s, best, parts[part]);
    }
  });
  for (const std::vector<SeedClaim>& part : parts)
    claims.insert(claims.end(), part.begin(), part.end());
}

// Lowers the voxels a new seed holds in `owner`'s block (best) by every seed that may beat it,
// and drops those an old seed wins (their claims hold in the field already).
void read_old_seeds(const Canvas& canvas, const std::vector<IndexSeed>& seeds, std::size_t owner,
                    std::size_t first_new, const ClaimantSource& source,
                    std::vector<LeastPair>& best) {
  if (std::none_of(best.begin(), best.end(), [](const LeastPair& b) { return b.second >= 0; }))
    return;
  const double largest = largest_value(best);
  Claimants near =
      claimants_below(seeds, owner, source.listed(largest * kBoundMargin, seeds[owner].voxel),
                      largest * largest * kBoundMargin, canvas.dimension);
  lower_pairs(canvas, seeds, owner, near.begin(), near.end(), best);
  for (LeastPair& b : best)
    if (static_cast<std::size_t>(b.second) < first_new) b.second = -1;  // an old seed's, as before
}

// The least u0 over the solved seeds at a block voxel, in index units, read from the solved
// field's distances; NaN where there is none.
struct SolvedLeast {
  const Canvas& canvas;
  const std::vector<float>* distance = nullptr;

  double at(const VoxelIndex& x) const {  // without a field: NaN, which decides nothing
    const std::int64_t slot = distance ? canvas.slot_of(x) : -1;
    if (slot < 0) return std::numeric_limits<double>::quiet_NaN();
    return static_cast<double>((*distance)[static_cast<std::size_t>(slot)]) / canvas.voxel_size;
  }
};

// The field's float values against a new seed's u0: beyond this relative margin the comparison is
// decided; within it the old seeds are read.
constexpr double kSolvedMargin = 1e-4;

// Settles the voxels of `owner`'s block that a new seed holds by the solved field: kept (decided)
// where the new seed is clearly nearer than the least old seed, dropped where clearly farther.
// Returns whether any voxel is left undecided.
bool settle_by_solved_field(const Canvas& canvas, std::size_t owner,
                            const std::vector<IndexSeed>& seeds, const SolvedLeast& solved,
                            std::vector<LeastPair>& best, std::vector<bool>& decided) {
  bool undecided = false;
  std::size_t n = 0;
  for_each_seed_block_voxel(seeds[owner].voxel, canvas.dimension, [&](const VoxelIndex& x) {
    LeastPair& b = best[n++];
    if (b.second < 0) return;
    const double old = solved.at(x);
    if (b.first < old * (1 - kSolvedMargin)) {
      decided[n - 1] = true;
    } else if (b.first > old * (1 + kSolvedMargin)) {
      b.second = -1;
    } else {
      undecided = true;
    }
  });
  return undecided;
}

// The claims of new seeds (seeds[first_new..]) in the block of an old seed: only voxels where a
// new seed is nearer than the owner can change, and only there are the other seeds read, unless
// the solved field decides (an old block of a field whose scale varies may list most seeds).
void claim_for_new_seeds(const Canvas& canvas, const std::vector<IndexSeed>& seeds,
                         std::size_t owner, std::size_t first_new,
                         const std::vector<std::int32_t>& new_seeds, const ClaimantSource& source,
                         const SolvedLeast& solved, std::vector<SeedClaim>& claims) {
  std::vector<LeastPair> best = owner_pairs(canvas, seeds, owner);
  Claimants near =
      claimants_below(seeds, owner, new_seeds, squared_block_limit(seeds[owner]), canvas.dimension);
  lower_pairs(canvas, seeds, owner, near.begin(), near.end(), best);
  for (LeastPair& b : best)
    if (static_cast<std::size_t>(b.second) == owner) b.second = -1;  // no new seed is nearer
  if (std::none_of(best.begin(), best.end(), [](const LeastPair& b) { return b.second >= 0; }))
    return;
  std::vector<bool> decided(best.size(), false);
  if (!settle_by_solved_field(canvas, owner, seeds, solved, best, decided)) {
    report_claims(canvas, seeds, owner, best, claims);
    return;
  }
  // The decided voxels stay out of the reading, and come back to be reported.
  const std::vector<LeastPair> kept(best);
  for (std::size_t n = 0; n < best.size(); ++n)
    if (decided[n]) best[n].second = -1;
  read_old_seeds(canvas, seeds, owner, first_new, source, best);
  for (std::size_t n = 0; n < best.size(); ++n)
    if (decided[n]) best[n] = kept[n];
  report_claims(canvas, seeds, owner, best, claims);
}

// An insertion: the new seeds' blocks against every seed, and the voxels of old blocks that a new
// seed may claim.
void claim_new_blocks(const Canvas& canvas, const std::vector<IndexSeed>& seeds,
                      std::size_t first_new, const SeedGridLevels* grids, std::size_t gridded,
                      const SolvedLeast& solved, std::vector<SeedClaim>& claims) {
  std::vector<std::int32_t> all(seeds.size());
  for (std::size_t t = 0; t < seeds.size(); ++t) all[t] = static_cast<std::int32_t>(t);
  const std::vector<std::int32_t> new_seeds(all.begin() + static_cast<std::ptrdiff_t>(first_new),
                                            all.end());
  const ClaimantSource source{grids, &all, gridded};
  for (std::size_t s = 0; s < seeds.size(); ++s) {
    if (s >= first_new) {
      std::vector<LeastPair> best = owner_pairs(canvas, seeds, s);
      settle_block(canvas, seeds, s, source, best);
      report_claims(canvas, seeds, s, best, claims);
      continue;
    }
    bool affected = false;
    for (std::size_t n = first_new; n < seeds.size() && !affected; ++n)
      affected = may_claim(seeds[n], seeds[s], canvas.dimension);
    if (affected)
      claim_for_new_seeds(canvas, seeds, s, first_new, new_seeds, source, solved, claims);
  }
}

}  // namespace

struct SeedClaimCache::Derived {
  std::vector<Vec3> positions;   // the seeds of the last call
  std::vector<IndexSeed> index;  // derived from them
  // Grids over index[0..gridded), rebuilt when the seeds after them grow past a share of all
  // (an insertion lists those whole) or the seeds before them change.
  std::unique_ptr<SeedGridLevels> grids;
  std::size_t gridded = 0;

  // The grids, given that the first `known` seeds are those of the last call.
  const SeedGridLevels& grids_for(const Canvas& canvas, std::size_t known) {
    constexpr std::size_t kLeastUngridded = 256, kUngriddedShare = 32;
    const std::size_t ungridded = index.size() - std::min(gridded, index.size());
    if (!grids || gridded > known ||
        ungridded > std::max(kLeastUngridded, index.size() / kUngriddedShare)) {
      grids = std::make_unique<SeedGridLevels>(canvas, index);
      gridded = index.size();
    }
    return *grids;
  }
};

SeedClaimCache::SeedClaimCache() = default;
SeedClaimCache::~SeedClaimCache() = default;
SeedClaimCache::SeedClaimCache(SeedClaimCache&&) noexcept = default;
SeedClaimCache& SeedClaimCache::operator=(SeedClaimCache&&) noexcept = default;
void SeedClaimCache::clear() {
  derived_.reset();
}

std::size_t SeedClaimCache::known_prefix(const std::vector<Vec3>& seeds) const {
  if (!derived_) return 0;
  const std::vector<Vec3>& last = derived_->positions;
  const std::size_t most = std::min(last.size(), seeds.size());
  std::size_t n = 0;
  while (n < most && last[n] == seeds[n]) ++n;
  return n;
}

std::vector<SeedClaim> foreign_seed_claims(const Canvas& canvas, const std::vector<Vec3>& seeds,
                                           std::size_t first_new) {
  SeedClaimCache cache;
  return foreign_seed_claims(canvas, seeds, first_new, cache);
}

std::vector<SeedClaim> foreign_seed_claims(const Canvas& canvas, const std::vector<Vec3>& seeds,
                                           std::size_t first_new, SeedClaimCache& cache,
                                           const std::vector<float>* solved_distance) {
  if (!cache.derived_) cache.derived_ = std::make_unique<SeedClaimCache::Derived>();
  const std::size_t known = cache.known_prefix(seeds);
  SeedClaimCache::Derived& derived = *cache.derived_;
  derived.index.resize(known);
  index_seeds(canvas, seeds, known, derived.index);
  derived.positions.resize(known);
  derived.positions.insert(derived.positions.end(),
                           seeds.begin() + static_cast<std::ptrdiff_t>(known), seeds.end());
  const std::vector<IndexSeed>& index = derived.index;
  std::vector<SeedClaim> claims;
  // The grids first: they may be rebuilt, and with them `gridded`.
  const SeedGridLevels& grids = derived.grids_for(canvas, first_new == 0 ? 0 : known);
  if (first_new == 0)
    claim_all_blocks(canvas, index, grids, claims);
  else
    claim_new_blocks(canvas, index, first_new, &grids, derived.gridded,
                     SolvedLeast{canvas, solved_distance}, claims);
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
