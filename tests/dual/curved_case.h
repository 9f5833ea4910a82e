#pragma once
// The curved-dual test case shared by the default and the heavy tests: a uniform anisotropic
// metric on the unit box, Poisson-disk seeds in the metric, the curved dual with or without local
// fields, and what it measures against the straight simplices (geodesics are straight there).
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "rvor/curved_dual.h"

namespace rvor::test {

double distance_to_segment(const Vec3& p, const Vec3& a, const Vec3& b);
// Distance from p to the triangle (a, b, c): to its plane where p projects inside, else to the
// nearest side.
double distance_to_triangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c);
// True when the F-space midpoint of (a, b) is nearer to a and b than to any other seed by at
// least `margin` (metric units).
bool is_gabriel(const std::vector<Vec3>& seeds, const Mat3& F, int a, int b, double margin);

struct CurvedCase {
  int dimension;
  int resolution;
  std::size_t seed_count;
  std::uint64_t rng_seed;
  bool reference_solver = false;  // else the exact field of the uniform metric
  bool local_fields = true;       // else the labeled field only (edges checked if Gabriel)
};

struct CurvedMeasures {
  std::size_t edges = 0, gabriel = 0, unreached = 0;
  double max_deviation_voxels = 0.0;       // Gabriel edges
  double max_relative_length_error = 0.0;  // Gabriel edges
  double max_deviation_all = 0.0, max_relative_length_error_all = 0.0;
  std::size_t faces = 0, unreached_faces = 0, face_triangles = 0;
  double max_face_deviation = 0.0;  // voxels from the flat triangle
  double local_seconds = 0.0, local_voxels_per_seed = 0.0;
};

// Builds and checks the case with GoogleTest expectations: every edge within 2 voxels of its
// segment and 2% of |F (a - b)| (with local fields; else Gabriel edges only), every face vertex
// within 2 voxels of its flat triangle, everything reached. Prints the measures. With `out_dir`,
// writes curved_dual.vtu and curved_faces.vtu there.
CurvedMeasures run_case(const CurvedCase& c, const std::string& out_dir = "");

}  // namespace rvor::test
