#pragma once
// The exact start of docs/scheme.md ("Initialisation"): on a canvas whose metric is one tensor
// everywhere and whose domain is convex (a box, a sphere, a convex mesh...), u0_s(x) = |F (x - s)|
// is the geodesic distance, and the propagators start each voxel at the least u0 over the seeds
// instead of +inf. This finds, per brick, the few seeds that can be nearest to one of its voxels,
// so that a voxel compares a handful of seeds, not all of them.
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

// Whether the exact start applies: a uniform diagonal metric (the isotropic one among them) on a
// canvas that fills its index box, or whose domain the builder knew convex (Canvas::convex_domain)
// and whose voxels are one face-connected piece: a convex domain's voxels can still fall apart (a
// sliver at a sharp corner, a shape thinner than a voxel), and a piece without seeds started at u0
// would count to infinity, each voxel a step above its neighbour, until the round limit.
// A diagonal metric's stencil has axis offsets only, so in a box the neighbour of a voxel towards
// any seed along an axis lies in the canvas, and the scheme reproduces u0 wherever those
// neighbours carry the voxel's label; at the curved boundary of a domain many voxels thick a
// missing neighbour leaves the value above u0 by a fraction of a voxel step, which a relaxation or
// two raises (a slanted plate a few voxels thick is a staircase whose values lie well above u0:
// the start is then still sound, but slow). Any other stencil loses terms at the box's faces, and
// there the scheme's values lie above u0 by more than the relaxations raise in a step
// (docs/scheme.md, "Initialisation": uniform:10,3,1 took more evaluations from u0 than from +inf).
// Outside a convex domain u0 can lie far below the geodesic distance (behind a hole).
bool exact_start_applies(const Canvas& canvas);
// The domain half of exact_start_applies (for an engine that knows the metric half already):
// the canvas fills its index box, or its domain is convex and its voxels one face-connected piece.
bool exact_start_domain(const Canvas& canvas);

// Per canvas brick b, the seeds seeds[begin[b]..begin[b+1]) (labels, ascending): for a uniform
// metric they hold, for every voxel x of the brick, each seed of least u0(x), ties included.
struct BrickSeedLists {
  std::vector<std::uint32_t> begin;  // brick_count + 1 entries
  std::vector<std::int32_t> seeds;
};

// The lists for `seeds` (which must lie in the canvas: validate_seeds), measured in the diagonal of
// the metric of the canvas's first active voxel: where exact_start_applies (which this does not
// check again), the metric of every voxel. In the coordinates scaled by the square roots of that
// diagonal the metric is Euclidean and a brick is an axis-aligned box; a seed is listed when its
// least distance to the box is at most the least of the seeds' greatest distances to it, found
// among the seeds within the nearest seed's distance plus the box's diameter of its centre (a
// k-d tree over the seeds: one nearest and one radius query per brick). Throws rvor::Error on a
// canvas without active voxels.
BrickSeedLists nearest_seed_candidates(const Canvas& canvas, const std::vector<Vec3>& seeds);

}  // namespace rvor
