#pragma once
// The initialisation of docs/scheme.md, shared by every propagator: the voxels of the (2r+1)^d
// block around each seed's voxel are boundary data, frozen at the least exact value
// u0_t(x) = |F_t (x - t)| over all seeds t (ties: the smaller label).
#include <cstdint>
#include <memory>
#include <vector>

#include "rvor/canvas.h"

namespace rvor {

constexpr int kSeedBlockRadius = 2;  // r

// Calls visit(x) for each voxel index x of the block centred on voxel `centre` (active or not,
// inside the canvas or not); a 2D canvas's block is one layer.
template <typename Visit>
void for_each_seed_block_voxel(const VoxelIndex& centre, int dimension, Visit&& visit) {
  const int rz = dimension == 3 ? kSeedBlockRadius : 0;
  for (int dk = -rz; dk <= rz; ++dk)
    for (int dj = -kSeedBlockRadius; dj <= kSeedBlockRadius; ++dj)
      for (int di = -kSeedBlockRadius; di <= kSeedBlockRadius; ++di)
        visit(VoxelIndex{centre.i + di, centre.j + dj, centre.k + dk});
}

// A block voxel whose least u0 belongs to a seed whose own block does not contain it (two seeds a
// few voxels apart, or a strongly anisotropic metric): the propagators assign these after the
// blocks, so that a voxel is never frozen to a seed that is not its nearest.
struct SeedClaim {
  VoxelIndex voxel;
  std::int32_t label = -1;
};

// The claims of `seeds` (which must lie in the canvas: validate_seeds). With `first_new` > 0 (an
// insertion into a field solved for seeds[0..first_new)) only claims that a new seed can change
// are listed: on the new seeds' blocks, and by new seeds; the others hold in the field already.
std::vector<SeedClaim> foreign_seed_claims(const Canvas& canvas, const std::vector<Vec3>& seeds,
                                           std::size_t first_new = 0);

// What the claims derive from each seed (its voxel's metric, eigenvalues, reach), kept between
// calls on one canvas: a call derives only the seeds after the longest prefix it shares with the
// last call's (with 100 000 seeds, deriving all took ~0.1 s of every insertion). For one canvas
// only: clear() it when the canvas changes.
class SeedClaimCache {
 public:
  SeedClaimCache();
  ~SeedClaimCache();
  SeedClaimCache(SeedClaimCache&&) noexcept;
  SeedClaimCache& operator=(SeedClaimCache&&) noexcept;
  void clear();
  // How many leading seeds of `seeds` are those of the last call, coordinate for coordinate.
  std::size_t known_prefix(const std::vector<Vec3>& seeds) const;

 private:
  friend std::vector<SeedClaim> foreign_seed_claims(const Canvas&, const std::vector<Vec3>&,
                                                    std::size_t, SeedClaimCache&,
                                                    const std::vector<float>*);
  struct Derived;
  std::unique_ptr<Derived> derived_;
};

// foreign_seed_claims with the seeds' derived data from `cache`, which it updates. An insertion
// may pass `solved_distance`, the distances (world units, one per slot) of the field solved for
// seeds[0..first_new): their seed blocks hold the least u0 over those seeds, which then decides
// where a new seed wins unless the two lie within 1e-4 relative (else the old seeds are read).
std::vector<SeedClaim> foreign_seed_claims(const Canvas& canvas, const std::vector<Vec3>& seeds,
                                           std::size_t first_new, SeedClaimCache& cache,
                                           const std::vector<float>* solved_distance = nullptr);

}  // namespace rvor
