#pragma once
// The voxels of a seed's star (private to rvor_dual, for local_fields.cpp): where its local field
// is solved. In a uniform metric the star (the union of a's Delaunay simplices) is star-shaped
// from a in index space, so a solve restricted to it is exact there and costs a few cells' worth
// of voxels instead of the whole ball that holds the star.
#include <array>
#include <cstdint>
#include <vector>

#include "rvor/metric.h"

namespace rvor::detail {

// A simplex of the star: its vertices (index coordinates, z = 0 in 2D) and how far around it
// voxels count (index units).
struct StarSimplex {
  std::vector<Vec3> vertices;
  double margin = 0.0;
};

// Dense mask over the index box [lo, lo + dims) (x fastest): 1 for voxels within the margin of a
// simplex. Top simplices (d + 1 vertices) are taken as the intersection of their faces'
// half-spaces pushed out by the margin (a superset of the Minkowski dilation); edges and flat
// simplices as capsules around their edges.
std::vector<uint8_t> star_mask(const std::array<int, 3>& lo, const std::array<int, 3>& dims,
                               int dimension, const std::vector<StarSimplex>& simplices);

}  // namespace rvor::detail
