#pragma once
// A mesh domain for the dual tests: a closed triangle mesh (an icosahedron subdivided twice and
// projected on a sphere: 320 faces, convex) written as .off, and its canvas from the OpenVDB
// canvas builder.
#include <string>
#include <vector>

#include "rvor/canvas.h"

namespace rvor::test {

struct Icosphere {
  struct Plane {
    Vec3 normal;    // unit, outward
    double offset;  // normal . x on the plane
  };
  std::vector<Plane> planes;
  // Distance from x to the boundary for x inside (the polyhedron is convex), negative outside.
  double depth(const Vec3& x) const;
};

Icosphere write_icosphere_off(const std::string& path, const Vec3& centre, double radius);

// The canvas of the closed surface mesh at `path` with the uniform metric G, `resolution` voxels
// along its bounding box's longest side.
Canvas build_uniform_mesh_canvas(const std::string& path, const Mat3& G, int resolution);

}  // namespace rvor::test
