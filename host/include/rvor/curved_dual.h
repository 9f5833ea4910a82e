#pragma once
// The curved Riemannian Delaunay dual: each nerve edge as a geodesic polyline from seed a through
// the bisector point of smallest distance to seed b, and each nerve triangle (a, b, c) as a
// triangulated patch of geodesics from the points of its curved edge (b, c) to a.
//
// Distances. With local fields (local_fields.h: u_a, seed a's own distance over its star box),
// the bisector is the whole set {u_a = u_b} where both boxes overlap and geodesics run through any
// cell of the star: edges follow the definition for every Delaunay edge. Without them
// (a cheaper fallback, no extra solves), only the labeled field is known: u_a inside a's cell.
// Each side then descends within its own cell, the bisector point is restricted to the common
// Voronoi face (correct for "Gabriel" edges, whose segment midpoint lies on that face; for the
// others it lies on the face's boundary, off the segment, and the edge is broken there), and no
// faces are built (a geodesic from the opposite edge to a crosses other cells).
//
// The bisector point: with local fields, the voxel of smallest max(u_a, u_b) over both boxes;
// without, the edge's nearest witness (nerve.h). Either is only a coarse estimate (the distance
// is flat along the bisector near its minimum), so it is then moved to where the descent
// directions towards a and b are opposite and u_a = u_b: the fixed point of x -> midpoint of the
// two seeds as extrapolated from x (v - G^{-1} grad(u^2) / 2 per voxel v).
//
// Tracing (per side, label L in {a, b}): from the bisector point, step ~0.5 voxel against the
// metric gradient direction D grad u (D = G^{-1}), with the gradient taken by finite differences
// of the squared distance u^2 (same descent direction as u, smooth at the seed, exact differences
// in a uniform metric) on voxels where u_L is known (central where both neighbours are, else
// one-sided of second order, else of first order corrected by h^2 G_aa; voxels with no such
// neighbour along some axis are skipped) and interpolated (bi/trilinearly, weights renormalised
// over the cell corners where u_L is known; where none is, inverse-distance weighted over the
// 4^d, then 8^d block around the cell). The trace stops within 1 voxel of the seed or in its seed
// block, and the seed is then appended. A trace that stalls (cycles, runs out of steps, is pushed
// against the canvas's boundary, or stays off the known voxels for more than a few steps) goes on
// by steepest descent over voxels (a staircase), which is then pulled taut: a later point replaces
// the points before it where a straight segment through known voxels is no longer in the metric.
// A trace that no descent brings to its seed is reported as not reached (the polyline ends where
// it stopped). An edge reached on both sides whose polyline is longer than the straight segment
// between its seeds (each measured as CurvedEdge::length is, the segment on active voxels) is
// replaced by that segment: a geodesic is the shortest path, and such a trace went astray (seeds
// the canvas does not resolve in a fast-varying metric) or zigzags more than the geodesic bends
// (common in 3D shock metrics at coarse resolutions; README, "Straightened edges").
//
// Faces (local fields only): the curved edge (b, c) is sampled every ~2 voxels of its length
// (2 to 16 intervals); from each sample a geodesic to a is traced by descending u_a; the
// geodesics, resampled to the same number of points (~2 voxels apart, 2 to 16 intervals), are
// joined row by row into triangles, the last row fanning into a: at most 16 x 32 triangles per
// face. Cost: up to 17 geodesics of |ab| / 0.5 steps per triangle.
#include <array>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "rvor/canvas.h"
#include "rvor/local_fields.h"
#include "rvor/nerve.h"
#include "rvor/propagation.h"

namespace rvor {

struct CurvedEdge {
  std::array<int32_t, 2> seeds{-1, -1};  // ascending, as in the nerve
  // World points from seeds[0] to seeds[1]; points[bisector_index] is the bisector point.
  std::vector<Vec3> points;
  std::size_t bisector_index = 0;
  // Sum of the segment lengths, each cut into pieces of at most half a voxel, each piece in the
  // metric interpolated at its midpoint.
  double length = 0.0;
  // Per side (seeds[0], seeds[1]): whether the trace came within 1 voxel of the seed, and
  // whether it got there by the tracer's fallback, a steepest descent over voxels (a staircase)
  // where the descent of u stalled.
  std::array<bool, 2> side_reached{false, false};
  std::array<bool, 2> side_staircase{false, false};
  // Whether the traced polyline, reached on both sides, came out longer than the straight segment
  // between the seeds (in the same measure, the segment on active voxels) and was replaced by it:
  // points are then the two seeds and the segment's metric midpoint, the bisector point
  // (CurvedDualOptions::straighten_longer_edges). The side flags above say how it was traced.
  bool straightened = false;
  bool reached() const { return side_reached[0] && side_reached[1]; }
  bool staircase() const { return side_staircase[0] || side_staircase[1]; }
};

// A triangulated geodesic patch for the nerve triangle seeds[0..2]: geodesics from the points of
// the curved edge (seeds[1], seeds[2]) to the apex seeds[0]. The apex is the triangle's smallest
// seed unless some of its geodesics missed it and another seed's missed fewer (build_curved_dual).
struct CurvedFace {
  std::array<int32_t, 3> seeds{-1, -1, -1};        // the apex, then its opposite edge ascending
  std::vector<Vec3> points;                        // world; points[0] is the apex seed
  std::vector<std::array<uint32_t, 3>> triangles;  // indices into points
  std::size_t geodesics = 0;                       // traced from the opposite edge
  std::size_t unreached_geodesics = 0;  // of which did not come within 1 voxel of the apex
  std::size_t staircase_geodesics = 0;  // of which reached it by the fallback (CurvedEdge)
  bool reached() const { return geodesics > 0 && unreached_geodesics == 0; }
};

struct CurvedDual {
  int dimension = 3;
  std::vector<Vec3> vertices;     // the seeds
  std::vector<CurvedEdge> edges;  // one per nerve edge, in the nerve's order
  std::vector<CurvedFace>
      faces;  // one per nerve triangle, in its order; empty without local fields
  std::size_t unreached_edges = 0;
  std::size_t unreached_faces = 0;     // faces with an unreached geodesic
  std::size_t staircase_edges = 0;     // edges with a side ended by the fallback (CurvedEdge)
  std::size_t staircase_faces = 0;     // faces with a geodesic ended so
  std::size_t straightened_edges = 0;  // edges replaced by their straight segment (CurvedEdge)
  bool local_fields = false;           // whether local fields were given
  double seconds = 0.0;                // edges and faces, not the local fields
};

struct CurvedDualOptions {
  // Pull staircases taut (above). Off only to measure what the pulling changes.
  bool pull_staircases = true;
  // A geodesic is the shortest path between its seeds: a traced edge longer than the straight
  // segment between them is replaced by the segment (CurvedEdge::straightened). Off only to
  // measure the traces themselves.
  bool straighten_longer_edges = true;
};

// Traces every nerve edge and, with `locals` (compute_local_fields on the same canvas, field,
// nerve and seeds), every nerve triangle. `field` is the labeled canvas the nerve was extracted
// from and `seeds` the propagation's seeds (label i = seeds[i]). Throws rvor::Error when the field
// does not match the canvas, or the nerve or the local fields do not match the seeds, or a seed's
// voxel holds a distance larger than the seed's own from it by more than a voxel diagonal (the
// field was solved for other seeds; seeds in another order are not detected).
CurvedDual build_curved_dual(const Canvas& canvas, const VoronoiField& field, const Nerve& nerve,
                             const std::vector<Vec3>& seeds, const LocalFields* locals = nullptr,
                             const CurvedDualOptions& options = {});

// VTK .vtu of the curved edges as polylines (VTK_POLY_LINE, cell type 4). Cell data: length
// (Float64, in the metric), reached (UInt8, 1 when both sides reached their seed), staircase,
// straightened (UInt8, CurvedEdge), seed_a, seed_b (Int32). Atomic.
void write_curved_dual_vtu(const std::string& path, const CurvedDual& dual);
// Throws rvor::Error (prefixed with `where`) where an edge or face names a seed that is not one of
// the dual's vertices, an edge's bisector index lies past its points or a face's triangle uses a
// point it does not have: what the writers check before writing (an altered dual was written as
// a corrupt file).
void require_consistent_curved_dual(const CurvedDual& dual, const std::string& where);

// VTK .vtu of the curved faces as triangles (VTK_TRIANGLE, cell type 5), all patches in one
// point set. Cell data: face (Int32, index in dual.faces and the nerve's triangles), seed_a,
// seed_b, seed_c (Int32; seed_a the apex), reached (UInt8, 1 when every geodesic of the face
// reached the apex). Atomic.
void write_curved_faces_vtu(const std::string& path, const CurvedDual& dual);

}  // namespace rvor
