// Tensor math of canvas/metric.cpp against closed-form truths: spectra chosen by hand, rotated
// by a fixed orthonormal frame so that nothing is axis-aligned by accident.
#include <cmath>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <Eigen/Cholesky>
#include <Eigen/Geometry>

#include "rvor/error.h"
#include "rvor/metric.h"

namespace rvor {
namespace {

Mat3 rotation() {
  return Eigen::AngleAxisd(0.7, Vec3(1, 2, 3).normalized()).toRotationMatrix();
}

// Q diag(values) Q^T: a metric whose eigenvalues are known exactly.
Mat3 with_spectrum(const Vec3& values) {
  const Mat3 Q = rotation();
  return Q * values.asDiagonal() * Q.transpose();
}

// Dynamic sizes so that one helper compares both matrices and vectors.
void expect_near_matrix(const Eigen::MatrixXd& actual, const Eigen::MatrixXd& expected,
                        double relative) {
  const double tolerance = relative * std::max(1.0, expected.cwiseAbs().maxCoeff());
  EXPECT_LE((actual - expected).cwiseAbs().maxCoeff(), tolerance) << "actual\n"
                                                                  << actual << "\nexpected\n"
                                                                  << expected;
}

std::string require_spd_message(const Mat3& G, const std::string& where) {
  try {
    require_spd(G, where);
  } catch (const Error& error) {
    return error.what();
  }
  return "";
}

TEST(TensorMath, SolOrderIsM11M12M22M13M23M33) {
  const Mat3 G = tensor_from_sol({1, 2, 3, 4, 5, 6});
  EXPECT_EQ(G(0, 0), 1);
  EXPECT_EQ(G(0, 1), 2);
  EXPECT_EQ(G(1, 0), 2);
  EXPECT_EQ(G(1, 1), 3);
  EXPECT_EQ(G(0, 2), 4);
  EXPECT_EQ(G(2, 0), 4);
  EXPECT_EQ(G(1, 2), 5);
  EXPECT_EQ(G(2, 1), 5);
  EXPECT_EQ(G(2, 2), 6);
  EXPECT_EQ(tensor_to_sol(G), (SolTensor{1, 2, 3, 4, 5, 6}));
}

TEST(TensorMath, SquareRootSquaresBackAndHasTheRootSpectrum) {
  const Mat3 G = with_spectrum(Vec3(0.01, 4, 2500));
  const Mat3 F = metric_sqrt(G);
  expect_near_matrix(F * F, G, 1e-12);
  expect_near_matrix(F, with_spectrum(Vec3(0.1, 2, 50)), 1e-12);
  expect_near_matrix(F, F.transpose(), 1e-15);
}

TEST(TensorMath, LogAndExpAreInverse) {
  const Mat3 G = with_spectrum(Vec3(1e-3, 1, 1e3));
  expect_near_matrix(metric_exp(metric_log(G)), G, 1e-12);
  // The smallest eigenvalue carries an absolute error ~ eps |G|, so its log a relative error
  // ~ eps |G| / 1e-3 = 1e-10.
  expect_near_matrix(metric_log(G), with_spectrum(Vec3(std::log(1e-3), 0, std::log(1e3))), 1e-9);
  Mat3 S;
  S << 0.5, -1, 0.25, -1, 2, 0.1, 0.25, 0.1, -3;  // symmetric, indefinite: any S has an exp
  expect_near_matrix(metric_log(metric_exp(S)), S, 1e-12);
}

TEST(TensorMath, LengthIsTheMetricNorm) {
  const Mat3 G = Vec3(4, 9, 16).asDiagonal();
  EXPECT_DOUBLE_EQ(metric_length(G, Vec3(1, 0, 0)), 2);
  EXPECT_DOUBLE_EQ(metric_length(G, Vec3(1, 1, 1)), std::sqrt(29.0));
  EXPECT_DOUBLE_EQ(metric_length(G, Vec3::Zero()), 0);
}

TEST(TensorMath, DistortionOfAMetricWithItselfIsOne) {
  const Mat3 G = with_spectrum(Vec3(0.5, 3, 70));
  EXPECT_NEAR(distortion(G, G), 1, 1e-12);
}

TEST(TensorMath, DistortionOfDiag411AgainstIdentityIsTwo) {
  const Mat3 G = Vec3(4, 1, 1).asDiagonal();
  EXPECT_NEAR(distortion(G, Mat3::Identity()), 2, 1e-12);
  EXPECT_NEAR(distortion(Mat3::Identity(), G), 2, 1e-12);
}

TEST(TensorMath, DistortionIsTheLargestRootRatioOfCommutingMetrics) {
  // Same eigenvectors: F1 F2^-1 has eigenvalues sqrt(a_i / b_i).
  const Mat3 G1 = with_spectrum(Vec3(1, 9, 4)), G2 = with_spectrum(Vec3(4, 1, 4));
  EXPECT_NEAR(distortion(G1, G2), 3, 1e-12);  // max(sqrt(9/1), sqrt(4/1))
}

TEST(TensorMath, LogEuclideanOfCommutingMetricsIsTheGeometricMeanOfEigenvalues) {
  const Vec3 a(1, 8, 100), b(4, 1, 0.01), c(2, 2, 2);
  const std::vector<double> weights = {1, 3, 4};  // normalised to 1/8, 3/8, 4/8
  const Mat3 G =
      interpolate_log_euclidean({with_spectrum(a), with_spectrum(b), with_spectrum(c)}, weights);
  Vec3 mean;
  for (int i = 0; i < 3; ++i)
    mean[i] = std::pow(a[i], 1.0 / 8) * std::pow(b[i], 3.0 / 8) * std::pow(c[i], 4.0 / 8);
  expect_near_matrix(G, with_spectrum(mean), 1e-12);
}

TEST(TensorMath, LogEuclideanOfOneMetricIsThatMetric) {
  const Mat3 G = with_spectrum(Vec3(0.2, 5, 30));
  expect_near_matrix(interpolate_log_euclidean({G}, {2.5}), G, 1e-12);
}

TEST(TensorMath, LinearInterpolationIsTheNormalisedWeightedSum) {
  const Mat3 G1 = with_spectrum(Vec3(1, 2, 3)), G2 = Vec3(10, 20, 30).asDiagonal();
  expect_near_matrix(interpolate_linear({G1, G2}, {1, 3}), 0.25 * G1 + 0.75 * G2, 1e-14);
  expect_near_matrix(interpolate_linear({G1, G2}, {0, 5}), G2, 1e-14);
}

TEST(TensorMath, InterpolationRejectsBadWeights) {
  const Mat3 I = Mat3::Identity();
  EXPECT_THROW(interpolate_linear({}, {}), Error);
  EXPECT_THROW(interpolate_linear({I, I}, {1}), Error);
  EXPECT_THROW(interpolate_log_euclidean({I, I}, {1, -1}), Error);
  EXPECT_THROW(interpolate_log_euclidean({I}, {0}), Error);
  EXPECT_THROW(interpolate_log_euclidean({I}, {std::nan("")}), Error);
}

TEST(TensorMath, MetricFromFrameHasTheGivenEigenpairs) {
  const Vec3 v1 = Vec3(1, 1, 0).normalized(), v2 = Vec3(-1, 1, 0).normalized();
  const Mat3 G3 = metric_from_frame(3, v1, 2, v2, 3, 5);
  expect_near_matrix(G3 * v1, 4 * v1, 1e-14);
  expect_near_matrix(G3 * v2, 9 * v2, 1e-14);
  expect_near_matrix(G3 * Vec3::UnitZ(), 25 * Vec3::UnitZ(), 1e-14);
  const Mat3 G2 = metric_from_frame(2, v1, 2, v2, 3, 5);
  expect_near_matrix(G2 * v1, 4 * v1, 1e-14);
  expect_near_matrix(G2 * v2, 9 * v2, 1e-14);
  EXPECT_EQ(G2(2, 2), 1);
  EXPECT_EQ(G2(0, 2), 0);
  EXPECT_EQ(G2(1, 2), 0);
}

TEST(TensorMath, IsSpdAcceptsSpdAndTwoDimensionalForm) {
  EXPECT_TRUE(is_spd(with_spectrum(Vec3(1e-6, 1, 1e6))));
  EXPECT_TRUE(is_spd(tensor_from_sol({4, 1, 3, 0, 0, 1})));
}

TEST(TensorMath, RequireSpdRejectsNanNamingWhere) {
  Mat3 G = Mat3::Identity();
  G(1, 1) = std::nan("");
  const std::string message = require_spd_message(G, "'swirl' at (0.1, 0.2, 0)");
  EXPECT_NE(message.find("'swirl' at (0.1, 0.2, 0)"), std::string::npos) << message;
  EXPECT_NE(message.find("not finite"), std::string::npos) << message;
}

TEST(TensorMath, RequireSpdRejectsInfinityNamingWhere) {
  Mat3 G = Mat3::Identity();
  G(0, 0) = INFINITY;
  EXPECT_NE(require_spd_message(G, "voxel 17").find("voxel 17"), std::string::npos);
}

TEST(TensorMath, RequireSpdRejectsNonSymmetricNamingWhere) {
  Mat3 G = Mat3::Identity();
  G(0, 1) = 0.5;  // G(1, 0) stays 0
  const std::string message = require_spd_message(G, "file.sol:12");
  EXPECT_NE(message.find("file.sol:12"), std::string::npos) << message;
  EXPECT_NE(message.find("not symmetric positive definite"), std::string::npos) << message;
}

TEST(TensorMath, RequireSpdRejectsIndefiniteNamingWhere) {
  const std::string message = require_spd_message(with_spectrum(Vec3(1, -0.5, 2)), "seed 3");
  EXPECT_NE(message.find("seed 3"), std::string::npos) << message;
  EXPECT_NE(message.find("not symmetric positive definite"), std::string::npos) << message;
}

TEST(TensorMath, RequireSpdRejectsSemidefiniteAndZeroNamingWhere) {
  EXPECT_NE(require_spd_message(Mat3::Zero(), "the zero tensor").find("the zero tensor"),
            std::string::npos);
  EXPECT_NE(require_spd_message(with_spectrum(Vec3(1, 0, 2)), "singular").find("singular"),
            std::string::npos);
}

// A positive definite tensor too close to singular for double rounding is refused as too
// anisotropic, not as "not positive definite".
TEST(TensorMath, NearlySingularPositiveTensorsAreCalledTooAnisotropic) {
  const std::string message = require_spd_message(with_spectrum(Vec3(1, 1, 1e15)), "here");
  EXPECT_NE(message.find("metric here is too anisotropic"), std::string::npos) << message;
  EXPECT_EQ(spd_problem(with_spectrum(Vec3(1, 1, 1e12))), "");
  EXPECT_NE(spd_problem(with_spectrum(Vec3(1, -1e-3, 1))).find("not symmetric positive definite"),
            std::string::npos);
}

// Entries near double's largest: symmetrised as (G + G^T) / 2, the sum overflowed to inf and the
// tensor was called "not symmetric positive definite".
TEST(TensorMath, HugeEntriesAreJudgedWithoutOverflow) {
  Mat3 G = Mat3::Identity();
  G(0, 0) = 1e308;
  const std::string problem = spd_problem(G);
  EXPECT_NE(problem.find("too anisotropic"), std::string::npos) << problem;
  EXPECT_EQ(spd_problem(1e307 * Mat3::Identity()), "");
}

// spd_problem cannot tell a 3D tensor with m13 = m23 = 0 from a 2D one; metric_problem judges
// the eigenvalues of the dimension's block, so a nearly zero m33 counts in 3D only.
TEST(TensorMath, MetricProblemJudgesTheCanvasDimension) {
  const Mat3 thin_z = tensor_from_sol({1, 0, 1, 0, 0, 1e-20});
  EXPECT_EQ(spd_problem(thin_z), "");
  EXPECT_EQ(metric_problem(thin_z, 2), "");
  EXPECT_NE(metric_problem(thin_z, 3).find("too anisotropic"), std::string::npos);
  EXPECT_FALSE(is_storable_metric(stored_metric(thin_z, 3), 3));
  EXPECT_TRUE(is_storable_metric(stored_metric(thin_z, 2), 2));
  const Mat3 thin_x = tensor_from_sol({1e-20, 0, 1, 0, 0, 1});
  EXPECT_NE(metric_problem(thin_x, 3).find("too anisotropic"), std::string::npos);
  EXPECT_NE(metric_problem(thin_x, 2).find("too anisotropic"), std::string::npos);
  // Strong but representable anisotropy stays accepted, with or without the eigen solve.
  EXPECT_EQ(metric_problem(tensor_from_sol({1, 0, 1, 0, 0, 1e-12}), 3), "");
  EXPECT_TRUE(is_storable_metric(stored_metric(tensor_from_sol({1, 0, 1, 0, 0, 1e-12}), 3), 3));
  EXPECT_TRUE(is_storable_metric(stored_metric(with_spectrum(Vec3(1e-2, 1, 1e2)), 3), 3));
}

TEST(TensorMath, IsSpdRejectsEveryRoundedSingularMatrix) {
  // Rotating diag(1, 0, 2) leaves a smallest eigenvalue of rounding noise, often positive.
  for (int i = 0; i < 500; ++i) {
    const Mat3 Q =
        Eigen::AngleAxisd(0.01 * i, Vec3(1, 2 + 0.01 * i, 3).normalized()).toRotationMatrix();
    EXPECT_FALSE(is_spd(Q * Vec3(1, 0, 2).asDiagonal() * Q.transpose())) << "rotation " << i;
  }
}

TEST(TensorMath, IsSpdAcceptsStrongAnisotropy) {
  EXPECT_TRUE(is_spd(with_spectrum(Vec3(1e-6, 1, 1e6))));  // ratio 1e12
  // A 2D metric whose xy block dwarfs the unused G(2,2) = 1 is still SPD.
  const Mat3 Q = rotation();
  Mat3 G = Mat3::Identity();
  G.topLeftCorner<2, 2>() = 1e20 * Eigen::Matrix2d(Vec3(1, 3, 0).head<2>().asDiagonal());
  G.topLeftCorner<2, 2>() =
      Q.topLeftCorner<2, 2>() * G.topLeftCorner<2, 2>() * Q.topLeftCorner<2, 2>().transpose();
  EXPECT_TRUE(is_spd(G));
}

// is_spd settles most tensors by bounds (trace and determinant) instead of an eigen solve; it must
// decide as the eigenvalues do on either side of the threshold, 64 epsilons of the largest:
// rotated spectra with ratios from 1e-1 to 1e-12 are accepted, 1e-15 and below refused.
TEST(TensorMath, IsSpdDecidesByTheSpectrumWithOrWithoutTheEigenSolve) {
  for (int i = 0; i < 50; ++i) {
    const Mat3 Q =
        Eigen::AngleAxisd(0.1 * i, Vec3(1, 2 + 0.1 * i, 3).normalized()).toRotationMatrix();
    for (int exponent = 1; exponent <= 12; ++exponent) {
      const double ratio = std::pow(10.0, -exponent);
      EXPECT_TRUE(is_spd(Q * Vec3(ratio, 1, 0.5).asDiagonal() * Q.transpose()))
          << "rotation " << i << ", ratio " << ratio;
      EXPECT_TRUE(is_spd(Q * Vec3(1, 1 / std::sqrt(ratio), 1 / ratio).asDiagonal() * Q.transpose()))
          << "rotation " << i << ", ratio " << ratio;
    }
    // At scales where the determinant alone is large (a bound without the trace's power would
    // accept these).
    for (const double ratio : {1e-15, 1e-17, 1e-20})
      for (const double scale : {1.0, 1e6, 1e12})
        EXPECT_FALSE(is_spd(scale * (Q * Vec3(ratio, 1, 0.5).asDiagonal() * Q.transpose())))
            << "rotation " << i << ", ratio " << ratio << ", scale " << scale;
  }
}

// The pivots decide as Eigen's Cholesky does on spectra clear of the boundary (next to it both
// are rounding-level tests, which is_spd's bound and eigen solve then settle): positive definite
// ones of ratio down to 1e-12 at any scale accepted, ones with a negative eigenvalue refused, and
// non-finite or zero matrices refused.
TEST(TensorMath, PositivePivotsDecideClearSpectraAsCholesky) {
  for (int i = 0; i < 200; ++i) {
    const Mat3 Q = Eigen::AngleAxisd(0.37 * i, Vec3(1, 2 + 0.05 * i, 3 - 0.02 * i).normalized())
                       .toRotationMatrix();
    for (const double scale : {1e-8, 1.0, 1e8})
      for (const double smallest : {1.0, 1e-3, 1e-12, -1e-12, -1e-3, -1.0}) {
        const Mat3 S = scale * (Q * Vec3(smallest, 1, 0.3).asDiagonal() * Q.transpose());
        EXPECT_EQ(has_positive_pivots(S), smallest > 0)
            << "rotation " << i << ", smallest " << smallest << ", scale " << scale;
        EXPECT_EQ(Eigen::LLT<Mat3>(S).info() == Eigen::Success, smallest > 0);
      }
  }
  for (int entry = 0; entry < 9; ++entry) {
    Mat3 S = Mat3::Identity();
    S(entry / 3, entry % 3) = S(entry % 3, entry / 3) = std::nan("");  // S stays symmetric
    EXPECT_FALSE(has_positive_pivots(S)) << "NaN at " << entry;
  }
  EXPECT_FALSE(has_positive_pivots(Mat3::Zero()));
}

TEST(TensorMath, RequireSpdAcceptsSpd) {
  EXPECT_NO_THROW(require_spd(with_spectrum(Vec3(0.1, 1, 10)), "fine"));
}

}  // namespace
}  // namespace rvor
