#pragma once
// The exact start of docs/scheme.md ("Initialisation"): on a canvas whose metric is one tensor
// everywhere and whose domain is convex (a box, a sphere, a convex mesh...), u0_s(x) = |F (x - s)|
// is the geodesic distance, and the propagators start each voxel at the least u0 over the seeds
// instead of +inf; on other domains, the voxels of the quarter bricks that see their nearest seed.
// This finds, per brick, the few seeds that can be nearest to one of its voxels, so that a voxel
// compares a handful of seeds, not all of them, and which quarters see them.
#include <cstdint>
#include <vector>

#include "rvor/canvas.h"

namespace rvor {

// Whether every active voxel carries the same metric, bit for bit (true for no active voxel).
bool has_uniform_metric(const Canvas& canvas);

// Whether the first active voxel's metric (for a uniform metric: every voxel's) has zero
// off-diagonal entries; false without active voxels.
bool first_metric_is_diagonal(const Canvas& canvas);

// Whether the active voxels fill the whole index box (a box or rectangle domain), so that the
// straight segment between two voxels stays in the domain. Elsewhere u0 can be far below the
// geodesic distance (behind a hole, in a component without seeds), and values that low hold each
// other up: the scheme would raise them by steps of about a voxel, or never.
bool fills_index_box(const Canvas& canvas);

// Whether the active voxels are one piece through their faces (the neighbours a diagonal metric's
// stencil reads); true without active voxels.
bool is_face_connected(const Canvas& canvas);

// Where the exact start may begin a voxel at u0 (docs/scheme.md, "Initialisation"). Only under a
// uniform diagonal metric (the isotropic one among them): a diagonal metric's stencil has axis
// offsets only, so where the neighbour of a voxel towards its seed along an axis lies in the
// canvas the scheme reproduces u0 wherever those neighbours carry the voxel's label. Any other
// stencil loses terms at the domain's faces, and there the scheme's values lie above u0 by more
// than the relaxations raise in a step (uniform:10,3,1 took more evaluations from u0 than from
// +inf). Then:
//  - every_brick: a canvas that fills its index box, or whose domain the builder knew convex
//    (Canvas::convex_domain) and whose voxels are one face-connected piece. At the curved boundary
//    of a domain many voxels thick a missing neighbour leaves the value above u0 by a fraction of
//    a voxel step, which a relaxation or two raises (a slanted plate a few voxels thick is a
//    staircase whose values lie well above u0: the start is then still sound, but slow).
//  - quarters_that_see_their_seeds: any other canvas. Behind a hole u0 lies far below the geodesic
//    distance, and values that low hold each other up: the scheme raises them by steps of about a
//    voxel. A convex domain's voxels can fall apart too (a sliver at a sharp corner, a shape
//    thinner than a voxel), and a piece without seeds started at u0 would count to infinity. So
//    a voxel starts at u0 only where its quarter brick sees its nearest seed
//    (mark_where_seeds_are_seen), elsewhere at +inf.
enum class ExactStartReach { none, every_brick, quarters_that_see_their_seeds };
// For a canvas whose metric half is known (an engine that has packed the stencils already).
ExactStartReach exact_start_reach(const Canvas& canvas, bool uniform_diagonal_metric);
ExactStartReach exact_start_reach(const Canvas& canvas);

// Per canvas brick b, the seeds seeds[begin[b]..begin[b+1]) (labels, ascending): for a uniform
// metric they hold, for every voxel x of the brick, each seed of least u0(x), ties included.
// Per entry, `seen` holds a bit per quarter brick (the 4^3 blocks of a brick, 4^2 in 2D; bit
// q = (x >= 4) + 2 (y >= 4) + 4 (z >= 4) in brick coordinates) that is set where a voxel of that
// quarter may start at the seed's u0, and a voxel whose nearest seed's bit is clear starts at +inf.
// The quarter bit of the voxel at (i, j, k) in its brick's coordinates (the kernel
// start_at_nearest_seeds computes it per brick row).
inline int quarter_of(int i, int j, int k) {
  const int half = Canvas::kBrickEdge / 2;
  return (i >= half ? 1 : 0) + (j >= half ? 2 : 0) + (k >= half ? 4 : 0);
}
// The voxel of that quarter closest to the brick's origin, in the brick's coordinates.
inline VoxelIndex quarter_origin(int q) {
  const int half = Canvas::kBrickEdge / 2;
  return {(q & 1) * half, ((q >> 1) & 1) * half, ((q >> 2) & 1) * half};
}

// The seed's point in continuous index coordinates as the exact start measures it (z = 0 in 2D).
Vec3 seed_index_point(const Canvas& canvas, const Vec3& seed);

struct BrickSeedLists {
  std::vector<std::uint32_t> begin;  // brick_count + 1 entries
  std::vector<std::int32_t> seeds;
  std::vector<std::uint8_t>
      seen;  // as many as seeds; each quarter's bit set by nearest_seed_candidates
};

// The lists for `seeds` (which must lie in the canvas: validate_seeds), measured in the diagonal of
// the metric of the canvas's first active voxel: where the exact start applies (which this does
// not check again), the metric of every voxel. In the coordinates scaled by the square roots of
// that diagonal the metric is Euclidean and a brick is an axis-aligned box; a seed is listed when
// its least distance to the box is at most the least of the seeds' greatest distances to it, found
// among the seeds within the nearest seed's distance plus the box's diameter of its centre (a
// k-d tree over the seeds: one nearest and one radius query per brick). Throws rvor::Error on a
// canvas without active voxels.
// With `only_bricks`, the bricks whose byte is 0 list no seed.
BrickSeedLists nearest_seed_candidates(const Canvas& canvas, const std::vector<Vec3>& seeds,
                                       const std::vector<std::uint8_t>* only_bricks = nullptr);

// Clears the bits of BrickSeedLists::seen whose quarter does not see the entry's seed: a quarter
// sees a seed when it is full (all its voxels active) and the convex hull of its voxel centres and
// the seed lies in full quarters, so that the straight segment from any of its voxels to the seed
// crosses active voxels only and the geodesic distance is the straight one. (A whole brick sees a
// seed when the same holds for the brick in full bricks: one test instead of eight.) The test walks
// from quarter to quarter through faces, so a quarter that sees a seed is joined to the seed's
// voxel through faces: no piece without seeds sees one.
void mark_where_seeds_are_seen(const Canvas& canvas, const std::vector<Vec3>& seeds,
                               BrickSeedLists& lists);

// The lists the exact start begins from: nearest_seed_candidates, marked by
// mark_where_seeds_are_seen unless `reach` is every_brick.
BrickSeedLists exact_start_lists(const Canvas& canvas, const std::vector<Vec3>& seeds,
                                 ExactStartReach reach,
                                 const std::vector<std::uint8_t>* only_bricks = nullptr);

// Under the exact start's metric, a byte per brick, set where a voxel's u0 of one of `seeds` may
// lie below its `distance` (a solved field's, world units; +inf where unlabelled): bricks whose
// least u0 over their box is not above their greatest distance. Only the bricks joined to a seed's
// own brick through the faces of such bricks are tested, so the cost follows the region the seeds
// win. That region reaches each seed's brick (its block) and grows from it, as a Voronoi cell
// does, and the bricks a connected region meets are joined through faces (where it crosses an
// edge or a corner, the bricks around that meet it too); a brick beyond it that the test would
// admit is left to the relaxations, which reach the same fixed point from the field (an
// insertion's start is only where they begin).
std::vector<std::uint8_t> bricks_seeds_may_lower(const Canvas& canvas,
                                                 const std::vector<Vec3>& seeds,
                                                 const std::vector<float>& distance);

// The lists of an insertion's exact start (docs/scheme.md, "Insertion on the device"):
// exact_start_lists of seeds[first_new..], labelled as among `seeds`, on the bricks where
// bricks_seeds_may_lower finds that they may lower `distance`, the field solved for the seeds
// before them; no entry on the other bricks.
BrickSeedLists insertion_start_lists(const Canvas& canvas, const std::vector<Vec3>& seeds,
                                     std::size_t first_new, const std::vector<float>& distance,
                                     ExactStartReach reach);

}  // namespace rvor
