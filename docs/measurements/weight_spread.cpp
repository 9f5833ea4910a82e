// How far the Selling weights of each design field's stencils spread: the share of voxel centres
// where sqrt(max rho / min rho) passes 16.8, above which the kernels' rounding bound
// (rounding_tolerance, kernels/eikonal_scheme.clh) exceeds 1e-6, and the largest spread. Built and
// run by weight_spread.sh; docs/scheme.md, "Convergence", quotes its output.
#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <cstdio>

#include "rvor/metric_field.h"
#include "rvor/selling.h"

namespace {

struct FieldCase {
  const char* name;
  int dimension;
  double lo, hi;  // the box [lo, hi]^d
  int resolution;
};

// sqrt(max / min) over the nonzero weights of the stencil at p.
double weight_spread(const rvor::MetricField& field, int dimension, const rvor::Vec3& p) {
  rvor::Mat3 G = field.at(p);
  if (dimension == 2) {
    G(0, 2) = G(1, 2) = G(2, 0) = G(2, 1) = 0;
    G(2, 2) = 1;
  }
  const rvor::SellingStencil stencil = rvor::selling_decomposition(G.inverse(), dimension);
  double least = INFINITY, most = 0;
  for (int t = 0; t < stencil.size; ++t)
    if (stencil.weight[t] > 0)
      least = std::min(least, stencil.weight[t]), most = std::max(most, stencil.weight[t]);
  return std::sqrt(most / least);
}

}  // namespace

int main() {
  const FieldCase cases[] = {
      {"radial_shock_3d", 3, 1, 11, 128},  {"hyperbolic_shock", 3, -1, 1, 64},
      {"hyperbolic_shock", 2, -1, 1, 512}, {"swirl", 2, -1, 1, 512},
      {"starred", 2, -1, 1, 512},          {"unidimensional_shock", 2, 0, 1, 512}};
  for (const FieldCase& c : cases) {
    const auto field = rvor::make_analytic_metric(c.name, c.dimension);
    const double h = (c.hi - c.lo) / c.resolution;
    long voxels = 0, above = 0;
    double largest = 0;
    for (int k = 0; k < (c.dimension == 3 ? c.resolution : 1); ++k)
      for (int j = 0; j < c.resolution; ++j)
        for (int i = 0; i < c.resolution; ++i) {
          const rvor::Vec3 p(c.lo + (i + 0.5) * h, c.lo + (j + 0.5) * h,
                             c.dimension == 3 ? c.lo + (k + 0.5) * h : 0.0);
          const double spread = weight_spread(*field, c.dimension, p);
          largest = std::max(largest, spread);
          ++voxels;
          above += spread > 16.8;
        }
    std::printf("%-22s %dD %4d: %5.2f%% of %ld voxels with a spread above 16.8, largest %.0f\n",
                c.name, c.dimension, c.resolution, 100.0 * above / voxels, voxels, largest);
  }
}
