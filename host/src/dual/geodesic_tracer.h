#pragma once
// Geodesic tracing by descent of a distance field (private to rvor_dual; the method is described
// in rvor/curved_dual.h). The distance of a label comes either from the labeled canvas (only on
// the voxels of that label: its discrete Voronoi cell) or, when local fields are given, from the
// label's own field u_label over its star box (rvor/local_fields.h).
#include <cstdint>
#include <vector>

#include "rvor/canvas.h"
#include "rvor/local_fields.h"
#include "rvor/propagation.h"

namespace rvor::detail {

class GeodesicTracer {
 public:
  // `locals` may be null: then only the labeled field is used. All are borrowed.
  GeodesicTracer(const Canvas& canvas, const VoronoiField& field, const LocalFields* locals)
      : canvas_(canvas), field_(field), locals_(locals), dimension_(canvas.dimension) {}

  bool has_local_fields() const { return locals_ != nullptr; }
  // Whether staircases are pulled taut (pull_taut in the .cpp; on by default). Off only to
  // measure what the pulling changes.
  void set_pull_staircases(bool pull) { pull_staircases_ = pull; }

  // Traces from `start` (index coordinates) towards the seed at `target` (index coordinates) by
  // descending the distance of `label`. Appends the visited points (index coordinates, not
  // `start`) to `path`, ending with `target` when reached (the return value): within a voxel of it,
  // or in the seed's block, whence the straight step is the exact field's. Stays in the canvas's
  // index box; where the descent stalls (cycles across a shock, is pushed against the boundary,
  // runs out of steps) or leaves the label's voxels, it ends by steepest descent over voxels.
  // `staircase`, when given, tells whether the trace ended by that fallback.
  bool trace(const Vec3& start, const Vec3& target, int32_t label, std::vector<Vec3>& path,
             bool* staircase = nullptr) const;

  // Moves a bisector point of (a, b) (index coordinates) to where the geodesic from a to b
  // crosses the bisector: the fixed point of x -> midpoint of the seeds as extrapolated from x,
  // each seed estimated from the voxels around x as v - G^{-1} grad(u^2) / (2 h^2) (exact in a
  // uniform metric; in general the fixed point is where u_a = u_b and the descent directions are
  // opposite: a stationary point of u on the bisector). The point stays in grid cells where both
  // distances are known (without local fields: the discrete common Voronoi face).
  Vec3 refine_bisector_point(const Vec3& start, int32_t a, int32_t b) const;

  // Local fields only: the voxel (index coordinates) of smallest max(u_a, u_b) where both are
  // known, i.e. within a voxel or so of the bisector point of smallest distance. False when the
  // two boxes share no voxel with both distances known, or without local fields.
  bool bisector_minimum(int32_t a, int32_t b, Vec3& x) const;

  // The metric at a point (index coordinates): interpolated over the active corners of its cell.
  Mat3 metric_near(const Vec3& x) const;
  // Metric length of the segment p-q (index coordinates, so in voxels: times h for world
  // units), summed over pieces of at most half a voxel, each in the metric at its midpoint.
  double segment_length(const Vec3& p, const Vec3& q) const;
  // Whether the segment p-q (index coordinates) stays on the canvas: the voxel nearest each point
  // every half voxel along it is active.
  bool segment_on_canvas(const Vec3& p, const Vec3& q) const;

 private:
  VoxelIndex nearest_voxel(const Vec3& x) const;
  template <typename F>
  void for_each_corner(const Vec3& x, F&& f) const;
  // The distance of `label` at a slot: NaN where unknown (another label's voxel without local
  // fields, outside the label's box, inactive or unreached).
  double distance_of(int64_t slot, int32_t label) const;
  bool carries(int64_t slot, int32_t label) const;
  double squared_distance(int64_t slot, int32_t label) const;
  Vec3 voxel_gradient(int64_t slot, int32_t label, bool& complete) const;
  bool cell_carries(const Vec3& x, int32_t label) const;
  // The fallback of trace where its descent stalls or leaves the label's voxels (see the .cpp).
  bool discrete_descent(const Vec3& x, const Vec3& target, const VoxelIndex& seed_voxel,
                        int32_t label, std::vector<Vec3>& path) const;
  // Whether the segment p-q passes through voxels of the label (see the .cpp).
  bool segment_carries(const Vec3& p, const Vec3& q, int32_t label, double spacing) const;
  // The staircase path[from..] (after `anchor`) shortened by straight segments (see the .cpp).
  void pull_taut(const Vec3& anchor, int32_t label, std::vector<Vec3>& path,
                 std::size_t from) const;
  // x clamped to the canvas's index box (half a voxel beyond the voxel centres).
  Vec3 inside_canvas(const Vec3& x) const;
  // Whether x lies within the seed block (rvor/seed_blocks.h) around `seed_voxel`, in a cell whose
  // active corners all carry `label`: there u is the seed's exact distance |F_s (x - s)|, whose
  // descent is the straight segment to the seed.
  bool in_seed_block(const Vec3& x, const VoxelIndex& seed_voxel, int32_t label) const;
  bool seed_estimate(const Vec3& x, int32_t label, Vec3& seed) const;
  bool sample_wide(const Vec3& x, int32_t label, Vec3& gradient, Mat3& G, int reach) const;
  bool sample(const Vec3& x, int32_t label, Vec3& gradient, Mat3& G) const;

  const Canvas& canvas_;
  const VoronoiField& field_;
  const LocalFields* locals_;
  int dimension_;
  bool pull_staircases_ = true;
};

// World coordinates of index coordinates (z pinned to the canvas plane in 2D).
Vec3 world_of_index(const Canvas& canvas, const Vec3& x);

}  // namespace rvor::detail
