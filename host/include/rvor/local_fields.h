#pragma once
// Per-seed local distance fields for the curved dual. The labeled field keeps, per voxel, only the
// distance to the nearest seed, so the distance u_a of seed a is unknown inside the other cells:
// the bisector {u_a = u_b} is then only known on the common Voronoi face, and a geodesic from a
// point of the opposite edge to a cannot be traced. A local field is u_a itself (seed a alone)
// over the index box of a's star: the bounding box of a and its nerve neighbours (the seeds),
// grown by a margin and clipped to the canvas. The box is convex, so it holds the star's
// Delaunay simplices: in a uniform metric every geodesic the dual needs (bisector points are on
// the segments, face geodesics in the triangles); the margin leaves room for geodesics that bend.
//
// Cost: one single-source CPU reference solve (docs/scheme.md, double precision) per seed on a
// cropped copy of the canvas, seeds spread over threads. Time and transient memory are those of
// the reference solver on the box's active voxels (about 100 B per voxel while solving, per
// thread); what is kept is 4 B per box voxel. A 3D star box holds several cells' worth of voxels
// (more for strongly anisotropic cells, whose boxes are loose), so the total is several times one
// full-canvas reference solve; `voxels` and `seconds` report what it was.
#include <array>
#include <cstddef>
#include <limits>
#include <vector>

#include "rvor/canvas.h"
#include "rvor/nerve.h"

namespace rvor {

// u of one seed over an index box of the canvas, dense, x fastest; +inf where inactive or
// unreached.
struct LocalField {
  std::array<int, 3> lo{}, dims{};
  std::vector<float> distance;

  float at(int i, int j, int k) const {
    i -= lo[0];
    j -= lo[1];
    k -= lo[2];
    if (i < 0 || j < 0 || k < 0 || i >= dims[0] || j >= dims[1] || k >= dims[2])
      return std::numeric_limits<float>::infinity();
    return distance[static_cast<std::size_t>(i) +
                    static_cast<std::size_t>(dims[0]) *
                        (static_cast<std::size_t>(j) + static_cast<std::size_t>(dims[1]) * k)];
  }
  float at(const VoxelIndex& v) const { return at(v.i, v.j, v.k); }
};

struct LocalFieldOptions {
  int margin = 4;                // voxels added on each side of the star's bounding box
  double relative_margin = 0.1;  // and this fraction of the box's extent on that axis
};

struct LocalFields {
  std::vector<LocalField> fields;  // fields[i]: seed i
  std::size_t voxels = 0;          // box voxels summed over seeds (what the solves covered)
  double seconds = 0.0;
};

// Solves u_i for every seed i over its star box (`nerve` gives the neighbours). Throws rvor::Error
// when the nerve does not match the seeds.
LocalFields compute_local_fields(const Canvas& canvas, const Nerve& nerve,
                                 const std::vector<Vec3>& seeds,
                                 const LocalFieldOptions& options = {});

}  // namespace rvor
