#include "rvor/metric.h"

#include <cmath>
#include <limits>
#include <sstream>

#include <Eigen/Eigenvalues>
#include <Eigen/SVD>

#include "rvor/error.h"

namespace rvor {

namespace {

// Applies f to the eigenvalues of a symmetric matrix.
template <typename Function>
Mat3 spectral_map(const Mat3& S, Function f) {
  Eigen::SelfAdjointEigenSolver<Mat3> eigen(S);
  Vec3 values = eigen.eigenvalues();
  for (int i = 0; i < 3; ++i) values[i] = f(values[i]);
  return eigen.eigenvectors() * values.asDiagonal() * eigen.eigenvectors().transpose();
}

std::string describe(const Mat3& G) {
  std::ostringstream out;
  out.precision(6);
  out << "[" << G(0, 0) << " " << G(0, 1) << " " << G(1, 1) << " " << G(0, 2) << " " << G(1, 2)
      << " " << G(2, 2) << "] (m11 m12 m22 m13 m23 m33)";
  return out.str();
}

Mat3 normalised_weighted_sum(const std::vector<Mat3>& terms, const std::vector<double>& weights) {
  if (terms.empty() || terms.size() != weights.size())
    throw Error("metric interpolation needs as many weights as metrics, and at least one");
  double total = 0;
  for (double w : weights) {
    if (!std::isfinite(w) || w < 0)
      throw Error("metric interpolation weight is negative or not finite");
    total += w;
  }
  if (total <= 0) throw Error("metric interpolation weights sum to zero");
  Mat3 sum = Mat3::Zero();
  for (std::size_t i = 0; i < terms.size(); ++i) sum += (weights[i] / total) * terms[i];
  return sum;
}

// The eigenvalues is_spd judges a symmetric S by: a 2D metric's z entry is decoupled from its xy
// block, so those of the xy block alone (a large xy block next to S(2,2) = 1 is no singular
// matrix), else those of S.
int judged_block_size(const Mat3& S) {
  return S(0, 2) == 0 && S(1, 2) == 0 ? 2 : 3;
}
Eigen::VectorXd judged_eigenvalues(const Mat3& S) {
  return metric_eigenvalues(S, judged_block_size(S));
}

// A rotated singular matrix often comes out of rounding with a tiny positive eigenvalue
// (~eps |S|): eigenvalues that small are noise, not a positive spectrum.
constexpr double kClearlyPositiveRatio = 64 * std::numeric_limits<double>::epsilon();
bool clearly_positive(const Eigen::VectorXd& values) {
  return values.minCoeff() > kClearlyPositiveRatio * values.maxCoeff();
}

// Whether the spectrum of the leading n x n block of an SPD S is clearly positive by bounds
// alone: its largest eigenvalue is at most the trace and its smallest at least det / trace^(n-1),
// so their ratio is at least det / trace^n. Twice the threshold covers the determinant's rounding
// (a few epsilons of trace^n); false means "not settled", not "not positive".
bool clearly_positive_by_bounds(const Mat3& S, int n) {
  const double trace = S.topLeftCorner(n, n).trace();
  const double det = n == 3 ? S.determinant() : S.topLeftCorner<2, 2>().determinant();
  return det / std::pow(trace, n) > 2 * kClearlyPositiveRatio;
}

bool is_symmetric(const Mat3& G) {
  return (G - G.transpose()).cwiseAbs().maxCoeff() <= 1e-9 * G.cwiseAbs().maxCoeff();
}

}  // namespace

Mat3 tensor_from_sol(const SolTensor& c) {
  Mat3 G;
  G << c[0], c[1], c[3], c[1], c[2], c[4], c[3], c[4], c[5];
  return G;
}

SolTensor tensor_to_sol(const Mat3& G) {
  return {G(0, 0), G(0, 1), G(1, 1), G(0, 2), G(1, 2), G(2, 2)};
}

bool has_positive_pivots(const Mat3& S) {
  const double d0 = S(0, 0);
  if (!(d0 > 0)) return false;
  const double l10 = S(1, 0) / d0, l20 = S(2, 0) / d0;
  const double d1 = S(1, 1) - l10 * S(1, 0);
  if (!(d1 > 0)) return false;
  const double e21 = S(2, 1) - l20 * S(1, 0);
  return S(2, 2) - l20 * S(2, 0) - e21 * (e21 / d1) > 0;
}

bool is_spd(const Mat3& G) {
  if (!G.allFinite()) return false;
  if (G.cwiseAbs().maxCoeff() <= 0 || !is_symmetric(G)) return false;
  const Mat3 S = 0.5 * G + 0.5 * G.transpose();  // not 0.5 (G + G^T): G + G^T overflows at 1e308
  if (!has_positive_pivots(S)) return false;
  // Positive pivots admit some matrices that are numerically singular: require a clearly positive
  // spectrum (S(2,2) > 0 follows from the pivots), settled without an eigen solve where
  // the bound of clearly_positive_by_bounds does (most tensors: the solve was most of a varying
  // metric's canvas build).
  return clearly_positive_by_bounds(S, judged_block_size(S)) ||
         clearly_positive(judged_eigenvalues(S));
}

namespace {

// The "too anisotropic" text for judged eigenvalues that are positive but not clearly so.
std::string too_anisotropic(const Eigen::VectorXd& values, const std::string& block,
                            const Mat3& G) {
  std::ostringstream ratio;
  ratio << values.minCoeff() / values.maxCoeff();
  return "is too anisotropic: the ratio of its smallest to its largest eigenvalue" + block + ", " +
         ratio.str() +
         ", is within rounding of a singular matrix (below 64 machine epsilons): " + describe(G);
}

}  // namespace

std::string spd_problem(const Mat3& G) {
  if (!G.allFinite()) return "is not finite: " + describe(G);
  if (is_spd(G)) return "";
  // Positive but nearly singular: say so, a "not positive definite" would mislead.
  const Mat3 S = 0.5 * G + 0.5 * G.transpose();
  const Eigen::VectorXd values = judged_eigenvalues(S);
  if (is_symmetric(G) && values.minCoeff() > 0 && S(2, 2) > 0)
    return too_anisotropic(values, values.size() == 2 ? " in the xy plane" : "", G);
  return "is not symmetric positive definite: " + describe(G);
}

std::string metric_problem(const Mat3& G, int dimension) {
  const std::string problem = spd_problem(G);
  if (!problem.empty()) return problem;
  // is_spd judges a tensor with m13 = m23 = 0 by its xy block (it does not know the dimension):
  // in 3D its m33 counts too.
  const Eigen::VectorXd values = metric_eigenvalues(G, dimension);
  if (!clearly_positive(values)) return too_anisotropic(values, "", G);
  return "";
}

void require_spd(const Mat3& G, const std::string& where) {
  const std::string problem = spd_problem(G);
  if (!problem.empty()) throw Error("metric " + where + " " + problem);
}

Mat3 stored_metric(const Mat3& G, int dimension) {
  Mat3 stored = Mat3::Identity();
  const int n = dimension == 3 ? 3 : 2;
  for (int r = 0; r < n; ++r)
    for (int c = 0; c < n; ++c) stored(r, c) = static_cast<double>(static_cast<float>(G(r, c)));
  return stored;
}

Eigen::VectorXd metric_eigenvalues(const Mat3& G, int dimension) {
  // Fixed-size solvers: is_spd calls this for every distinct tensor a canvas stores.
  if (dimension == 3)
    return Eigen::SelfAdjointEigenSolver<Mat3>(G, Eigen::EigenvaluesOnly).eigenvalues();
  return Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d>(G.topLeftCorner<2, 2>(),
                                                        Eigen::EigenvaluesOnly)
      .eigenvalues();
}

bool is_storable_metric(const Mat3& stored, int dimension) {
  if (!is_spd(stored)) return false;
  // Without an eigen solve where the bounds settle it: the largest eigenvalue is at most the
  // trace, the smallest at least det / trace^(n-1), so their ratio at least det / trace^n.
  const int n = dimension == 3 ? 3 : 2;
  const double trace = stored.topLeftCorner(n, n).trace();
  const double det = n == 3 ? stored.determinant() : stored.topLeftCorner<2, 2>().determinant();
  const double least_bound = det / std::pow(trace, n - 1);
  if (trace <= kMostMetricEigenvalue && least_bound >= kLeastMetricEigenvalue &&
      least_bound / trace > kClearlyPositiveRatio)
    return true;
  const Eigen::VectorXd values = metric_eigenvalues(stored, dimension);
  return clearly_positive(values) && values.minCoeff() >= kLeastMetricEigenvalue &&
         values.maxCoeff() <= kMostMetricEigenvalue;
}

void require_storable_metric(const Mat3& stored, const Mat3& given, int dimension,
                             const std::string& where) {
  if (!stored.allFinite()) {
    require_spd(given, where);  // "not finite", with the values
    throw Error("metric " + where + " does not fit in float: " + describe(given));
  }
  if (!is_spd(stored))
    throw Error("metric " + where + " is not symmetric positive definite once rounded to float " +
                "(canvases keep tensors in float): " + describe(given));
  const std::string problem = metric_problem(stored, dimension);
  if (!problem.empty()) throw Error("metric " + where + " " + problem);
  const Eigen::VectorXd values = metric_eigenvalues(stored, dimension);
  const double least = values.minCoeff(), most = values.maxCoeff();
  if (least >= kLeastMetricEigenvalue && most <= kMostMetricEigenvalue) return;
  std::ostringstream out;
  out << "metric " << where << " has eigenvalues from " << least << " to " << most << ", outside ["
      << kLeastMetricEigenvalue << ", " << kMostMetricEigenvalue
      << "], the range canvases keep in float (rescale the metric or the domain's length unit)";
  throw Error(out.str());
}

Mat3 metric_sqrt(const Mat3& G) {
  return spectral_map(G, [](double x) { return std::sqrt(std::max(x, 0.0)); });
}

Mat3 metric_log(const Mat3& G) {
  return spectral_map(G, [](double x) { return std::log(x); });
}

Mat3 metric_exp(const Mat3& S) {
  return spectral_map(S, [](double x) { return std::exp(x); });
}

double metric_length(const Mat3& G, const Vec3& v) {
  return std::sqrt(std::max(0.0, v.dot(G * v)));
}

double distortion(const Mat3& G1, const Mat3& G2) {
  const Mat3 F1 = metric_sqrt(G1), F2 = metric_sqrt(G2);
  auto spectral_norm = [](const Mat3& A) {
    Eigen::JacobiSVD<Mat3> svd(A);
    return svd.singularValues()[0];
  };
  return std::max(spectral_norm(F1 * F2.inverse()), spectral_norm(F2 * F1.inverse()));
}

Mat3 interpolate_log_euclidean(const std::vector<Mat3>& metrics,
                               const std::vector<double>& weights) {
  std::vector<Mat3> logs;
  logs.reserve(metrics.size());
  for (const Mat3& G : metrics) logs.push_back(metric_log(G));
  return metric_exp(normalised_weighted_sum(logs, weights));
}

Mat3 interpolate_linear(const std::vector<Mat3>& metrics, const std::vector<double>& weights) {
  return normalised_weighted_sum(metrics, weights);
}

Mat3 metric_from_frame(int dimension, const Vec3& v1, double a, const Vec3& v2, double b,
                       double c) {
  Mat3 G = a * a * v1 * v1.transpose() + b * b * v2 * v2.transpose();
  if (dimension == 3) {
    const Vec3 v3 = v1.cross(v2);
    G += c * c * v3 * v3.transpose();
  } else {
    G.row(2).setZero();
    G.col(2).setZero();
    G(2, 2) = 1.0;
  }
  return G;
}

}  // namespace rvor
