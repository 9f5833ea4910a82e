// The metric field interpolated (Log-Euclidean) on a Medit mesh: accuracy and order of
// convergence against a smooth anisotropic field, exactness for commuting tensors, points
// outside the mesh, thread safety, and the errors of load_mesh_metric().
#include <cmath>
#include <ctime>
#include <functional>
#include <random>
#include <thread>

#include <gtest/gtest.h>
#include <Eigen/Geometry>

#include "medit_test_meshes.h"
#include "rvor/medit.h"
#include "rvor/metric_field.h"
#include "support/temp_dir.h"

namespace rvor::test {
namespace {

using Field = std::function<Mat3(const Vec3&)>;

// A smooth field whose eigenvectors rotate through space and whose anisotropy varies (up to
// about 20), so that Log-Euclidean interpolation is not exact.
Mat3 rotating_anisotropic_field(const Vec3& p) {
  const Eigen::AngleAxisd turn_z(1.3 * p.x() + 0.6 * p.y(), Vec3::UnitZ());
  const Eigen::AngleAxisd turn_x(0.9 * p.z() - 0.4 * p.x(), Vec3::UnitX());
  const Mat3 R = (turn_z * turn_x).toRotationMatrix();
  const Vec3 eigenvalues(std::exp(1.5 + std::sin(2 * p.y())), 1.0 + p.x() * p.x(),
                         std::exp(-1.0 + p.z()));
  return R * eigenvalues.asDiagonal() * R.transpose();
}

// Tensors sharing eigenvectors whose logarithm is affine in p: Log-Euclidean interpolation
// reproduces it exactly.
Mat3 commuting_field(const Vec3& p) {
  const Mat3 R = Eigen::AngleAxisd(0.7, Vec3(1, 2, 3).normalized()).toRotationMatrix();
  const Vec3 logs(2 * p.x() - p.y() + 0.5, 3 * p.z() - 1, -p.x() + 2 * p.y() + p.z());
  return R * logs.array().exp().matrix().asDiagonal() * R.transpose();
}

Mat3 commuting_field_2d(const Vec3& p) {
  const Mat3 R = Eigen::AngleAxisd(0.4, Vec3::UnitZ()).toRotationMatrix();
  const Vec3 logs(2 * p.x() - p.y() + 0.5, 3 * p.y() - 1, 0);
  return R * logs.array().exp().matrix().asDiagonal() * R.transpose();
}

struct MeshFiles {
  std::string mesh, sol;
};

MeshFiles write_sampled(const TempDir& dir, const std::string& name, const MeditMesh& mesh,
                        const Field& field) {
  std::vector<Mat3> tensors;
  for (const Vec3& v : mesh.vertices) tensors.push_back(field(v));
  const MeshFiles files{dir.file(name + ".mesh"), dir.file(name + ".sol")};
  write_medit_mesh(files.mesh, mesh);
  write_medit_sol_tensors(files.sol, mesh.dimension, tensors);
  return files;
}

std::vector<Vec3> random_points(int count, unsigned seed, double lo = 0.0, double hi = 1.0) {
  std::mt19937 random(seed);
  std::uniform_real_distribution<double> uniform(lo, hi);
  std::vector<Vec3> points;
  for (int i = 0; i < count; ++i)
    points.emplace_back(uniform(random), uniform(random), uniform(random));
  return points;
}

double relative_error(const Mat3& actual, const Mat3& expected) {
  return (actual - expected).norm() / expected.norm();
}

struct ErrorStats {
  double max = 0, mean = 0;
};

ErrorStats interpolation_error(const MetricField& field, const Field& exact,
                               const std::vector<Vec3>& points) {
  ErrorStats stats;
  for (const Vec3& p : points) {
    const double e = relative_error(field.at(p), exact(p));
    stats.max = std::max(stats.max, e);
    stats.mean += e / points.size();
  }
  return stats;
}

TEST(MeshMetricField, ReproducesASmoothAnisotropicFieldAtSecondOrder) {
  TempDir dir;
  const std::vector<Vec3> points = random_points(3000, 7);
  std::vector<ErrorStats> errors;
  for (int n : {4, 8, 16}) {
    const auto files = write_sampled(dir, "cube" + std::to_string(n), unit_cube_tetrahedra(n),
                                     rotating_anisotropic_field);
    const auto field = load_mesh_metric(files.mesh, files.sol);
    errors.push_back(interpolation_error(*field, rotating_anisotropic_field, points));
    std::cout << "n=" << n << " max relative error " << errors.back().max << " mean "
              << errors.back().mean << "\n";
  }
  EXPECT_LT(errors[2].max, 0.02);
  for (std::size_t i = 1; i < errors.size(); ++i) {
    const double mean_ratio = errors[i - 1].mean / errors[i].mean;
    const double max_ratio = errors[i - 1].max / errors[i].max;
    EXPECT_GT(mean_ratio, 3.5) << "refinement " << i;
    EXPECT_LT(mean_ratio, 4.5) << "refinement " << i;
    EXPECT_GT(max_ratio, 3.0) << "refinement " << i;
    EXPECT_LT(max_ratio, 5.5) << "refinement " << i;
  }
}

TEST(MeshMetricField, ExactForCommutingTensors) {
  TempDir dir;
  const auto files = write_sampled(dir, "cube", unit_cube_tetrahedra(3), commuting_field);
  const auto field = load_mesh_metric(files.mesh, files.sol);
  for (const Vec3& p : random_points(500, 3))
    EXPECT_LT(relative_error(field->at(p), commuting_field(p)), 1e-12) << p.transpose();
}

TEST(MeshMetricField, CentroidGetsTheGeometricMeanOfCommutingVertexTensors) {
  TempDir dir;
  MeditMesh mesh = unit_cube_tetrahedra(1);
  mesh.tetrahedra.resize(1);
  mesh.tetrahedron_refs.resize(1);
  const Mat3 R = Eigen::AngleAxisd(1.1, Vec3(0.3, -1, 2).normalized()).toRotationMatrix();
  std::vector<Mat3> tensors(mesh.vertices.size(), Mat3::Identity());
  Vec3 product = Vec3::Ones();
  for (int k = 0; k < 4; ++k) {
    const Vec3 eigenvalues(1.0 + k, 10.0 / (1 + k * k), 0.5 + 3 * k);
    tensors[mesh.tetrahedra[0][k]] = R * eigenvalues.asDiagonal() * R.transpose();
    product = product.cwiseProduct(eigenvalues);
  }
  write_medit_mesh(dir.file("t.mesh"), mesh);
  write_medit_sol_tensors(dir.file("t.sol"), 3, tensors);
  const auto field = load_mesh_metric(dir.file("t.mesh"), dir.file("t.sol"));
  Vec3 centroid = Vec3::Zero();
  for (int v : mesh.tetrahedra[0]) centroid += mesh.vertices[v] / 4;
  const Vec3 geometric_mean = product.array().pow(0.25);
  const Mat3 expected = R * geometric_mean.asDiagonal() * R.transpose();
  EXPECT_LT(relative_error(field->at(centroid), expected), 1e-12);
}

// A thin slab: the bucket grid must not explode along the thin axis, and stay exact.
TEST(MeshMetricField, ThinSlabMesh) {
  TempDir dir;
  MeditMesh slab = unit_cube_tetrahedra(4);
  for (Vec3& v : slab.vertices) v.z() *= 1e-3;
  const auto files = write_sampled(dir, "slab", slab, commuting_field);
  const auto field = load_mesh_metric(files.mesh, files.sol);
  for (Vec3 p : random_points(300, 9)) {
    p.z() *= 1e-3;
    EXPECT_LT(relative_error(field->at(p), commuting_field(p)), 1e-12) << p.transpose();
  }
}

// Long thin slanted elements (a square grid sheared 40 to 1): each crosses many buckets of the
// lookup grid diagonally, and the buckets it meets are found by splitting its bounding box.
TEST(MeshMetricField, LongSlantedElements) {
  TempDir dir;
  MeditMesh sheared = unit_square_triangles(12);
  for (Vec3& v : sheared.vertices) v.x() += 40 * v.y();
  // The field sheared alike: its logarithm stays affine, so interpolation is exact.
  const auto unsheared = [](const Vec3& p) {
    return commuting_field_2d(Vec3(p.x() - 40 * p.y(), p.y(), 0));
  };
  const auto files = write_sampled(dir, "sheared", sheared, unsheared);
  const auto field = load_mesh_metric(files.mesh, files.sol);
  for (Vec3 p : random_points(2000, 23)) {
    p = Vec3(p.x() + 40 * p.y(), p.y(), 0);  // inside the sheared square
    EXPECT_LT(relative_error(field->at(p), unsheared(p)), 1e-12) << p.transpose();
  }
}

TEST(MeshMetricField, TwoDimensionalMeshIgnoresZ) {
  TempDir dir;
  const auto files = write_sampled(dir, "square", unit_square_triangles(5), commuting_field_2d);
  const auto field = load_mesh_metric(files.mesh, files.sol);
  EXPECT_EQ(field->dimension(), 2);
  for (Vec3 p : random_points(300, 5)) {
    const Mat3 expected = commuting_field_2d(Vec3(p.x(), p.y(), 0));
    p.z() = 17.0 * p.z() - 3.0;
    const Mat3 G = field->at(p);
    EXPECT_LT(relative_error(G, expected), 1e-12) << p.transpose();
    EXPECT_EQ(G(2, 2), 1.0);
    EXPECT_EQ(G(0, 2), 0.0);
  }
}

TEST(MeshMetricField, PointsOutsideTakeTheMetricOfTheClosestPointOfTheMesh) {
  TempDir dir;
  const auto files = write_sampled(dir, "cube", unit_cube_tetrahedra(4), commuting_field);
  const auto field = load_mesh_metric(files.mesh, files.sol);
  const std::vector<std::pair<Vec3, Vec3>> outside_and_closest = {
      {Vec3(1.5, 0.3, 0.6), Vec3(1, 0.3, 0.6)},  {Vec3(-0.2, 0.5, -0.1), Vec3(0, 0.5, 0)},
      {Vec3(10, 10, 10), Vec3(1, 1, 1)},         {Vec3(0.25, 1.01, 0.75), Vec3(0.25, 1, 0.75)},
      {Vec3(-1e6, 0.4, 0.9), Vec3(0, 0.4, 0.9)},
  };
  for (const auto& [outside, closest] : outside_and_closest)
    EXPECT_LT(relative_error(field->at(outside), commuting_field(closest)), 1e-12)
        << outside.transpose();
}

// An L-shaped 2D mesh: a point in the notch lies inside the bounding grid but in no triangle.
TEST(MeshMetricField, PointsInAConcaveNotchTakeTheClosestBoundaryPoint) {
  TempDir dir;
  MeditMesh square = unit_square_triangles(4);
  MeditMesh l_shape = square;
  l_shape.triangles.clear();
  l_shape.triangle_refs.clear();
  for (std::size_t t = 0; t < square.triangles.size(); ++t) {
    Vec3 centroid = Vec3::Zero();
    for (int v : square.triangles[t]) centroid += square.vertices[v] / 3;
    if (centroid.x() > 0.5 && centroid.y() > 0.5) continue;  // cut out the upper right quarter
    l_shape.triangles.push_back(square.triangles[t]);
    l_shape.triangle_refs.push_back(0);
  }
  const auto files = write_sampled(dir, "l", l_shape, commuting_field_2d);
  const auto field = load_mesh_metric(files.mesh, files.sol);
  const std::vector<std::pair<Vec3, Vec3>> outside_and_closest = {
      {Vec3(0.9, 0.6, 0), Vec3(0.9, 0.5, 0)},     // closest to the notch's bottom edge
      {Vec3(0.55, 0.95, 0), Vec3(0.5, 0.95, 0)},  // closest to its left edge
      {Vec3(0.7, 0.6, 0), Vec3(0.7, 0.5, 0)},
      {Vec3(1.2, 0.8, 0), Vec3(1.0, 0.5, 0)},  // outside the bounding box: a corner
  };
  for (const auto& [outside, closest] : outside_and_closest)
    EXPECT_LT(relative_error(field->at(outside), commuting_field_2d(closest)), 1e-12)
        << outside.transpose();
}

TEST(MeshMetricField, DescriptionAndNaturalDomain) {
  TempDir dir;
  const auto files = write_sampled(dir, "cube", unit_cube_tetrahedra(2), commuting_field);
  const auto field = load_mesh_metric(files.mesh, files.sol);
  EXPECT_EQ(field->description(), "metric from " + files.sol + " on " + files.mesh);
  EXPECT_EQ(field->dimension(), 3);
  const auto box = field->natural_domain();
  ASSERT_TRUE(box.has_value());
  EXPECT_EQ(box->lo, Vec3::Zero());
  EXPECT_EQ(box->hi, Vec3::Ones());
}

// A vertex that no element uses (exporters leave some) is not part of the mesh: it neither
// widens the natural domain nor stretches the lookup grid (with one at 1000 the whole mesh fell
// into one bucket, and every lookup scanned all its elements).
TEST(MeshMetricField, VerticesNoElementUsesAreIgnored) {
  TempDir dir;
  MeditMesh cube = unit_cube_tetrahedra(3);
  cube.vertices.push_back(Vec3(1000, 1000, 1000));
  const auto files = write_sampled(dir, "stray", cube, [](const Vec3& p) {
    return p.norm() > 10 ? Mat3::Identity() : commuting_field(p);
  });
  const auto field = load_mesh_metric(files.mesh, files.sol);
  const auto box = field->natural_domain();
  ASSERT_TRUE(box.has_value());
  EXPECT_EQ(box->hi, Vec3::Ones());
  for (const Vec3& p : random_points(200, 21))
    EXPECT_LT(relative_error(field->at(p), commuting_field(p)), 1e-12) << p.transpose();
}

TEST(MeshMetricField, ConcurrentQueriesGiveTheSerialResults) {
  TempDir dir;
  const auto files =
      write_sampled(dir, "cube", unit_cube_tetrahedra(6), rotating_anisotropic_field);
  const auto field = load_mesh_metric(files.mesh, files.sol);
  const std::vector<Vec3> points = random_points(4000, 11, -0.2, 1.2);
  std::vector<Mat3> serial;
  for (const Vec3& p : points) serial.push_back(field->at(p));
  std::vector<Mat3> parallel(points.size());
  std::vector<std::thread> threads;
  constexpr int kThreads = 4;
  for (int t = 0; t < kThreads; ++t)
    threads.emplace_back([&, t] {
      for (std::size_t i = t; i < points.size(); i += kThreads) parallel[i] = field->at(points[i]);
    });
  for (auto& thread : threads) thread.join();
  for (std::size_t i = 0; i < points.size(); ++i) EXPECT_EQ(parallel[i], serial[i]) << i;
}

// CPU seconds per query (other processes may share the cores: wall time says little).
double seconds_per_query(const MetricField& field, const std::vector<Vec3>& points) {
  const std::clock_t start = std::clock();
  double checksum = 0;
  for (const Vec3& p : points) checksum += field.at(p)(0, 0);
  EXPECT_TRUE(std::isfinite(checksum));
  return double(std::clock() - start) / CLOCKS_PER_SEC / points.size();
}

// Not a benchmark: guards against point location degrading to a scan of every element, inside
// the mesh and (closest-point search) outside it.
TEST(MeshMetricField, QueriesAreFast) {
#ifndef NDEBUG
  GTEST_SKIP() << "timings are meaningful in optimised builds only";
#endif
  TempDir dir;
  const auto files =
      write_sampled(dir, "cube", unit_cube_tetrahedra(24), rotating_anisotropic_field);
  const auto field = load_mesh_metric(files.mesh, files.sol);
  const double inside = seconds_per_query(*field, random_points(100000, 13));
  const double around = seconds_per_query(*field, random_points(20000, 17, -0.5, 1.5));
  std::cout << "82944 tetrahedra, random points: " << 1e-6 / inside
            << " million queries/s inside the mesh, " << 1e-6 / around
            << " million/s in a box 2x as wide (7/8 outside)\n";
  EXPECT_LT(inside, 50e-6);
  EXPECT_LT(around, 200e-6);
}

void expect_load_error(const std::string& message, const std::string& path,
                       const std::string& problem) {
  EXPECT_NE(message.find(path), std::string::npos) << message;
  EXPECT_NE(message.find(problem), std::string::npos) << message;
}

TEST(MeshMetricFieldErrors, SolWithAnotherVertexCount) {
  TempDir dir;
  const auto files = write_sampled(dir, "cube", unit_cube_tetrahedra(2), commuting_field);
  const auto other = write_sampled(dir, "other", unit_cube_tetrahedra(1), commuting_field);
  expect_load_error(error_message([&] { load_mesh_metric(files.mesh, other.sol); }),
                    other.sol + ":6:", "SolAtVertices has 8 entries but the mesh has 27 vertices");
}

TEST(MeshMetricFieldErrors, SolOfAnotherDimension) {
  TempDir dir;
  const auto files = write_sampled(dir, "cube", unit_cube_tetrahedra(1), commuting_field);
  std::vector<Mat3> tensors(8, Mat3::Identity());
  write_medit_sol_tensors(dir.file("flat.sol"), 2, tensors);
  expect_load_error(error_message([&] { load_mesh_metric(files.mesh, dir.file("flat.sol")); }),
                    dir.file("flat.sol"), "Dimension 2, but the mesh's Dimension is 3");
}

// The dimension is checked at its line, before the tensors: read with the other dimension's count
// of values, they went wrong first ("not SPD" at a vertex).
TEST(MeshMetricFieldErrors, SolClaimingAnotherDimensionIsRefusedAtItsLine) {
  TempDir dir;
  write_text(dir.file("flat.mesh"),
             "MeshVersionFormatted 2\nDimension 2\nVertices\n3\n0 0 0\n1 0 0\n0 1 0\n"
             "Triangles\n1\n1 2 3 0\nEnd\n");
  write_text(dir.file("flat.sol"),
             "MeshVersionFormatted 2\nDimension 3\nSolAtVertices\n3\n1 3\n4 0 1\n4 0 1\n4 0 1\n"
             "End\n");
  expect_load_error(
      error_message([&] { load_mesh_metric(dir.file("flat.mesh"), dir.file("flat.sol")); }),
      dir.file("flat.sol") + ":2:", "Dimension 3, but the mesh's Dimension is 2");
}

TEST(MeshMetricFieldErrors, MeshWithoutTetrahedra) {
  TempDir dir;
  MeditMesh mesh = unit_cube_tetrahedra(1);
  mesh.tetrahedra.clear();
  mesh.tetrahedron_refs.clear();
  mesh.triangles = {{0, 1, 2}};
  const auto files = write_sampled(dir, "surface", mesh, commuting_field);
  expect_load_error(error_message([&] { load_mesh_metric(files.mesh, files.sol); }), files.mesh,
                    "no Tetrahedra to interpolate the metric on");
}

TEST(MeshMetricFieldErrors, OnlyDegenerateElements) {
  TempDir dir;
  MeditMesh mesh;
  mesh.dimension = 3;
  mesh.vertices = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(1, 1, 0)};
  mesh.tetrahedra = {{0, 1, 2, 3}};
  const auto files = write_sampled(dir, "flat", mesh, commuting_field);
  expect_load_error(error_message([&] { load_mesh_metric(files.mesh, files.sol); }), files.mesh,
                    "degenerate");
}

TEST(MeshMetricFieldErrors, NonSpdTensorNamesTheSolFile) {
  TempDir dir;
  const auto files = write_sampled(dir, "cube", unit_cube_tetrahedra(1), commuting_field);
  std::vector<Mat3> tensors(8, Mat3::Identity());
  tensors[5](1, 1) = -1;
  write_medit_sol_tensors(files.sol, 3, tensors);
  expect_load_error(error_message([&] { load_mesh_metric(files.mesh, files.sol); }),
                    files.sol + ":13:", "tensor of vertex 6 (1-based) is not symmetric positive");
}

}  // namespace
}  // namespace rvor::test
