#pragma once
// Selling's decomposition of a symmetric positive definite D (the dual metric G^-1):
// D = sum_i rho_i e_i e_i^T with rho_i >= 0 and integer offsets e_i (3 terms in 2D, 6 in 3D),
// from an obtuse superbase found by Selling's iterative algorithm (Mirebeau 2019).
#include <array>

#include "rvor/canvas.h"
#include "rvor/metric.h"

namespace rvor {

// Offset size (measured on 20000 random orientations per anisotropy, tests/solver/test_selling.cpp;
// anisotropy = sqrt of the eigenvalue ratio of D, i.e. the eigenvalue ratio of F = G^{1/2}):
// max |component| is about anisotropy/2 in 2D and 0.71 * anisotropy in 3D (1 at <= 2, 5/7 at 10,
// 15/21 at 30, 50/71 at 100). The worst orientations are larger: a search over orientations of a
// needle (middle eigenvalue equal to the smallest; session 37's review) found 101 at anisotropy
// 120, 125 at 150, 134 at 160, so int8 offsets hold every orientation to ~150. Reconstruction
// sum rho e e^T = D holds to ~4e-16 relative up to anisotropy 100 (weights in extended precision).
struct SellingStencil {
  int size = 0;                                // number of terms with rho > 0 (<= 6)
  std::array<double, 6> weight{};              // rho_i
  std::array<std::array<int, 3>, 6> offset{};  // e_i (z = 0 in 2D)
};

// `dimension` 2 uses the upper-left 2x2 block. Terms with rho == 0 are dropped. Throws rvor::Error
// if D is not SPD or the iteration does not terminate (which only happens for non-SPD input).
SellingStencil selling_decomposition(const Mat3& D, int dimension);

// The longest offset component the engines store (int8 in both).
inline constexpr int kMostStencilOffset = 127;

// selling_decomposition of D, the dual of `canvas`'s tensor at `slot`, for the engines: a tensor
// that is not SPD (written with Canvas::mutable_metric after the builder checked it), or whose
// stencil has an offset component beyond kMostStencilOffset, is an rvor::Error naming the voxel,
// its world position and the tensor as stored, not its inverse.
SellingStencil canvas_selling_decomposition(const Canvas& canvas, std::size_t slot, const Mat3& D);

}  // namespace rvor
