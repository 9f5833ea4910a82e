#pragma once
// The curved Riemannian Delaunay dual: each edge of the nerve as a geodesic polyline from seed a
// through the bisector point of smallest distance (the edge's nearest witness, nerve.h) to seed b.
//
// The bisector point: the nearest witness is only a coarse estimate (the distance is flat along
// the bisector near its minimum), so it is first moved, within grid cells carrying both labels,
// to where the descent directions towards a and b are opposite and u_a = u_b: the fixed point of
// x -> midpoint of the two seeds as extrapolated from x (v - G^{-1} grad(u^2) / 2 per voxel v).
//
// Tracing (per side, label L in {a, b}): from the bisector point, step ~0.5 voxel against the
// metric gradient direction D grad u (D = G^{-1}), with the gradient taken by finite differences
// of the squared distance u^2 (same descent direction as u, smooth at the seed, exact differences
// in a uniform metric) on voxels of label L only (central where both neighbours carry L, else
// one-sided of second order, else of first order corrected by h^2 G_aa; voxels with no neighbour
// of label L along some axis are skipped) and interpolated (bi/trilinearly, weights renormalised
// over the cell corners of label L; where no corner qualifies, inverse-distance weighted over the
// 4^d, then 8^d block around the cell). The trace stops within 1 voxel of the seed, which is then
// appended; a trace that runs out of steps or off voxels of label L (for more than a few steps,
// crossed in its last direction) is reported as not reached (the polyline ends where it stopped).
// In a uniform metric the geodesics are straight, so a curved edge follows the straight segment
// wherever the segment's midpoint lies on the common Voronoi face of its seeds (a "Gabriel" edge);
// otherwise the bisector point of smallest distance lies on the face's boundary, off the segment,
// and the curved edge is broken there.
#include <array>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "rvor/canvas.h"
#include "rvor/nerve.h"
#include "rvor/propagation.h"

namespace rvor {

struct CurvedEdge {
  std::array<int32_t, 2> seeds{-1, -1};  // ascending, as in the nerve
  // World points from seeds[0] to seeds[1]; points[bisector_index] is the bisector point.
  std::vector<Vec3> points;
  std::size_t bisector_index = 0;
  // Sum of the segment lengths, each in the metric at its midpoint's voxel.
  double length = 0.0;
  // Per side (seeds[0], seeds[1]): whether the trace came within 1 voxel of the seed.
  std::array<bool, 2> side_reached{false, false};
  bool reached() const { return side_reached[0] && side_reached[1]; }
};

struct CurvedDual {
  int dimension = 3;
  std::vector<Vec3> vertices;     // the seeds
  std::vector<CurvedEdge> edges;  // one per nerve edge, in the nerve's order
  std::size_t unreached_edges = 0;
  double seconds = 0.0;
};

// Traces every nerve edge. `field` is the labeled canvas the nerve was extracted from and `seeds`
// the propagation's seeds (label i = seeds[i]). Throws rvor::Error when the field does not match
// the canvas or the nerve does not match the seeds.
CurvedDual build_curved_dual(const Canvas& canvas, const VoronoiField& field, const Nerve& nerve,
                             const std::vector<Vec3>& seeds);

// VTK .vtu of the curved edges as polylines (VTK_POLY_LINE, cell type 4). Cell data: length
// (Float64, in the metric), reached (UInt8, 1 when both sides reached their seed), seed_a, seed_b
// (Int32). Atomic.
void write_curved_dual_vtu(const std::string& path, const CurvedDual& dual);

}  // namespace rvor
