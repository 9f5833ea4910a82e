// Selling's decomposition: exact reconstruction, non-negative weights, small integer offsets.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <random>

#include <Eigen/QR>

#include "rvor/error.h"
#include "rvor/selling.h"

namespace rvor {
namespace {

// Random SPD matrix with eigenvalues 1 and anisotropy^2 (and a random one in between in 3D),
// i.e. anisotropy = ratio of the extreme eigenvalues of D^{1/2}, in a random orientation.
Mat3 random_spd(std::mt19937_64& random, int dimension, double anisotropy) {
  std::normal_distribution<double> normal;
  std::uniform_real_distribution<double> uniform(0, 1);
  Mat3 A;
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) A(r, c) = normal(random);
  if (dimension == 2) {
    A.row(2).setZero();
    A.col(2).setZero();
    A(2, 2) = 1;
  }
  const Mat3 Q = Eigen::HouseholderQR<Mat3>(A).householderQ();
  const double middle = std::pow(anisotropy, 2 * uniform(random));
  const Vec3 eigenvalues(1, anisotropy * anisotropy, dimension == 3 ? middle : 1);
  Mat3 D = Q * eigenvalues.asDiagonal() * Q.transpose();
  if (dimension == 2) {
    D.row(2).setZero();
    D.col(2).setZero();
    D(2, 2) = 1;
  }
  // A random overall scale: the decomposition must not depend on units.
  return std::pow(10.0, 4 * uniform(random) - 2) * D;
}

Mat3 reconstruct(const SellingStencil& stencil) {
  Mat3 sum = Mat3::Zero();
  for (int t = 0; t < stencil.size; ++t) {
    const Vec3 e(stencil.offset[t][0], stencil.offset[t][1], stencil.offset[t][2]);
    sum += stencil.weight[t] * e * e.transpose();
  }
  return sum;
}

struct SellingStudy {
  double worst_reconstruction = 0;
  int largest_component = 0;
};

SellingStudy check_random_matrices(int dimension, double max_anisotropy, int count) {
  std::mt19937_64 random(1234 + dimension);
  std::uniform_real_distribution<double> log_anisotropy(0, std::log(max_anisotropy));
  SellingStudy study;
  for (int n = 0; n < count; ++n) {
    const double anisotropy = n % 4 == 0 ? max_anisotropy : std::exp(log_anisotropy(random));
    const Mat3 D = random_spd(random, dimension, anisotropy);
    const SellingStencil stencil = selling_decomposition(D, dimension);
    EXPECT_GE(stencil.size, dimension);
    EXPECT_LE(stencil.size, dimension == 3 ? 6 : 3);
    for (int t = 0; t < stencil.size; ++t) {
      EXPECT_GT(stencil.weight[t], 0);
      if (dimension == 2) {
        EXPECT_EQ(stencil.offset[t][2], 0);
      }
      for (int c : stencil.offset[t])
        study.largest_component = std::max(study.largest_component, std::abs(c));
    }
    Mat3 expected = D;
    if (dimension == 2) expected(2, 2) = 0;
    const double error = (reconstruct(stencil) - expected).norm() / expected.norm();
    study.worst_reconstruction = std::max(study.worst_reconstruction, error);
  }
  return study;
}

TEST(Selling, IdentityGivesTheAxes) {
  for (int dimension : {2, 3}) {
    const SellingStencil stencil = selling_decomposition(Mat3::Identity(), dimension);
    ASSERT_EQ(stencil.size, dimension);
    for (int t = 0; t < stencil.size; ++t) {
      EXPECT_DOUBLE_EQ(stencil.weight[t], 1.0);
      EXPECT_EQ(std::abs(stencil.offset[t][0]) + std::abs(stencil.offset[t][1]) +
                    std::abs(stencil.offset[t][2]),
                1);
    }
  }
}

TEST(Selling, OffsetsAreCanonical) {
  std::mt19937_64 random(7);
  for (int n = 0; n < 200; ++n)
    for (int dimension : {2, 3}) {
      const SellingStencil stencil =
          selling_decomposition(random_spd(random, dimension, 30), dimension);
      for (int t = 0; t < stencil.size; ++t) {
        const auto& e = stencil.offset[t];
        const int first = e[0] != 0 ? e[0] : (e[1] != 0 ? e[1] : e[2]);
        EXPECT_GT(first, 0)
            << "offset must be the representative of +-e with a positive first entry";
      }
    }
}

TEST(Selling, ReconstructsRandomSpdMatrices2D) {
  const SellingStudy study = check_random_matrices(2, 100, 20000);
  std::printf(
      "[ measured ] 2D anisotropy <= 100: worst relative reconstruction %.2e, max |offset "
      "component| %d\n",
      study.worst_reconstruction, study.largest_component);
  EXPECT_LE(study.worst_reconstruction, 1e-12);
  EXPECT_LE(study.largest_component, 127);
}

TEST(Selling, ReconstructsRandomSpdMatrices3D) {
  const SellingStudy study = check_random_matrices(3, 100, 20000);
  std::printf(
      "[ measured ] 3D anisotropy <= 100: worst relative reconstruction %.2e, max |offset "
      "component| %d\n",
      study.worst_reconstruction, study.largest_component);
  EXPECT_LE(study.worst_reconstruction, 1e-12);
  EXPECT_LE(study.largest_component, 127);
}

TEST(Selling, OffsetBoundsByAnisotropy) {
  for (double anisotropy : {2.0, 5.0, 10.0, 30.0, 100.0, 300.0}) {
    const SellingStudy s2 = check_random_matrices(2, anisotropy, 4000);
    const SellingStudy s3 = check_random_matrices(3, anisotropy, 4000);
    std::printf(
        "[ measured ] anisotropy <= %5.0f: max |offset component| 2D %3d, 3D %3d; worst "
        "reconstruction 2D %.1e, 3D %.1e\n",
        anisotropy, s2.largest_component, s3.largest_component, s2.worst_reconstruction,
        s3.worst_reconstruction);
    if (anisotropy <= 100) {
      EXPECT_LE(s3.worst_reconstruction, 1e-12);
      EXPECT_LE(s2.worst_reconstruction, 1e-12);
    }
  }
}

TEST(Selling, RejectsNonSpd) {
  Mat3 indefinite = Mat3::Identity();
  indefinite(1, 1) = -1;
  EXPECT_THROW(selling_decomposition(indefinite, 3), Error);
  EXPECT_THROW(selling_decomposition(indefinite, 2), Error);
  Mat3 singular = Mat3::Zero();
  singular(0, 0) = 1;
  EXPECT_THROW(selling_decomposition(singular, 3), Error);
  Mat3 nan = Mat3::Identity();
  nan(0, 1) = nan(1, 0) = std::nan("");
  EXPECT_THROW(selling_decomposition(nan, 2), Error);
  EXPECT_THROW(selling_decomposition(Mat3::Identity(), 4), Error);
}

}  // namespace
}  // namespace rvor
