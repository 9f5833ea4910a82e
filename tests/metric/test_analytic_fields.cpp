// The analytic fields: finite and SPD everywhere on a fine grid of their domain and at the points
// where their formulas are singular, scale behaviour, and values at points computed by hand
// from the formulas of DESIGN.md.
#include <cmath>
#include <memory>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <Eigen/Geometry>

#include "rvor/metric_field.h"

namespace rvor {
namespace {

struct FieldCase {
  std::string spec;
  int dimension;
};

std::string case_name(const testing::TestParamInfo<FieldCase>& info) {
  return info.param.spec + "_" + std::to_string(info.param.dimension) + "d";
}

const std::vector<FieldCase> kAllFields = {
    {"euclidean", 2},
    {"euclidean", 3},
    {"swirl", 2},
    {"starred", 2},
    {"hyperbolic_shock", 2},
    {"hyperbolic_shock", 3},
    {"unidimensional_shock", 2},
    {"radial_shock_3d", 3},
};

// Points where a formula divides by zero or loses its eigenvector direction, and tiny
// neighbours of them where naive normalisation under- or overflows.
const std::vector<Vec3> kSingularPoints = {
    Vec3(0, 0, 0),       Vec3(1e-300, 0, 0),
    Vec3(0, 1e-300, 0),  Vec3(1e-170, -1e-170, 0),
    Vec3(1e-9, 2e-9, 0), Vec3(-1e-160, 0, 1e-160),
    Vec3(0, 0, 1),       Vec3(0.6, 0.3, 0),
    Vec3(1, 0, 0),       Vec3(0, 1, 0),
    Vec3(7, 0, 0),       Vec3(2, 3, 6),
};

std::unique_ptr<MetricField> make(const std::string& spec, int dimension) {
  return make_analytic_metric(spec, dimension);
}

// Finite, SPD, and in 2D of the stored 2D form (zero z row and column, G(2,2) = 1).
testing::AssertionResult is_valid_metric(const Mat3& G, int dimension) {
  if (!is_spd(G)) return testing::AssertionFailure() << "not finite SPD:\n" << G;
  if (dimension == 2 &&
      (G(2, 2) != 1 || G(0, 2) != 0 || G(1, 2) != 0 || G(2, 0) != 0 || G(2, 1) != 0))
    return testing::AssertionFailure() << "not of the 2D form:\n" << G;
  return testing::AssertionSuccess();
}

Box domain_or_unit_cube(const MetricField& field) {
  if (field.natural_domain()) return *field.natural_domain();
  const double z = field.dimension() == 2 ? 0 : 1;
  return Box{Vec3(-1, -1, -z), Vec3(1, 1, z)};
}

// Calls visit(p) at every node of an n^d grid over the box (both ends included).
template <typename Visit>
void for_each_grid_point(const Box& box, int dimension, int n, Visit visit) {
  const int nz = dimension == 2 ? 1 : n;
  for (int k = 0; k < nz; ++k)
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) {
        const Vec3 t(double(i) / (n - 1), double(j) / (n - 1), nz == 1 ? 0 : double(k) / (n - 1));
        visit(box.lo + t.cwiseProduct(box.hi - box.lo));
      }
}

class EveryField : public testing::TestWithParam<FieldCase> {};

TEST_P(EveryField, IsFiniteAndSpdOnAFineGridOfItsDomain) {
  const auto field = make(GetParam().spec, GetParam().dimension);
  const int d = GetParam().dimension;
  int failures = 0;
  for_each_grid_point(domain_or_unit_cube(*field), d, d == 2 ? 101 : 41, [&](const Vec3& p) {
    const testing::AssertionResult valid = is_valid_metric(field->at(p), d);
    if (!valid && ++failures <= 5)
      ADD_FAILURE() << "at " << p.transpose() << ": " << valid.message();
  });
  EXPECT_EQ(failures, 0);
}

TEST_P(EveryField, IsFiniteAndSpdAtSingularPointsAndFarAway) {
  const auto field = make(GetParam().spec, GetParam().dimension);
  std::vector<Vec3> points = kSingularPoints;
  points.push_back(Vec3(-20, 35, 3));  // outside every natural domain: still a metric
  points.push_back(Vec3(1e3, -1e3, 1e3));
  for (const Vec3& p : points)
    EXPECT_TRUE(is_valid_metric(field->at(p), GetParam().dimension)) << "at " << p.transpose();
}

TEST_P(EveryField, ScaleMultipliesTheMetricBySquaredScale) {
  const auto plain = make(GetParam().spec, GetParam().dimension);
  const auto scaled = make(GetParam().spec + ":scale=2.5", GetParam().dimension);
  for (const Vec3& p : {Vec3(0.3, -0.4, 0.5), Vec3(2, 3, 6), Vec3(0, 0, 0), Vec3(-0.9, 0.7, 0)}) {
    Mat3 expected = 6.25 * plain->at(p);
    if (GetParam().dimension == 2) expected(2, 2) = 1;  // the unused z entry is not scaled
    const Mat3 actual = scaled->at(p);
    EXPECT_LE((actual - expected).cwiseAbs().maxCoeff(), 1e-12 * expected.cwiseAbs().maxCoeff())
        << "at " << p.transpose();
  }
}

TEST_P(EveryField, ReportsItsDimensionAndDescribesItself) {
  const auto field = make(GetParam().spec + ":scale=3", GetParam().dimension);
  EXPECT_EQ(field->dimension(), GetParam().dimension);
  EXPECT_NE(field->description().find(GetParam().spec), std::string::npos);
  EXPECT_NE(field->description().find("scale 3"), std::string::npos) << field->description();
}

INSTANTIATE_TEST_SUITE_P(AnalyticFields, EveryField, testing::ValuesIn(kAllFields), case_name);

void expect_eigenpair(const Mat3& G, const Vec3& v, double eigenvalue, double relative = 1e-9) {
  const Vec3 Gv = G * v, expected = eigenvalue * v;
  EXPECT_LE((Gv - expected).norm(), relative * expected.norm())
      << "G v = " << Gv.transpose() << ", expected " << expected.transpose() << "\nG =\n"
      << G;
}

void expect_box(const std::optional<Box>& box, const Vec3& lo, const Vec3& hi) {
  ASSERT_TRUE(box.has_value());
  EXPECT_EQ(box->lo, lo);
  EXPECT_EQ(box->hi, hi);
}

TEST(AnalyticFields, NaturalDomains) {
  const Vec3 lo2(-1, -1, 0), hi2(1, 1, 0);
  for (const char* name : {"swirl", "starred", "hyperbolic_shock", "unidimensional_shock"})
    expect_box(make(name, 2)->natural_domain(), lo2, hi2);
  expect_box(make("hyperbolic_shock", 3)->natural_domain(), Vec3(-1, -1, -1), Vec3(1, 1, 1));
  expect_box(make("radial_shock_3d", 3)->natural_domain(), Vec3(1, 1, 1), Vec3(11, 11, 11));
  EXPECT_FALSE(make("euclidean", 3)->natural_domain());
  EXPECT_FALSE(make("uniform:1,0,1", 2)->natural_domain());
}

TEST(AnalyticFields, EuclideanIsTheIdentityTimesSquaredScale) {
  EXPECT_EQ(make("euclidean", 3)->at(Vec3(5, -2, 1)), Mat3::Identity());
  EXPECT_EQ(make("euclidean:scale=3", 3)->at(Vec3(5, -2, 1)), Mat3(9 * Mat3::Identity()));
  EXPECT_EQ(make("euclidean:scale=3", 2)->at(Vec3(5, -2, 0)), Mat3(Vec3(9, 9, 1).asDiagonal()));
}

TEST(AnalyticFields, Uniform2dIsTheGivenTensorEverywhere) {
  Mat3 expected;
  expected << 4, 1, 0, 1, 3, 0, 0, 0, 1;
  const auto field = make("uniform:4,1,3", 2);
  EXPECT_EQ(field->at(Vec3(0, 0, 0)), expected);
  EXPECT_EQ(field->at(Vec3(-7, 100, 0)), expected);
}

TEST(AnalyticFields, Uniform3dReadsComponentsInSolOrder) {
  Mat3 expected;  // m11 m12 m22 m13 m23 m33 = 1 0.1 2 0.2 0.3 3
  expected << 1, 0.1, 0.2, 0.1, 2, 0.3, 0.2, 0.3, 3;
  EXPECT_EQ(make("uniform:1,0.1,2,0.2,0.3,3", 3)->at(Vec3(1, 2, 3)), expected);
  EXPECT_EQ(make("uniform:1,0.1,2,0.2,0.3,3,scale=2", 3)->at(Vec3(1, 2, 3)), Mat3(4 * expected));
}

TEST(AnalyticFields, UnidimensionalShockIsDiagonalWithTheShockEigenvalues) {
  const auto field = make("unidimensional_shock", 2);
  // On both shock lines h = 1 / 0.0025 = 400.
  EXPECT_NEAR(field->at(Vec3(0.6, 0.3, 0))(0, 0), 160000, 1e-6);
  EXPECT_NEAR(field->at(Vec3(0.6, 0.3, 0))(1, 1), 160000, 1e-6);
  // |x - 0.6| = 1: h1 = 1 / (0.0025 + 0.2 (1 - e^-1)) = 7.7565009858;
  // |y - 0.3| = 0.5: h2 = 1 / (0.0025 + 0.2 (1 - e^-0.5)) = 12.3162010128.
  const Mat3 G = field->at(Vec3(-0.4, 0.8, 0));
  EXPECT_NEAR(G(0, 0), 7.7565009858 * 7.7565009858, 1e-6);
  EXPECT_NEAR(G(1, 1), 12.3162010128 * 12.3162010128, 1e-6);
  EXPECT_EQ(G(0, 1), 0);
  EXPECT_EQ(G(2, 2), 1);
}

TEST(AnalyticFields, RadialShockOnTheSphereOfRadiusSeven) {
  const auto field = make("radial_shock_3d", 3);
  const Vec3 p(2, 3, 6);  // |p| = 7: h1 = 0.025, radial eigenvalue 1 / 0.025^2 = 1600
  const Mat3 G = field->at(p);
  expect_eigenpair(G, p.normalized(), 1600);
  expect_eigenpair(G, Vec3(3, -2, 0).normalized(), 1);  // tangent to the sphere
  expect_eigenpair(G, p.cross(Vec3(3, -2, 0)).normalized(), 1);
}

TEST(AnalyticFields, RadialShockAwayFromTheSphere) {
  const Vec3 p(10, 7, 0);  // r^2 = 149: h1 = 0.025 + 1 - e^-1 = 0.6571205588
  const Mat3 G = make("radial_shock_3d", 3)->at(p);
  expect_eigenpair(G, p.normalized(), 1 / (0.6571205588 * 0.6571205588), 1e-9);
  expect_eigenpair(G, Vec3::UnitZ(), 1);
}

TEST(AnalyticFields, RadialShockIsIsotropicWithTheRadialEigenvalueAtTheOrigin) {
  const double h1 = 0.025 + 1 - std::exp(-0.49);
  const Mat3 expected = Mat3::Identity() / (h1 * h1);
  EXPECT_LE((make("radial_shock_3d", 3)->at(Vec3::Zero()) - expected).norm(), 1e-12);
}

TEST(AnalyticFields, HyperbolicShockAtTheOriginFollowsV) {
  // T = 1/0.6, v = (2T, -5T) is along (2, -5); |v|^2 = 29 / 0.36.
  const Vec3 along = Vec3(2, -5, 0).normalized(), across = Vec3(5, 2, 0).normalized();
  const Mat3 G2 = make("hyperbolic_shock", 2)->at(Vec3::Zero());  // h = 0.1
  expect_eigenpair(G2, along, 29 / 0.36 / 0.01);
  expect_eigenpair(G2, across, 100);
  const Mat3 G3 = make("hyperbolic_shock", 3)->at(Vec3(0, 0, 0.7));  // h = 0.05, z ignored
  expect_eigenpair(G3, along, 29 / 0.36 / 0.0025);
  expect_eigenpair(G3, across, 400);
  expect_eigenpair(G3, Vec3::UnitZ(), 400);
}

TEST(AnalyticFields, HyperbolicShockAwayFromTheOrigin) {
  // At (0.5, 0.2): T = (1 - tanh^2((1 - sin 1) / 0.6)) / 0.6 = 1.5555255561,
  // v = (3.9010511121, -4.0022702239), |v|^2 = 31.2363667243.
  const Vec3 v(3.9010511121, -4.0022702239, 0);
  const Mat3 G = make("hyperbolic_shock", 2)->at(Vec3(0.5, 0.2, 0));
  expect_eigenpair(G, v.normalized(), 31.2363667243 / 0.01, 1e-8);
  expect_eigenpair(G, Vec3(-v.y(), v.x(), 0).normalized(), 100, 1e-8);
}

TEST(AnalyticFields, SwirlIsIsotropicAtTheOriginAndContinuousThere) {
  const auto field = make("swirl", 2);
  Mat3 expected = 1e4 * Mat3::Identity();
  expected(2, 2) = 1;
  EXPECT_EQ(field->at(Vec3::Zero()), expected);
  // a = |50 (1 - (f - 1)^2)| ~ 50 r^(1/3): about 5e-4 at r = 1e-15.
  EXPECT_LE((field->at(Vec3(1e-15, 0, 0)) - expected).norm(), 1e-3 * 1e4);
}

TEST(AnalyticFields, SwirlOnTheUnitCircleIsTangentialToTheFlow) {
  // At (1, 0): r = 1, f = 1, a = 50; (1 - r^2)^2 = 0 so v1 = J (cos 3, sin 3) = (-sin 3, cos 3).
  const Mat3 G = make("swirl", 2)->at(Vec3(1, 0, 0));
  expect_eigenpair(G, Vec3(-std::sin(3.0), std::cos(3.0), 0), 1e4 / 51);
  expect_eigenpair(G, Vec3(std::cos(3.0), std::sin(3.0), 0), 1e4);
}

TEST(AnalyticFields, SwirlInsideTheDisk) {
  // At (0.5, 0): f = (0.5^(1/3) + 0.5) / 2, a = 43.7642631626,
  // v1 = (-0.3489953937, -0.4553062460).
  const Vec3 v1 = Vec3(-0.3489953937, -0.4553062460, 0).normalized();
  const Mat3 G = make("swirl", 2)->at(Vec3(0.5, 0, 0));
  expect_eigenpair(G, v1, 1e4 / 44.7642631626, 1e-8);
  expect_eigenpair(G, Vec3(-v1.y(), v1.x(), 0), 1e4, 1e-8);
}

TEST(AnalyticFields, StarredIsIsotropicAtTheOrigin) {
  const auto field = make("starred", 2);
  const Mat3 expected = Vec3(400, 400, 1).asDiagonal();  // 1 / 0.05^2
  EXPECT_LE((field->at(Vec3::Zero()) - expected).norm(), 1e-12 * 400);
  EXPECT_LE((field->at(Vec3(1e-6, 2e-6, 0)) - expected).norm(), 1e-6 * 400);
}

TEST(AnalyticFields, StarredFollowsG) {
  // At (1, 1): g = (2.1, -2.1), |g| = 2.9698484810, l1 = 1 / (1 + |g|) = 0.2518987827.
  const Mat3 G = make("starred", 2)->at(Vec3(1, 1, 0));
  expect_eigenpair(G, Vec3(1, -1, 0).normalized(), 25.3811986972, 1e-9);
  expect_eigenpair(G, Vec3(1, 1, 0).normalized(), 400);
}

TEST(AnalyticFields, StarredClampsL1AtOneTenth) {
  // At (3, 0): g = (29.7, -0.9), 1 / (1 + |g|) < 0.1, so l1 = 0.1 and (l1 / h)^2 = 4.
  const Mat3 G = make("starred", 2)->at(Vec3(3, 0, 0));
  expect_eigenpair(G, Vec3(29.7, -0.9, 0).normalized(), 4);
  expect_eigenpair(G, Vec3(0.9, 29.7, 0).normalized(), 400);
}

TEST(AnalyticFields, NamesListEveryField) {
  const std::vector<std::string> expected = {
      "euclidean",      "uniform", "swirl", "starred", "hyperbolic_shock", "unidimensional_shock",
      "radial_shock_3d"};
  EXPECT_EQ(analytic_metric_names(), expected);
}

}  // namespace
}  // namespace rvor
