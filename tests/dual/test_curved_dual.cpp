// Curved dual in uniform anisotropic metrics: geodesics are straight, so every curved edge whose
// segment midpoint lies on the common Voronoi face of its seeds (Gabriel in F-space, with a margin)
// must follow the straight segment within 2 voxels and measure |F (a - b)| within 2%. Edges whose
// midpoint lies in a third seed's cell start from the face's boundary and are only required to
// reach both seeds. The .vtu must read back in VTK with one polyline per edge.
#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <sstream>

#include "dual/dual_fixtures.h"
#include "rvor/curved_dual.h"
#include "rvor/error.h"
#include "rvor/nerve.h"
#include "support/box_canvas.h"
#include "support/run_command.h"
#include "support/temp_dir.h"

namespace rvor {
namespace {

double distance_to_segment(const Vec3& p, const Vec3& a, const Vec3& b) {
  const Vec3 ab = b - a;
  const double t = std::clamp((p - a).dot(ab) / ab.squaredNorm(), 0.0, 1.0);
  return (p - (a + t * ab)).norm();
}

// True when the F-space midpoint of (a, b) is nearer to a and b than to any other seed by at
// least `margin` (metric units).
bool is_gabriel(const std::vector<Vec3>& seeds, const Mat3& F, int a, int b, double margin) {
  const Vec3 m = 0.5 * (seeds[a] + seeds[b]);
  const double r = (F * (m - seeds[a])).norm();
  for (std::size_t c = 0; c < seeds.size(); ++c) {
    if (static_cast<int>(c) == a || static_cast<int>(c) == b) continue;
    if ((F * (m - seeds[c])).norm() < r + margin) return false;
  }
  return true;
}

struct CurvedCase {
  int dimension;
  int resolution;
  std::size_t seed_count;
  std::uint64_t rng_seed;
  bool reference_solver = false;  // else the exact field of the uniform metric
};

struct CurvedMeasures {
  std::size_t edges = 0, gabriel = 0, unreached = 0;
  double max_deviation_voxels = 0.0;       // Gabriel edges
  double max_relative_length_error = 0.0;  // Gabriel edges
  double max_deviation_all = 0.0, max_relative_length_error_all = 0.0;
};

CurvedMeasures run_case(const CurvedCase& c, const std::string& vtu_path = "") {
  const Mat3 F = test::random_uniform_sqrt_metric(c.dimension, Vec3(4, 1, 2), c.rng_seed);
  const Vec3 lo(0, 0, 0), hi(1, 1, 1);
  const Canvas canvas = test::make_uniform_box_canvas(c.dimension, lo, hi, c.resolution, F * F);
  const double h = canvas.voxel_size;
  const std::vector<Vec3> seeds = test::poisson_disk_seeds(
      c.dimension, lo, hi, 3 * h, F, test::poisson_radius(c.dimension, lo, hi, F, c.seed_count),
      c.seed_count, c.rng_seed);
  const VoronoiField field = c.reference_solver ? test::solve_reference(canvas, seeds)
                                                : test::exact_uniform_field(canvas, seeds, F);
  const Nerve nerve = extract_nerve(canvas, field, seeds.size());
  const CurvedDual dual = build_curved_dual(canvas, field, nerve, seeds);
  EXPECT_EQ(dual.edges.size(), nerve.edges.size());
  EXPECT_EQ(dual.vertices.size(), seeds.size());

  const double F_max = Eigen::SelfAdjointEigenSolver<Mat3>(F).eigenvalues().maxCoeff();
  CurvedMeasures m;
  m.edges = dual.edges.size();
  m.unreached = dual.unreached_edges;
  for (const CurvedEdge& e : dual.edges) {
    const Vec3& a = seeds[e.seeds[0]];
    const Vec3& b = seeds[e.seeds[1]];
    EXPECT_TRUE(e.reached()) << "edge " << e.seeds[0] << "-" << e.seeds[1];
    EXPECT_GE(e.points.size(), 3u);
    EXPECT_LT(e.bisector_index, e.points.size());
    if (!e.points.empty()) {
      EXPECT_EQ(e.points.front(), a);
      EXPECT_EQ(e.points.back(), b);
    }
    double deviation = 0.0;
    for (const Vec3& p : e.points) deviation = std::max(deviation, distance_to_segment(p, a, b));
    deviation /= h;
    const double exact = (F * (a - b)).norm();
    const double error = std::abs(e.length - exact) / exact;
    m.max_deviation_all = std::max(m.max_deviation_all, deviation);
    m.max_relative_length_error_all = std::max(m.max_relative_length_error_all, error);
    if (!is_gabriel(seeds, F, e.seeds[0], e.seeds[1], 2 * h * F_max)) continue;
    ++m.gabriel;
    m.max_deviation_voxels = std::max(m.max_deviation_voxels, deviation);
    m.max_relative_length_error = std::max(m.max_relative_length_error, error);
    EXPECT_LE(deviation, 2.0) << "edge " << e.seeds[0] << "-" << e.seeds[1];
    EXPECT_LE(error, 0.02) << "edge " << e.seeds[0] << "-" << e.seeds[1];
  }
  std::printf(
      "[curved %dD %d^%d, %zu seeds, %s field] %zu edges (%zu Gabriel), %zu unreached, %.3f s; "
      "Gabriel "
      "edges: "
      "max deviation %.3f voxels, max relative length error %.4f; all edges: %.3f voxels, %.4f\n",
      c.dimension, c.resolution, c.dimension, seeds.size(),
      c.reference_solver ? "reference" : "exact", m.edges, m.gabriel, m.unreached, dual.seconds,
      m.max_deviation_voxels, m.max_relative_length_error, m.max_deviation_all,
      m.max_relative_length_error_all);
  if (!vtu_path.empty()) write_curved_dual_vtu(vtu_path, dual);
  return m;
}

TEST(CurvedDual, Uniform2DEdgesFollowStraightSegmentsWithExactLengths) {
  for (std::uint64_t rng_seed : {11u, 12u}) {
    const CurvedMeasures m = run_case({2, 128, 20, rng_seed});
    EXPECT_GT(m.edges, 20u);
    EXPECT_GE(m.gabriel * 2, m.edges);  // the checked edges are most of them
    EXPECT_EQ(m.unreached, 0u);
  }
}

TEST(CurvedDual, Uniform3DEdgesFollowStraightSegmentsWithExactLengths) {
  for (std::uint64_t rng_seed : {21u, 22u}) {
    const CurvedMeasures m = run_case({3, 48, 20, rng_seed});
    EXPECT_GT(m.edges, 40u);
    EXPECT_GE(m.gabriel * 4, m.edges);  // fewer Delaunay edges are Gabriel in 3D
    EXPECT_EQ(m.unreached, 0u);
  }
}

TEST(CurvedDual, ReferenceSolverFieldsGiveTheSameGeodesics) {
  for (int dimension : {2, 3}) {
    const CurvedMeasures m = run_case({dimension, dimension == 2 ? 128 : 40, 20, 41, true});
    EXPECT_GT(m.gabriel, 10u);
    EXPECT_EQ(m.unreached, 0u);
  }
}

// phi(x) = x + a (sin(w y), sin(w x)) / w, a < 1: a 2D diffeomorphism; G = J^T J pulls the
// Euclidean metric back, so d(p, q) = |phi(p) - phi(q)| and the geodesic from p to q is the
// pull-back of the segment [phi(p), phi(q)] (where that segment stays in phi(domain)).
struct PullBack2D {
  double a = 0.4, w = 3.0;
  Vec3 phi(const Vec3& x) const {
    return {x.x() + a * std::sin(w * x.y()) / w, x.y() + a * std::sin(w * x.x()) / w, 0};
  }
  Mat3 metric(const Vec3& x) const {
    Mat3 J = Mat3::Identity();
    J(0, 1) = a * std::cos(w * x.y());
    J(1, 0) = a * std::cos(w * x.x());
    Mat3 G = J.transpose() * J;
    G.row(2).setZero();
    G.col(2).setZero();
    G(2, 2) = 1;
    return G;
  }
};

TEST(CurvedDual, PulledBackMetricEdgesFollowExactGeodesics) {
  const PullBack2D pull;
  const Vec3 lo(-1, -1, 0), hi(1, 1, 0);
  const Canvas canvas =
      test::make_box_canvas(2, lo, hi, 160, [&](const Vec3& x) { return pull.metric(x); });
  const double h = canvas.voxel_size;
  const Vec3 seed_lo(-0.7, -0.7, 0), seed_hi(0.7, 0.7, 0);
  const std::vector<Vec3> seeds = test::poisson_disk_seeds(
      2, seed_lo, seed_hi, 0, Mat3::Identity(),
      test::poisson_radius(2, seed_lo, seed_hi, Mat3::Identity(), 20), 20, 51);
  VoronoiField field;
  field.distance.assign(canvas.slot_count(), std::numeric_limits<float>::infinity());
  field.label.assign(canvas.slot_count(), -1);
  std::vector<Vec3> images;
  for (const Vec3& s : seeds) images.push_back(pull.phi(s));
  for (std::size_t slot = 0; slot < canvas.slot_count(); ++slot) {
    if (!canvas.active[slot]) continue;
    const Vec3 p = pull.phi(canvas.world_of(slot));
    double best = std::numeric_limits<double>::infinity();
    for (std::size_t s = 0; s < images.size(); ++s)
      if ((p - images[s]).norm() < best) {
        best = (p - images[s]).norm();
        field.label[slot] = static_cast<int32_t>(s);
      }
    field.distance[slot] = static_cast<float>(best);
  }
  const Nerve nerve = extract_nerve(canvas, field, seeds.size());
  const CurvedDual dual = build_curved_dual(canvas, field, nerve, seeds);
  EXPECT_EQ(dual.unreached_edges, 0u);
  std::size_t checked = 0;
  double max_deviation = 0, max_error = 0;
  for (const CurvedEdge& e : dual.edges) {
    const Vec3 &pa = images[e.seeds[0]], &pb = images[e.seeds[1]];
    // Gabriel in phi-space with a 2-voxel margin (|J| <= 1 + a).
    if (!is_gabriel(images, Mat3::Identity(), e.seeds[0], e.seeds[1], 2 * h * (1 + pull.a)))
      continue;
    ++checked;
    double deviation = 0;  // in phi-space, voxels
    for (const Vec3& p : e.points)
      deviation = std::max(deviation, distance_to_segment(pull.phi(p), pa, pb) / h);
    const double exact = (pa - pb).norm();
    const double error = std::abs(e.length - exact) / exact;
    max_deviation = std::max(max_deviation, deviation);
    max_error = std::max(max_error, error);
    EXPECT_LE(deviation, 2.0) << "edge " << e.seeds[0] << "-" << e.seeds[1];
    EXPECT_LE(error, 0.02) << "edge " << e.seeds[0] << "-" << e.seeds[1];
  }
  std::printf(
      "[curved 2D pull-back 160^2, %zu seeds] %zu edges (%zu Gabriel in phi-space), %zu "
      "unreached: max deviation from phi^-1(segment) %.3f voxels (phi-space), max relative "
      "length error %.4f\n",
      seeds.size(), dual.edges.size(), checked, dual.unreached_edges, max_deviation, max_error);
  EXPECT_GT(checked, 10u);
}

TEST(CurvedDual, VtuReadsBackInVtkWithOnePolylinePerEdge) {
  test::TempDir dir;
  const std::string path = dir.file("curved_dual.vtu");
  const CurvedMeasures m = run_case({2, 96, 20, 31}, path);
  const auto vtk = test::run_command(
      test::debian_python() +
      " -c \"import vtk; r = vtk.vtkXMLUnstructuredGridReader(); r.SetFileName('" + path +
      "'); r.Update(); g = r.GetOutput(); "
      "print(g.GetNumberOfCells(), g.GetCellType(0), "
      "g.GetCellData().GetArray('reached').GetRange()[0], "
      "g.GetCellData().GetArray('length').GetRange()[0])\"");
  ASSERT_EQ(vtk.exit_code, 0) << vtk.err;
  std::istringstream fields(vtk.out);
  std::size_t cells = 0;
  int type = 0;
  double min_reached = -1, min_length = -1;
  fields >> cells >> type >> min_reached >> min_length;
  EXPECT_EQ(cells, m.edges);
  EXPECT_EQ(type, 4);  // VTK_POLY_LINE
  EXPECT_EQ(min_reached, 1.0);
  EXPECT_GT(min_length, 0.0);
}

// A larger case: thin cells and many edges, where incomplete gradients once left edges unreached.
TEST(CurvedDual, EveryEdgeReachesItsSeedsWith500Seeds3D) {
  const CurvedMeasures m = run_case({3, 96, 500, 61});
  EXPECT_EQ(m.unreached, 0u);
}

TEST(CurvedDual, RejectsMismatchedSeeds) {
  const Mat3 F = Mat3::Identity();
  const Canvas canvas =
      test::make_uniform_box_canvas(2, Vec3(0, 0, 0), Vec3(1, 1, 1), 32, Mat3::Identity());
  const std::vector<Vec3> seeds{Vec3(0.25, 0.5, 0), Vec3(0.75, 0.5, 0)};
  const VoronoiField field = test::exact_uniform_field(canvas, seeds, F);
  const Nerve nerve = extract_nerve(canvas, field, seeds.size());
  EXPECT_THROW(build_curved_dual(canvas, field, nerve, {seeds[0]}), Error);
  const CurvedDual dual = build_curved_dual(canvas, field, nerve, seeds);
  ASSERT_EQ(dual.edges.size(), 1u);
  EXPECT_TRUE(dual.edges[0].reached());
  EXPECT_NEAR(dual.edges[0].length, 0.5, 0.01);
}

}  // namespace
}  // namespace rvor
