#include "rvor/seed_blocks.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <tuple>

#include <Eigen/LU>

namespace rvor {

namespace {

// A seed as the claims see it, in index units (voxel centres at integers): u0 / h.
struct IndexSeed {
  Vec3 centre;       // continuous index coordinates (z = 0 in 2D)
  VoxelIndex voxel;  // the containing voxel, the centre of its block
  Mat3 G;            // the metric of that voxel

  double u0(const VoxelIndex& x) const {
    const Vec3 q = Vec3(x.i, x.j, x.k) - centre;
    return std::sqrt(std::max(0.0, q.dot(G * q)));
  }
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
    result.push_back(seed);
  }
  return result;
}

// Calls visit(x) for the voxels of the seed's block (active or not).
template <typename Visit>
void for_each_block_voxel(const IndexSeed& seed, int dimension, Visit&& visit) {
  const int rz = dimension == 3 ? kSeedBlockRadius : 0;
  for (int dk = -rz; dk <= rz; ++dk)
    for (int dj = -kSeedBlockRadius; dj <= kSeedBlockRadius; ++dj)
      for (int di = -kSeedBlockRadius; di <= kSeedBlockRadius; ++di)
        visit(VoxelIndex{seed.voxel.i + di, seed.voxel.j + dj, seed.voxel.k + dk});
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

  const std::vector<std::int32_t>& seeds_near(const VoxelIndex& x) const {
    return lists_[cell_index(x.i / cell_, x.j / cell_, x.k / cell_)];
  }

 private:
  using CellBox = std::pair<std::array<int, 3>, std::array<int, 3>>;

  int max_dim() const { return std::max({dims_[0], dims_[1], dims_[2]}); }
  std::size_t cell_index(int i, int j, int k) const {
    return static_cast<std::size_t>(i) +
           static_cast<std::size_t>(cells_[0]) * (j + static_cast<std::size_t>(cells_[1]) * k);
  }

  // Half-widths of {q : q^T G q <= reach^2} are reach sqrt((G^-1)_aa).
  CellBox cell_box(const IndexSeed& seed, double reach) const {
    const Mat3 D = seed.G.inverse();
    CellBox box;
    for (int a = 0; a < 3; ++a) {
      const double half = a < dimension_ ? reach * std::sqrt(std::max(0.0, D(a, a))) : 0.0;
      const double lo = std::clamp(seed.centre[a] - half, 0.0, dims_[a] - 1.0);
      const double hi = std::clamp(seed.centre[a] + half, 0.0, dims_[a] - 1.0);
      box.first[a] = static_cast<int>(std::floor(lo)) / cell_;
      box.second[a] = static_cast<int>(std::ceil(hi)) / cell_;
    }
    return box;
  }

  std::size_t registrations(const std::vector<IndexSeed>& seeds, double reach) {
    for (int a = 0; a < 3; ++a) cells_[a] = (dims_[a] + cell_ - 1) / cell_;
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

// The largest u0 of any seed over its own block: no claim is farther from its seed.
double largest_block_u0(const std::vector<IndexSeed>& seeds, int dimension) {
  double reach = 0;
  for (const IndexSeed& seed : seeds)
    for_each_block_voxel(seed, dimension,
                         [&](const VoxelIndex& x) { reach = std::max(reach, seed.u0(x)); });
  return reach;
}

}  // namespace

std::vector<SeedClaim> foreign_seed_claims(const Canvas& canvas, const std::vector<Vec3>& seeds,
                                           std::size_t first_new) {
  const std::vector<IndexSeed> index = index_seeds(canvas, seeds);
  const SeedGrid grid(canvas, index, largest_block_u0(index, canvas.dimension));
  std::vector<SeedClaim> claims;
  for (std::size_t s = 0; s < index.size(); ++s)
    for_each_block_voxel(index[s], canvas.dimension, [&](const VoxelIndex& x) {
      if (canvas.slot_of(x) < 0) return;
      const std::vector<std::int32_t>& near = grid.seeds_near(x);
      // An old block voxel can only change if a new seed is near it.
      if (s < first_new && std::none_of(near.begin(), near.end(), [&](std::int32_t t) {
            return static_cast<std::size_t>(t) >= first_new;
          }))
        return;
      std::pair<double, std::int32_t> best{index[s].u0(x), static_cast<std::int32_t>(s)};
      for (const std::int32_t t : near) best = std::min(best, {index[t].u0(x), t});
      if (!index[best.second].owns(x)) claims.push_back({x, best.second});
    });
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
