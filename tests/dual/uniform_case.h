#pragma once
// One case of the issue-4 check of the straight dual for a uniform anisotropic metric: 200
// Poisson-disk seeds (in the metric), labels from the reference propagator or exact, then
//  - >= 99.5% of the dual's top simplices are simplices of CGAL's Delaunay triangulation of
//    F * seeds, and each one that is not is flagged near-degenerate by the product;
//  - >= 99% of the Delaunay simplices whose circumcentre (mapped back) lies in the domain with a
//    margin of 3 voxels are in the dual;
//  - the near-degenerate flag agrees with its definition evaluated with the exact metric;
//  - the raw nerve (before near-degenerate configurations are decided in the metric) matches
//    at least min_raw_match (regression guard: it is limited by the canvas resolution).
// Prints the measured rates. Failures are reported through GoogleTest.
#include <cstdint>

#include "rvor/metric.h"

namespace rvor::test {

struct Case {
  int dimension;
  int resolution;  // voxels along the longest side
  Vec3 scales;     // eigenvalues of F = sqrt(G) (2D: the first two)
  std::uint64_t rng_seed;
  bool use_solver;       // the reference propagator, or the exact labels of the uniform metric
  double min_raw_match;  // the raw nerve's measured match rates stay above this
};

// On the unit square / cube.
void run_box_case(const Case& c);
// On a canvas built from a closed .off mesh (a sphere of diameter 1, written to a temporary
// directory); 3D only.
void run_mesh_case(const Case& c);

}  // namespace rvor::test
