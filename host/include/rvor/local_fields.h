#pragma once
// Per-seed local distance fields for the curved dual. The labeled field keeps, per voxel, only the
// distance to the nearest seed, so the distance u_a of seed a is unknown inside the other cells:
// the bisector {u_a = u_b} is then only known on the common Voronoi face, and a geodesic from a
// point of the opposite edge to a cannot be traced. A local field is u_a itself (seed a alone)
// over a's star: a's edges, and the top simplices at a, taken straight in index space and grown by
// a margin. Where the metric is nearly uniform over a top simplex, only the apexes of its
// triangles take it (a face is traced towards its smallest seed first: the smallest seed, and in
// 3D the second smallest, the apex of the face opposite the smallest); elsewhere every seed of it
// does (local_fields.cpp, star_simplices). In a uniform metric that region is star-shaped from a,
// so a solve restricted to it is exact there, and it holds the geodesics the dual traces on u_a
// (the bisector point of smallest distance of each edge is on the segment, the geodesics of the
// faces with apex a are in their triangles; a face retried towards another apex, or a 3D triangle
// of no tetrahedron, has the edges' capsules only); in a varying metric the margin leaves room for
// geodesics that bend, and a geodesic that leaves the star is reported as not reached. The solve
// also stops at a distance limit that bounds every point of a's curved edges and faces
// (distance_limits in local_fields.cpp), beyond which u_a is not needed.
//
// Cost: one single-source CPU reference solve (docs/scheme.md, double precision) per seed on a
// cropped copy of the canvas (the star's bounding box, active on the star only), seeds spread over
// threads, as many at once as LocalFieldOptions::memory_budget allows: about 320 B per voxel of
// the bounding box while solving, per solve in flight; kept: 4 B per voxel of the bounding box.
// The solve keeps each voxel's terms and skips the evaluations that cannot change it (reference
// solver, SingleSourceTerms). Measured (README, "The curved dual"): `rvor voronoi --domain
// box:0,0,0,1,1,1 --resolution 96 --metric uniform:10,3,5,2,1,4 --random-seeds 500 --dual curved
// --device cpu`: the boxes hold 31 times the canvas's voxels, 12 times solved, 6.8 s on 2 cores
// against 6.2 to 6.4 s for the CPU solve of the labeled field (a loaded hour). `solved_voxels` and
// `seconds` report what it was.
#include <array>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <limits>
#include <optional>
#include <vector>

#include "rvor/canvas.h"
#include "rvor/nerve.h"

namespace rvor {

// u of one seed over an index box of the canvas (lo, dims); +inf where inactive or unreached. Kept
// by bricks of the box (8^3 voxels, 8x8x1 in 2D, from lo on): only those holding a solved voxel,
// x fastest within a brick. A star covers about a third of its box, but touches most of its bricks:
// radial_shock_3d 96^3, 500 seeds (README, "What it costs"), 12.65M voxels solved, 26.4M kept in
// bricks, 33.0M in whole boxes (da5cffd's parent).
struct LocalField {
  std::array<int, 3> lo{}, dims{};
  std::array<int, 3> brick_dims{};  // bricks of the box per axis
  int brick_edge_z = Canvas::kBrickEdge;
  std::vector<int32_t> brick_start;  // per brick of the box (x fastest): its first value, or -1
  std::vector<float> values;         // the kept bricks' values

  bool empty() const { return values.empty(); }
  float at(int i, int j, int k) const {
    i -= lo[0];
    j -= lo[1];
    k -= lo[2];
    if (i < 0 || j < 0 || k < 0 || i >= dims[0] || j >= dims[1] || k >= dims[2])
      return std::numeric_limits<float>::infinity();
    const int e = Canvas::kBrickEdge;
    const int32_t start = brick_start[static_cast<std::size_t>(i / e) +
                                      static_cast<std::size_t>(brick_dims[0]) *
                                          (static_cast<std::size_t>(j / e) +
                                           static_cast<std::size_t>(brick_dims[1]) *
                                               static_cast<std::size_t>(k / brick_edge_z))];
    if (start < 0) return std::numeric_limits<float>::infinity();
    return values[static_cast<std::size_t>(start) +
                  static_cast<std::size_t>(i % e + e * (j % e + e * (k % brick_edge_z)))];
  }
  float at(const VoxelIndex& v) const { return at(v.i, v.j, v.k); }
};

// compute_local_fields throws rvor::Error for a margin outside [0, 1000] voxels, a relative margin
// outside [0, 10] or a distortion that is negative or NaN.
struct LocalFieldOptions {
  // Around each simplex of the star: voxels, plus this fraction of its longest edge. Near the
  // star's boundary the stencils lose neighbours and the values degrade; the tracer reads them
  // near hull edges. Measured (uniform, anisotropy 16 in G): edges within 1.2 voxels of their
  // segments with 0.1; 2.4 voxels with 0.05 (past the 2-voxel requirement).
  int margin = 2;
  double relative_margin = 0.1;
  // The same fraction for an edge in a seed's star where the star's top simplices do not all
  // surround it (some around it are not in the star, or they do not close around it: a hull
  // edge); there the edge's capsule alone holds, on some side, the stencils its segment's values
  // read. Measured (test LocalFieldsAreTheSeedsOwnDistancesOverTheirStars prints it; uniform,
  // anisotropy 4 in F), the field's worst relative error along the edges: 2D (96^2, 15 seeds)
  // 3.6e-3 with 0.1, 4.7e-4 with 0.2; 3D (48^3, 40 seeds) 1.1e-2 with 0.2. At 618a75d, when every
  // seed's star held all its top simplices and every edge 0.1: 7.1e-4 and 2.5e-2.
  double edge_relative_margin = 0.2;
  // A top simplex whose seeds' metrics are within this distortion (rvor/metric.h) of each other
  // goes only to the stars of its triangles' apexes; beyond it (or with 0), to all its seeds'.
  // Measured on 3D hyperbolic_shock, 48^3, 400 seeds (coarse: the metric varies several-fold
  // between neighbouring seeds; test StarsKeepTheirSimplicesWhereTheMetricVaries prints it): with
  // every top simplex given to its apexes only, 11 of 3077 edges come out over 5% longer than with
  // every simplex in every star, one 3.1 times (its geodesic bends out of the capsules); with 1.5,
  // none. Uniform metrics keep the whole saving (the README's uniform case: 10.5M voxels solved,
  // 12.7M at 618a75d, when every seed's star held all its simplices).
  double apex_only_distortion = 1.5;
  // Bytes the job may hold (rvor/memory_budget.h; 0: default_memory_budget()): the fields kept
  // and the solves in flight, beside the canvas and its field. Fewer solves run at once where
  // that fits; where one does not, compute_local_fields throws rvor::Error before solving.
  std::uint64_t memory_budget = 0;
  // Called after each seed's solve with the seeds solved so far and how many there are to solve
  // (from the solving threads, one call at a time), for progress reports on long runs.
  std::function<void(std::size_t solved, std::size_t total)> progress;
};

struct LocalFields {
  std::vector<LocalField> fields;  // fields[i]: seed i
  std::size_t voxels = 0;          // voxels of the kept bricks summed over seeds
  std::size_t solved_voxels = 0;   // of which solved: in the star and within the distance limit
  double seconds = 0.0;
  // Canvas::content_hash of the canvas they were computed on (build_curved_dual refuses them on
  // another).
  std::optional<std::uint64_t> canvas_hash;
  // The seeds they were solved for (z = 0 on a 2D canvas): build_curved_dual refuses them for
  // other seeds, which it traced on without an error (every geodesic towards a field of another
  // seed, most of them unreached).
  std::vector<Vec3> seeds;
};

// Solves u_i for every seed i over its star (`nerve` gives the simplices). Throws rvor::Error
// when the nerve does not match the seeds.
LocalFields compute_local_fields(const Canvas& canvas, const Nerve& nerve,
                                 const std::vector<Vec3>& seeds,
                                 const LocalFieldOptions& options = {});

}  // namespace rvor
