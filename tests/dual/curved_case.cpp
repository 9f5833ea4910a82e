// The shared curved-dual test case (curved_case.h).
#include "dual/curved_case.h"

#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <cstdio>

#include "dual/dual_fixtures.h"
#include "rvor/local_fields.h"
#include "rvor/nerve.h"
#include "support/box_canvas.h"

namespace rvor::test {

double distance_to_segment(const Vec3& p, const Vec3& a, const Vec3& b) {
  const Vec3 ab = b - a;
  const double t = std::clamp((p - a).dot(ab) / ab.squaredNorm(), 0.0, 1.0);
  return (p - (a + t * ab)).norm();
}

// Distance from p to the triangle (a, b, c): to its plane where p projects inside, else to the
// nearest side.
double distance_to_triangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
  const Vec3 n = (b - a).cross(c - a);
  if (n.squaredNorm() > 0.0) {
    const Vec3 q = p - n * (p - a).dot(n) / n.squaredNorm();
    const bool inside = (b - a).cross(q - a).dot(n) >= 0 && (c - b).cross(q - b).dot(n) >= 0 &&
                        (a - c).cross(q - c).dot(n) >= 0;
    if (inside) return (p - q).norm();
  }
  return std::min(
      {distance_to_segment(p, a, b), distance_to_segment(p, b, c), distance_to_segment(p, c, a)});
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

namespace {

// Every patch vertex of every face: distance to the flat triangle of its seeds, in voxels.
void measure_faces(const CurvedDual& dual, const std::vector<Vec3>& seeds, double h,
                   CurvedMeasures& m) {
  m.faces = dual.faces.size();
  m.unreached_faces = dual.unreached_faces;
  for (const CurvedFace& f : dual.faces) {
    EXPECT_TRUE(f.reached()) << "face " << f.seeds[0] << "-" << f.seeds[1] << "-" << f.seeds[2];
    m.face_triangles += f.triangles.size();
    double deviation = 0.0;
    for (const Vec3& p : f.points)
      deviation = std::max(deviation, distance_to_triangle(p, seeds[f.seeds[0]], seeds[f.seeds[1]],
                                                           seeds[f.seeds[2]]));
    deviation /= h;
    m.max_face_deviation = std::max(m.max_face_deviation, deviation);
    EXPECT_LE(deviation, 2.0) << "face " << f.seeds[0] << "-" << f.seeds[1] << "-" << f.seeds[2];
  }
}

// The default dual's edges against the traces (`traced`): none longer, and each straightened
// one its segment, with the segment's length.
void expect_straightened_on_their_segments(const CurvedDual& dual, const CurvedDual& traced,
                                           const Mat3& F) {
  ASSERT_EQ(dual.edges.size(), traced.edges.size());
  for (std::size_t n = 0; n < dual.edges.size(); ++n) {
    const CurvedEdge& e = dual.edges[n];
    EXPECT_LE(e.length, traced.edges[n].length * (1 + 1e-12)) << "edge " << n;
    if (!e.straightened) continue;
    const Vec3& a = dual.vertices[e.seeds[0]];
    const Vec3& b = dual.vertices[e.seeds[1]];
    ASSERT_EQ(e.points.size(), 3u) << "edge " << n;
    EXPECT_LT(distance_to_segment(e.points[1], a, b), 1e-9) << "edge " << n;
    // The canvas keeps its tensors in float: lengths to about 1e-7.
    EXPECT_NEAR(e.length, (F * (b - a)).norm(), 1e-6 * (F * (b - a)).norm()) << "edge " << n;
  }
}

}  // namespace

CurvedMeasures run_case(const CurvedCase& c, const std::string& vtu_path) {
  const Mat3 F = random_uniform_sqrt_metric(c.dimension, Vec3(4, 1, 2), c.rng_seed);
  const Vec3 lo(0, 0, 0), hi(1, 1, 1);
  const Canvas canvas = make_uniform_box_canvas(c.dimension, lo, hi, c.resolution, F * F);
  const double h = canvas.voxel_size;
  const std::vector<Vec3> seeds = poisson_disk_seeds(
      c.dimension, lo, hi, 3 * h, F, poisson_radius(c.dimension, lo, hi, F, c.seed_count),
      c.seed_count, c.rng_seed);
  const VoronoiField field =
      c.reference_solver ? solve_reference(canvas, seeds) : exact_uniform_field(canvas, seeds, F);
  const Nerve nerve = extract_nerve(canvas, field, seeds.size());
  CurvedMeasures m;
  LocalFields locals;
  if (c.local_fields) {
    locals = compute_local_fields(canvas, nerve, seeds);
    m.local_seconds = locals.seconds;
    m.local_voxels_per_seed = static_cast<double>(locals.solved_voxels) / seeds.size();
  }
  // The traces themselves: in a uniform metric nearly every traced edge comes out a little longer
  // than its segment, which straightening then gives exactly (max deviation 0.000 voxels), so the
  // default dual measured the segments, not the tracer.
  CurvedDualOptions traced;
  traced.straighten_longer_edges = false;
  const LocalFields* used = c.local_fields ? &locals : nullptr;
  const CurvedDual dual = build_curved_dual(canvas, field, nerve, seeds, used, traced);
  expect_straightened_on_their_segments(build_curved_dual(canvas, field, nerve, seeds, used), dual,
                                        F);
  EXPECT_EQ(dual.edges.size(), nerve.edges.size());
  EXPECT_EQ(dual.vertices.size(), seeds.size());
  EXPECT_EQ(dual.faces.size(), c.local_fields ? nerve.triangles.size() : 0u);

  const double F_max = Eigen::SelfAdjointEigenSolver<Mat3>(F).eigenvalues().maxCoeff();
  m.edges = dual.edges.size();
  m.unreached = dual.unreached_edges;
  // A uniform metric's descent does not stall: no trace needs the staircase fallback.
  EXPECT_EQ(dual.staircase_edges, 0u);
  EXPECT_EQ(dual.staircase_faces, 0u);
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
    if (c.local_fields) {
      EXPECT_LE(deviation, 2.0) << "edge " << e.seeds[0] << "-" << e.seeds[1];
      EXPECT_LE(error, 0.02) << "edge " << e.seeds[0] << "-" << e.seeds[1];
    }
    if (!is_gabriel(seeds, F, e.seeds[0], e.seeds[1], 2 * h * F_max)) continue;
    ++m.gabriel;
    m.max_deviation_voxels = std::max(m.max_deviation_voxels, deviation);
    m.max_relative_length_error = std::max(m.max_relative_length_error, error);
    EXPECT_LE(deviation, 2.0) << "edge " << e.seeds[0] << "-" << e.seeds[1];
    EXPECT_LE(error, 0.02) << "edge " << e.seeds[0] << "-" << e.seeds[1];
  }
  measure_faces(dual, seeds, h, m);
  std::printf(
      "[curved %dD %d^%d, %zu seeds, %s field, %s] %zu edges (%zu Gabriel), %zu unreached, "
      "%.3f s; Gabriel edges: max deviation %.3f voxels, max relative length error %.4f; all "
      "edges: %.3f voxels, %.4f; %zu faces (%zu triangles, %zu unreached): max deviation %.3f "
      "voxels; local fields %.3f s, %.0f voxels per seed\n",
      c.dimension, c.resolution, c.dimension, seeds.size(),
      c.reference_solver ? "reference" : "exact",
      c.local_fields ? "local fields" : "labeled field only", m.edges, m.gabriel, m.unreached,
      dual.seconds, m.max_deviation_voxels, m.max_relative_length_error, m.max_deviation_all,
      m.max_relative_length_error_all, m.faces, m.face_triangles, m.unreached_faces,
      m.max_face_deviation, m.local_seconds, m.local_voxels_per_seed);
  if (!vtu_path.empty()) {
    write_curved_dual_vtu(vtu_path + "/curved_dual.vtu", dual);
    write_curved_faces_vtu(vtu_path + "/curved_faces.vtu", dual);
  }
  return m;
}

}  // namespace rvor::test
