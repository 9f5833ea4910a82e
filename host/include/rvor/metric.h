#pragma once
// Riemannian metric tensors: 3x3 symmetric positive definite matrices G (length of v is
// sqrt(v^T G v)). A 2D metric is stored as a 3x3 matrix with G(2,2) = 1 and G(0,2) = G(1,2) = 0.
// Component order of the 6 stored values follows Medit/MMG .sol tensors: m11 m12 m22 m13 m23 m33.
#include <array>
#include <string>
#include <vector>

#include <Eigen/Core>

namespace rvor {

using Vec3 = Eigen::Vector3d;
using Mat3 = Eigen::Matrix3d;
using SolTensor = std::array<double, 6>;  // m11 m12 m22 m13 m23 m33

Mat3 tensor_from_sol(const SolTensor& c);
SolTensor tensor_to_sol(const Mat3& G);

// True when G is symmetric (to a relative 1e-9), finite and positive definite.
bool is_spd(const Mat3& G);
// Whether the symmetric S has an LDL^T factorisation with positive pivots (S is positive definite
// to rounding): Cholesky's test without its square roots, written out for 3x3; like Eigen's LLT,
// it reads the lower triangle only, and finiteness is the caller's to check (diag(inf, 1, 1)
// passes). An Eigen::LLT per voxel took a quarter of a Selling decomposition and a sixth of a
// varying metric's canvas build. (The leading minors through determinants are not a substitute:
// their cancellation rejected rotated spectra of ratio 1e-12, which Cholesky accepts.)
bool has_positive_pivots(const Mat3& S);
// Throws rvor::Error "metric <where> is not symmetric positive definite: [..]" (or "is not
// finite") unless is_spd(G). `where` names the source, e.g. "'swirl' at (0.1, 0.2, 0)".
void require_spd(const Mat3& G, const std::string& where);
// What is wrong with G ("is not finite: ...", "is not symmetric positive definite: ...", "is too
// anisotropic: ..."), or "" when is_spd(G).
std::string spd_problem(const Mat3& G);
// spd_problem, with G judged as the metric of a canvas of `dimension`: in 3D every eigenvalue
// counts, so a tensor with m13 = m23 = 0 and a nearly zero m33 is too anisotropic (spd_problem
// alone cannot tell it from a 2D tensor, whose m33 is unused).
std::string metric_problem(const Mat3& G, int dimension);
// Eigenvalues (ascending) of G's xy block in 2D, of G in 3D: the metric a canvas of that
// dimension uses.
Eigen::VectorXd metric_eigenvalues(const Mat3& G, int dimension);

// The tensor as a canvas stores it: rounded to float, and in 2D its xy block (the z row and
// column of the identity).
Mat3 stored_metric(const Mat3& G, int dimension);
// The eigenvalues a canvas accepts: well inside float's range, so that products of tensors, voxel
// sizes and distances stay normal floats in every engine.
constexpr double kLeastMetricEigenvalue = 1e-30, kMostMetricEigenvalue = 1e30;
// Whether `stored` (from stored_metric) is SPD with eigenvalues (of its xy block in 2D) in
// [kLeastMetricEigenvalue, kMostMetricEigenvalue].
bool is_storable_metric(const Mat3& stored, int dimension);
// Throws rvor::Error naming `where` unless is_storable_metric. `given` is the tensor before
// storage, for the message.
void require_storable_metric(const Mat3& stored, const Mat3& given, int dimension,
                             const std::string& where);

// The functions below take SPD tensors and do not check (they run in inner loops; validate input
// with require_spd): a negative eigenvalue is taken as 0 by metric_sqrt and gives NaN in
// metric_log, and distortion of a singular tensor is meaningless.
// F = G^{1/2}, the symmetric square root (eigen-decomposition). d_G(x, y) = |F (x - y)|.
Mat3 metric_sqrt(const Mat3& G);
Mat3 metric_log(const Mat3& G);                      // symmetric matrix logarithm of an SPD matrix
Mat3 metric_exp(const Mat3& S);                      // symmetric matrix exponential
double metric_length(const Mat3& G, const Vec3& v);  // sqrt(v^T G v)

// Distortion psi(G1, G2) = max(|F1 F2^-1|_2, |F2 F1^-1|_2) >= 1.
double distortion(const Mat3& G1, const Mat3& G2);

// G = exp(sum w_i log G_i); weights are normalised to sum 1. Throws on empty or mismatched input.
Mat3 interpolate_log_euclidean(const std::vector<Mat3>& metrics,
                               const std::vector<double>& weights);
// G = sum w_i G_i (weights normalised).
Mat3 interpolate_linear(const std::vector<Mat3>& metrics, const std::vector<double>& weights);

// M = a^2 v1 v1^T + b^2 v2 v2^T + c^2 v3 v3^T, where a, b, c are eigenvalues of F and the v_i an
// orthonormal frame (v3 = v1 x v2 is used when dimension is 3; 2D metrics ignore c).
Mat3 metric_from_frame(int dimension, const Vec3& v1, double a, const Vec3& v2, double b, double c);

}  // namespace rvor
