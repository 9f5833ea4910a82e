#pragma once
// The steps of build_straight_dual, one translation unit each: combinatorial topology, exact
// geometric predicates and the triangulation of near-degenerate configurations (the only CGAL
// code), quality in the metric.
#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "rvor/dual.h"

namespace rvor::dual {

struct Topology {
  // +1/-1 per top simplex: its orientation relative to its sorted vertex order, chosen so that
  // neighbours across manifold facets are consistently oriented.
  std::vector<int8_t> parity;
  std::vector<int32_t> component;  // connected component (across manifold facets) per top simplex
  std::vector<std::array<int32_t, 3>> non_manifold_facets;
  std::vector<uint8_t> on_non_manifold_facet;  // per top simplex
  std::size_t non_manifold_boundary = 0;       // boundary edges (3D) / vertices (2D) not closing up
  int euler_characteristic = 0;
  int boundary_euler_characteristic = 0;
  std::size_t dangling = 0;
  std::size_t unused_vertices = 0;
};

Topology analyse_topology(const StraightDual& dual);

// Euler characteristic of the union of the canvas's active voxels as closed cubes (squares in 2D):
// the domain's topology as the canvas holds it (1 for a ball, 0 for a solid torus, 2 for two balls
// or a ball with a cavity), which a dual covering it has too.
int canvas_euler_characteristic(const Canvas& canvas);

// Exact orientation (-1, 0, +1) of the dual's vertices s[0..d] in that order (s[3] unread in 2D).
int orientation_sign(const StraightDual& dual, const std::array<int32_t, 4>& s);
// Exact orientation (-1, 0, +1) of each top simplex taken in its sorted vertex order.
std::vector<int> orientation_signs(const StraightDual& dual);

// Pairs (i < j) of top simplices whose intersection is more than their common face; flat
// simplices (orientation 0) are left out (they are reported as inverted).
std::vector<std::array<std::size_t, 2>> intersecting_pairs(const StraightDual& dual,
                                                           const std::vector<int>& orientation);

// The Delaunay triangulation of a few points (CGAL, exact predicates; cospherical points are
// resolved by its symbolic perturbation, so the simplices never overlap): index tuples into
// `points`, sorted, -1 padded in 2D (z ignored). Empty when the points span fewer dimensions.
std::vector<std::array<int32_t, 4>> delaunay_of(const std::vector<Vec3>& points, int dimension);

// The nerve's top simplices with the near-degenerate ones decided by the empty-sphere test in the
// metric at their witness (local_delaunay.cpp): sorted, distinct, with a near-degenerate mark each
// (witnessed or added simplices with another seed within about a voxel of their circumsphere).
struct LocalDelaunay {
  std::vector<std::array<int32_t, 4>> top;  // sorted seeds, -1 padded in 2D
  std::vector<uint8_t> near_degenerate;     // per top simplex
  std::size_t removed = 0;  // witnessed top simplices with a seed inside their circumsphere
  std::size_t added = 0;    // Delaunay simplices of near-degenerate configurations not witnessed
};

// What every dual entry point checks (`who` starts its messages): the nerve is the canvas's and
// the seeds' (dimension, seed count, every simplex naming seeds in range) and the seeds are finite.
// Returns the seeds as the propagators read them: z = 0 on a 2D canvas, whatever z was given.
std::vector<Vec3> checked_dual_seeds(const Canvas& canvas, const Nerve& nerve,
                                     const std::vector<Vec3>& seeds, const std::string& who);

// The metric of the voxel holding seeds[seed]; throws if that voxel is not active.
Mat3 seed_metric(const Canvas& canvas, const std::vector<Vec3>& seeds, std::size_t seed);
// seed_metric of every seed.
std::vector<Mat3> seed_metrics(const Canvas& canvas, const std::vector<Vec3>& seeds);

LocalDelaunay resolve_near_degenerate(const Canvas& canvas, const Nerve& nerve,
                                      const std::vector<Vec3>& seeds);
// The nerve's top simplices unchanged, none marked.
LocalDelaunay witnessed_as_is(const Nerve& nerve);

// Fills dual.quality and dual.quality_summary.
void measure_quality(StraightDual& dual);

}  // namespace rvor::dual
