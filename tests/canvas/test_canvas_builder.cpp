#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>

#include "canvas_test_support.h"
#include "rvor/canvas_builder.h"
#include "rvor/error.h"
#include "support/box_canvas.h"
#include "support/limited_child.h"
#include "support/temp_dir.h"

namespace rvor {
namespace {

// A 2D canvas keeps only the xy block of a tensor given to set_active, with 1 along z, as the
// builder stores it: with another zz entry the reference and the kernels weighed the source
// factorization differently (docs/scheme.md, "Local update", step 2) and disagreed by 10%.
TEST(CanvasStorage, SetActiveStoresTheCanvasDimensionsBlock) {
  Canvas canvas;
  canvas.allocate(2, 0.5, Vec3::Zero(), {8, 8, 1}, {VoxelIndex{0, 0, 0}});
  Mat3 G;
  G << 2, 0.5, 0.3, 0.5, 3, 0.2, 0.3, 0.2, 4;
  canvas.set_active(5, G);
  Mat3 expected;
  expected << 2, 0.5, 0, 0.5, 3, 0, 0, 0, 1;
  EXPECT_EQ(canvas.metric_at(5), expected);
}

using test::FunctionMetric;

std::string build_error(const DomainSpec& domain, const MetricField& metric,
                        CanvasOptions options) {
  try {
    build_canvas(domain, metric, options);
  } catch (const Error& error) {
    return error.what();
  }
  return "";
}

Canvas build(const std::string& spec, int resolution, const MetricField& metric) {
  CanvasOptions options;
  options.resolution = resolution;
  return build_canvas(parse_domain(spec), metric, options);
}

Mat3 varying_metric(const Vec3& p) {
  Mat3 G;
  G << 2 + p.x(), 0.3 * p.y(), 0.1, 0.3 * p.y(), 3, 0.2 * p.z(), 0.1, 0.2 * p.z(), 4;
  return G;
}

void expect_same_canvas(const Canvas& built, const Canvas& expected) {
  EXPECT_EQ(built.dimension, expected.dimension);
  EXPECT_DOUBLE_EQ(built.voxel_size, expected.voxel_size);
  EXPECT_TRUE(built.origin.isApprox(expected.origin, 1e-12)) << built.origin.transpose();
  EXPECT_EQ(built.dims, expected.dims);
  EXPECT_EQ(built.brick_grid_dims, expected.brick_grid_dims);
  EXPECT_EQ(built.active_voxel_count, expected.active_voxel_count);
  ASSERT_EQ(built.brick_count(), expected.brick_count());
  for (std::size_t slot = 0; slot < built.slot_count(); ++slot) {
    if (!built.active[slot]) continue;
    const int64_t other = expected.slot_of(built.voxel_of(slot));
    ASSERT_GE(other, 0) << "slot " << slot;
    for (int n = 0; n < 6; ++n) ASSERT_EQ(built.metric_of(slot)[n], expected.metric_of(other)[n]);
  }
}

TEST(BuildCanvas, BoxMatchesTheDenseTestCanvas) {
  const FunctionMetric metric(3, varying_metric);
  const Canvas built = build("box:-1,-0.5,0,1,0.5,0.3", 40, metric);
  const Canvas expected =
      test::make_box_canvas(3, Vec3(-1, -0.5, 0), Vec3(1, 0.5, 0.3), 40, varying_metric);
  expect_same_canvas(built, expected);
  EXPECT_EQ(built.active_voxel_count, 40u * 20u * 6u);
  EXPECT_NE(built.description.find("box:-1,-0.5,0,1,0.5,0.3"), std::string::npos);
  EXPECT_NE(built.description.find("resolution 40"), std::string::npos);
}

// A box domain is closed: points on its faces, the upper ones included, lie in boundary voxels
// (cells are half-open, so x = hi used to round one past the last voxel); a point off the box by
// more than rounding does not.
TEST(BuildCanvas, PointsOnTheBoxFacesLieInBoundaryVoxels) {
  const FunctionMetric metric(3, [](const Vec3&) { return Mat3::Identity(); });
  for (const int resolution : {16, 17}) {
    const Canvas canvas = build("box:-1,-1,-1,1,1,1", resolution, metric);
    const int last = resolution - 1;
    for (const Vec3& corner : {Vec3(-1, -1, -1), Vec3(1, 1, 1), Vec3(1, -1, 0.3)}) {
      const VoxelIndex v = canvas.voxel_containing(corner);
      EXPECT_GE(canvas.slot_of(v), 0) << resolution << ": " << corner.transpose();
      for (const int index : {v.i, v.j, v.k}) EXPECT_TRUE(index >= 0 && index <= last);
    }
    EXPECT_LT(canvas.slot_of(canvas.voxel_containing(Vec3(1.01, 0, 0))), 0);
    EXPECT_LT(canvas.slot_of(canvas.voxel_containing(Vec3(0, -1.01, 0))), 0);
  }
}

TEST(BuildCanvas, RectangleIsOneLayer) {
  const FunctionMetric metric(2, [](const Vec3& p) {
    Mat3 G = Mat3::Identity();
    G(0, 0) = 1 + p.x() * p.x();
    G(2, 2) = 7;  // not stored: 2D canvases keep G(2,2) = 1
    return G;
  });
  const Canvas built = build("rect:0,0,2,1", 50, metric);
  EXPECT_EQ(built.dimension, 2);
  EXPECT_EQ(built.dims, (std::array<int, 3>{50, 25, 1}));
  EXPECT_EQ(built.active_voxel_count, 50u * 25u);
  EXPECT_EQ(built.brick_volume(), 64);
  for (const VoxelIndex& o : built.brick_origins) EXPECT_EQ(o.k, 0);
  for (std::size_t slot = 0; slot < built.slot_count(); ++slot)
    if (built.active[slot]) {
      ASSERT_EQ(built.metric_at(slot)(2, 2), 1.0);
    }
  const Canvas expected =
      test::make_box_canvas(2, Vec3(0, 0, 0), Vec3(2, 1, 0), 50, [&](const Vec3& p) {
        Mat3 G = metric.at(p);
        G(2, 2) = 1;
        return G;
      });
  expect_same_canvas(built, expected);
}

double active_volume(const Canvas& canvas) {
  return canvas.active_voxel_count * std::pow(canvas.voxel_size, canvas.dimension);
}

TEST(BuildCanvas, ImplicitShapesHaveTheirVolume) {
  const double pi = M_PI;
  const auto euclidean3 = test::euclidean_metric(3);
  EXPECT_NEAR(active_volume(build("implicit:sphere:center=1,2,3,r=1", 64, euclidean3)),
              4.0 / 3.0 * pi, 0.02 * 4.0 / 3.0 * pi);
  EXPECT_NEAR(active_volume(build("implicit:torus:R=1,r=0.25", 80, euclidean3)),
              2 * pi * pi * 0.25 * 0.25, 0.03 * 2 * pi * pi * 0.0625);
  EXPECT_NEAR(active_volume(build("implicit:ellipsoid:a=1,b=0.75,c=0.5", 64, euclidean3)),
              4.0 / 3.0 * pi * 0.375, 0.02 * 4.0 / 3.0 * pi * 0.375);
  const Canvas disk = build("implicit:disk:center=0.5,0,r=1", 64, test::euclidean_metric(2));
  EXPECT_EQ(disk.dimension, 2);
  EXPECT_EQ(disk.dims[2], 1);
  EXPECT_NEAR(active_volume(disk), pi, 0.02 * pi);
}

TEST(BuildCanvas, ImplicitVoxelsAreExactlyThoseWithCentresInside) {
  const Canvas canvas = build("implicit:sphere:r=1", 24, test::euclidean_metric(3));
  std::size_t inside = 0;
  for (int k = 0; k < canvas.dims[2]; ++k)
    for (int j = 0; j < canvas.dims[1]; ++j)
      for (int i = 0; i < canvas.dims[0]; ++i) {
        const bool in_sphere = canvas.world_of(VoxelIndex{i, j, k}).norm() <= 1.0;
        inside += in_sphere;
        ASSERT_EQ(canvas.slot_of(i, j, k) >= 0, in_sphere) << i << " " << j << " " << k;
      }
  EXPECT_EQ(canvas.active_voxel_count, inside);
}

TEST(BuildCanvas, ClosedMeshesInEveryFormatHaveTheirVolume) {
  test::TempDir dir;
  const Vec3 lo(0.1, -0.2, 0.3), hi(2.1, 0.8, 1.1);  // volume 1.6
  test::write_box_off(dir.file("box.off"), lo, hi);
  test::write_box_obj(dir.file("box.obj"), lo, hi);
  test::write_box_stl_ascii(dir.file("box.stl"), lo, hi);
  test::write_box_stl_binary(dir.file("binary.stl"), lo, hi);
  for (const std::string name : {"box.off", "box.obj", "box.stl", "binary.stl"}) {
    const Canvas canvas = build("mesh:" + dir.file(name), 40, test::euclidean_metric(3));
    EXPECT_EQ(canvas.dimension, 3);
    EXPECT_NEAR(active_volume(canvas), 1.6, 0.03 * 1.6) << name;
  }
}

// The box [0,2]^3 whose top face is four triangles meeting at (1, 1, apex): a roof above 2, a
// dent below it, and one flat face (triangulated) at 2.
void write_roofed_box_off(const std::string& path, double apex) {
  std::ofstream out(path);
  out << "OFF\n9 9 0\n";
  for (int n = 0; n < 8; ++n) out << 2 * (n & 1) << " " << (n & 2) << " " << (n & 4) / 2 << "\n";
  out << "1 1 " << apex << "\n";
  out << "4 0 2 3 1\n4 0 1 5 4\n4 2 6 7 3\n4 0 4 6 2\n4 1 3 7 5\n";  // bottom and sides
  out << "3 4 5 8\n3 5 7 8\n3 7 6 8\n3 6 4 8\n";                     // top, around the apex
}

// The box [0,1]x[0,2]x[0,3] turned about (1, 2, 3), its corners written with 6 digits as
// exporters do, its faces split into triangles: their corners lie off the faces' planes by ~1e-6.
void write_turned_box_off(const std::string& path) {
  const Eigen::Matrix3d turn =
      Eigen::AngleAxisd(0.7, Vec3(1, 2, 3).normalized()).toRotationMatrix();
  std::ofstream out(path);
  out << "OFF\n8 12 0\n";
  char line[96];
  for (int n = 0; n < 8; ++n) {
    const Vec3 p = turn * Vec3(n & 1, (n & 2), 1.5 * ((n & 4) / 2));
    std::snprintf(line, sizeof line, "%.6g %.6g %.6g\n", p.x(), p.y(), p.z());
    out << line;
  }
  for (const char* face : {"0 2 3", "0 3 1", "0 1 5", "0 5 4", "2 6 7", "2 7 3", "0 4 6", "0 6 2",
                           "1 3 7", "1 7 5", "4 5 7", "4 7 6"})
    out << "3 " << face << "\n";
}

// Canvas::convex_domain, which lets a uniform diagonal metric start at u0 (rvor/nearest_seeds.h):
// boxes, spheres, ellipsoids, disks and convex meshes in any orientation are convex; a torus, a
// dented box, a bottle and two separate boxes are not.
TEST(BuildCanvas, KnowsWhichDomainsAreConvex) {
  test::TempDir dir;
  test::write_box_off(dir.file("box.off"), Vec3(0, 0, 0), Vec3(1, 1, 1));
  test::write_boxes_off(dir.file("flipped.off"), {{Vec3(0, 0, 0), Vec3(1, 2, 1)}}, true);
  test::write_boxes_off(dir.file("two.off"),
                        {{Vec3(0, 0, 0), Vec3(1, 1, 1)}, {Vec3(2, 0, 0), Vec3(3, 1, 1)}});
  test::write_bottle_off(dir.file("bottle.off"), 1.0);
  write_roofed_box_off(dir.file("roof.off"), 2.5);
  write_roofed_box_off(dir.file("flat.off"), 2.0);
  write_roofed_box_off(dir.file("dent.off"), 1.5);
  write_turned_box_off(dir.file("turned.off"));
  const std::pair<std::string, bool> cases[] = {{"box:0,0,0,1,2,3", true},
                                                {"rect:0,0,1,2", true},
                                                {"implicit:sphere:r=1", true},
                                                {"implicit:ellipsoid", true},
                                                {"implicit:disk:r=1", true},
                                                {"implicit:torus", false},
                                                {"mesh:" + dir.file("box.off"), true},
                                                {"mesh:" + dir.file("flipped.off"), true},
                                                {"mesh:" + dir.file("roof.off"), true},
                                                {"mesh:" + dir.file("flat.off"), true},
                                                {"mesh:" + dir.file("dent.off"), false},
                                                {"mesh:" + dir.file("bottle.off"), false},
                                                {"mesh:" + dir.file("two.off"), false},
                                                {"mesh:" + dir.file("turned.off"), true}};
  for (const auto& [spec, convex] : cases) {
    const int dimension = parse_domain(spec).dimension();
    EXPECT_EQ(build(spec, 16, test::euclidean_metric(dimension)).convex_domain, convex) << spec;
  }
}

TEST(BuildCanvas, OpenMeshIsRejected) {
  test::TempDir dir;
  test::write_box_off(dir.file("open.off"), Vec3(0, 0, 0), Vec3(1, 1, 1), true);
  const std::string message =
      build_error(parse_domain("mesh:" + dir.file("open.off")), test::euclidean_metric(3), {});
  EXPECT_NE(message.find("is not closed"), std::string::npos) << message;
}

std::string mesh_error(const test::TempDir& dir, const std::string& name) {
  return build_error(parse_domain("mesh:" + dir.file(name)), test::euclidean_metric(3), {});
}

TEST(BuildCanvas, SelfIntersectingMeshesAreRejected) {
  test::TempDir dir;
  // Two closed boxes that overlap, and two that touch along an edge without sharing its vertices:
  // every edge is used by two triangles, yet neither surface bounds a volume.
  test::write_boxes_off(dir.file("overlap.off"), {{Vec3(0, 0, 0), Vec3(1, 1, 1)},
                                                  {Vec3(0.5, 0.5, 0.5), Vec3(1.5, 1.5, 1.5)}});
  test::write_boxes_off(dir.file("touch.off"),
                        {{Vec3(0, 0, 0), Vec3(1, 1, 1)}, {Vec3(1, 1, 0), Vec3(2, 2, 1)}});
  for (const std::string name : {"overlap.off", "touch.off"}) {
    const std::string message = mesh_error(dir, name);
    EXPECT_NE(message.find("mesh " + dir.file(name) + " intersects itself: "), std::string::npos)
        << message;
  }
  // The first box's triangles are 0-11, the second's 12-23: every crossing pair has one of each.
  const std::string message = mesh_error(dir, "overlap.off");
  const std::size_t at = message.find("intersects itself: ");
  ASSERT_NE(at, std::string::npos) << message;
  int a = -1, b = -1;
  ASSERT_EQ(std::sscanf(message.c_str() + at, "intersects itself: triangle %d", &a), 1) << message;
  const std::size_t second = message.find(") and triangle ");
  ASSERT_NE(second, std::string::npos) << message;
  ASSERT_EQ(std::sscanf(message.c_str() + second, ") and triangle %d", &b), 1) << message;
  EXPECT_LT(a, 12);
  EXPECT_GE(b, 12);
  EXPECT_LT(b, 24);
}

// Coordinates past what float distances hold are named before the mesh's geometry is checked:
// a unit cube 1e16 from the origin, its corners rounded together, was refused for a degenerate
// triangle, and one with a vertex at 1e300 for crossing itself.
TEST(BuildCanvas, FarMeshesAreRefusedForTheirCoordinates) {
  test::TempDir dir;
  test::write_box_off(dir.file("far.off"), Vec3(1e16, 0, 0), Vec3(1e16 + 1, 1, 1));
  test::write_text(dir.file("spike.off"),
                   "OFF\n4 4 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1e300\n"
                   "3 0 2 1\n3 0 1 3\n3 1 2 3\n3 0 3 2\n");
  for (const std::string name : {"far.off", "spike.off"}) {
    const std::string message = mesh_error(dir, name);
    EXPECT_NE(message.find("domain mesh:" + dir.file(name) + " has coordinates beyond +-1e+15"),
              std::string::npos)
        << message;
  }
}

TEST(BuildCanvas, NestedAndMisorientedMeshesAreAccepted) {
  test::TempDir dir;
  // A box with a box-shaped cavity (two disjoint surfaces), and a box with one face reversed.
  test::write_boxes_off(dir.file("cavity.off"),
                        {{Vec3(0, 0, 0), Vec3(3, 3, 3)}, {Vec3(1, 1, 1), Vec3(2, 2, 2)}});
  test::write_boxes_off(dir.file("flipped.off"), {{Vec3(0, 0, 0), Vec3(1, 1, 1)}}, true);
  EXPECT_NEAR(active_volume(build("mesh:" + dir.file("cavity.off"), 60, test::euclidean_metric(3))),
              26.0, 0.03 * 26.0);
  EXPECT_NEAR(
      active_volume(build("mesh:" + dir.file("flipped.off"), 40, test::euclidean_metric(3))), 1.0,
      0.03);
}

// A chamber open to the outside through a neck narrower than a voxel is outside the solid.
// meshToLevelSet's sign, a flood fill of the outside through voxels the surface does not cross,
// could not pass necks up to 2 voxels wide and filled the chamber.
TEST(BuildCanvas, PocketsBehindNarrowOpeningsAreOutside) {
  test::TempDir dir;
  for (const double neck : {0.05, 0.25, 0.5}) {  // 0.4, 2 and 4 voxels at resolution 32
    const std::string name = dir.file("bottle.off");
    test::write_bottle_off(name, neck);
    const Canvas canvas = build("mesh:" + name, 32, test::euclidean_metric(3));
    std::size_t wrong = 0;
    for (int k = 0; k < canvas.dims[2]; ++k)
      for (int j = 0; j < canvas.dims[1]; ++j)
        for (int i = 0; i < canvas.dims[0]; ++i)
          wrong +=
              (canvas.slot_of(i, j, k) >= 0) != test::in_bottle(canvas.world_of({i, j, k}), neck);
    EXPECT_EQ(wrong, 0u) << "neck " << neck;
  }
}

// The canvas of a mesh file whose bounds are `resolution` long: voxels of size 1, centred at
// integer coordinates from 0 (checked).
Canvas unit_voxel_canvas(const std::string& path, int resolution) {
  const Canvas canvas = build("mesh:" + path, resolution, test::euclidean_metric(3));
  EXPECT_EQ(canvas.voxel_size, 1.0);
  EXPECT_EQ(canvas.world_of(VoxelIndex{0, 0, 0}), Vec3::Zero());
  return canvas;
}

// Rays through the mesh's vertices and edges: an octahedron whose corners are voxel centres (a
// tiny tetrahedron at two corners of the bounds makes the voxel size 1 and the first centre 0).
// Each such ray must still cross the surface an even number of times.
TEST(BuildCanvas, RaysThroughVerticesAndEdgesKeepTheirParity) {
  test::TempDir dir;
  test::write_text(dir.file("octahedron.off"),
                   "OFF\n14 16 0\n14 8 8\n2 8 8\n8 14 8\n8 2 8\n8 8 14\n8 8 2\n"
                   "-0.5 -0.5 -0.5\n-0.3 -0.5 -0.5\n-0.5 -0.3 -0.5\n-0.5 -0.5 -0.3\n"
                   "16.5 16.5 16.5\n16.3 16.5 16.5\n16.5 16.3 16.5\n16.5 16.5 16.3\n"
                   "3 0 2 4\n3 2 1 4\n3 1 3 4\n3 3 0 4\n3 2 0 5\n3 1 2 5\n3 3 1 5\n3 0 3 5\n"
                   "3 6 8 7\n3 6 7 9\n3 6 9 8\n3 7 8 9\n3 10 12 11\n3 10 11 13\n3 10 13 12\n"
                   "3 11 12 13\n");
  const Canvas canvas = unit_voxel_canvas(dir.file("octahedron.off"), 17);
  std::size_t checked = 0;
  for (int k = 0; k < canvas.dims[2]; ++k)
    for (int j = 0; j < canvas.dims[1]; ++j)
      for (int i = 0; i < canvas.dims[0]; ++i) {
        const int taxicab = std::abs(i - 8) + std::abs(j - 8) + std::abs(k - 8);
        if (taxicab == 6) continue;  // on the surface: either way
        EXPECT_EQ(canvas.slot_of(i, j, k) >= 0, taxicab < 6) << i << " " << j << " " << k;
        ++checked;
      }
  EXPECT_GT(checked, 4000u);
}

// A face that nearly contains the x direction: its (y, z) area rounds to 0 in double, and the
// crossing must then be placed exactly (it was NaN, and whole rows went wrong). The tetrahedron
// is the reviewer's case; every voxel centre clearly inside or outside is checked.
TEST(BuildCanvas, FacesNearlyAlongTheRaysCrossWhereTheyAre) {
  test::TempDir dir;
  const std::vector<Vec3> corners = {
      Vec3(-0.5, 1.0000000000000004, 1.0000000000000002), Vec3(10.0, 7.0, 7.0),
      Vec3(3.0, 12.999999999999996, 12.999999999999996), Vec3(15.5, -0.5, 10.0)};
  test::write_text(dir.file("sliver.off"),
                   "OFF\n8 8 0\n-0.5 1.0000000000000004 1.0000000000000002\n10 7 7\n"
                   "3 12.999999999999996 12.999999999999996\n15.5 -0.5 10\n0 13 -0.5\n1 13 0\n"
                   "0 12 0\n0.3 12.7 0.5\n3 0 1 2\n3 0 3 1\n3 1 3 2\n3 0 2 3\n3 4 5 6\n"
                   "3 4 7 5\n3 5 7 6\n3 4 6 7\n");
  const Canvas canvas = unit_voxel_canvas(dir.file("sliver.off"), 16);
  const auto volume = [](const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d) {
    return (b - a).cross(c - a).dot(d - a);
  };
  const int faces[4][4] = {{1, 2, 3, 0}, {0, 2, 3, 1}, {0, 1, 3, 2}, {0, 1, 2, 3}};
  std::size_t inside = 0;
  for (int k = 0; k < canvas.dims[2]; ++k)
    for (int j = 0; j < canvas.dims[1]; ++j)
      for (int i = 0; i < canvas.dims[0]; ++i) {
        const Vec3 p(i, j, k);
        bool in = true, clear = true;
        for (const auto& f : faces) {
          const double here = volume(corners[f[0]], corners[f[1]], corners[f[2]], p);
          const double opposite =
              volume(corners[f[0]], corners[f[1]], corners[f[2]], corners[f[3]]);
          clear = clear && std::abs(here) > 1e-6 * std::abs(opposite);
          in = in && (here > 0) == (opposite > 0);
        }
        if (!clear || (j >= 12 && i <= 1 && k <= 1)) continue;  // on a face, or by the small one
        EXPECT_EQ(canvas.slot_of(i, j, k) >= 0, in) << i << " " << j << " " << k;
        inside += in;
      }
  EXPECT_GT(inside, 100u);
}

// Vertices are taken to index coordinates in double: in float (meshToLevelSet's input) a box at
// UTM-like coordinates lost a whole layer of voxels.
TEST(BuildCanvas, MeshesFarFromTheOriginKeepEveryVoxel) {
  test::TempDir dir;
  const Vec3 lo(500000.3, 5000000.7, 100.1), hi(500020.3, 5000010.7, 108.1);
  test::write_box_off(dir.file("far.off"), lo, hi);
  const Canvas canvas = build("mesh:" + dir.file("far.off"), 128, test::euclidean_metric(3));
  EXPECT_EQ(canvas.active_voxel_count,
            std::size_t(canvas.dims[0]) * canvas.dims[1] * canvas.dims[2]);
}

// An L-shaped prism with hexagonal caps, scaled by `size` and moved by `offset` (plus 0.3, 0.7,
// 0.1); with
// `box_beside`, also the separate box [offset + 3, offset + 13] x [offset, offset + 10]^2.
std::string l_prism_off(double size, double offset, bool box_beside = false) {
  const double corners[12][3] = {{0, 0, 0}, {2, 0, 0}, {2, 1, 0}, {1, 1, 0}, {1, 2, 0}, {0, 2, 0},
                                 {0, 0, 1}, {2, 0, 1}, {2, 1, 1}, {1, 1, 1}, {1, 2, 1}, {0, 2, 1}};
  std::ostringstream off;
  off.precision(17);
  off << "OFF\n" << (box_beside ? 20 : 12) << " " << (box_beside ? 14 : 8) << " 0\n";
  for (const auto& c : corners)
    off << offset + 0.3 + size * c[0] << " " << offset + 0.7 + size * c[1] << " "
        << offset + 0.1 + size * c[2] << "\n";
  for (int k = 0; box_beside && k < 8; ++k)
    off << offset + (k & 1 ? 13 : 3) << " " << offset + (k & 2 ? 10 : 0) << " "
        << offset + (k & 4 ? 10 : 0) << "\n";
  off << "6 1 0 5 4 3 2\n6 8 9 10 11 6 7\n4 0 1 7 6\n4 1 2 8 7\n4 2 3 9 8\n4 3 4 10 9\n"
         "4 4 5 11 10\n4 5 0 6 11\n";
  if (box_beside)
    off << "4 12 14 15 13\n4 16 17 19 18\n4 12 13 17 16\n4 14 18 19 15\n4 12 16 18 14\n"
           "4 13 15 19 17\n";
  return off.str();
}

// Polygons are triangulated in their plane: an L-shaped cap whose fan from its first corner
// leaves the outline (and then crosses the sides), also 2 cm wide at UTM-like coordinates beside
// a larger body, and a square face with a corner on one of its sides, whose fan has a triangle of
// zero area, all bound their volume.
TEST(BuildCanvas, NonConvexAndCollinearPolygonsAreTriangulatedInside) {
  test::TempDir dir;
  test::write_text(dir.file("l.off"), l_prism_off(1, 0));
  test::write_text(dir.file("far_l.off"), l_prism_off(0.01, 5e6, true));
  test::write_text(dir.file("side.off"),
                   "OFF\n9 6 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n0 0 1\n1 0 1\n1 1 1\n0 1 1\n"
                   "0.5 0 0\n5 0 3 2 1 8\n4 4 5 6 7\n5 0 8 1 5 4\n4 1 2 6 5\n4 2 3 7 6\n"
                   "4 3 0 4 7\n");
  EXPECT_NEAR(active_volume(build("mesh:" + dir.file("l.off"), 40, test::euclidean_metric(3))), 3.0,
              0.03 * 3.0);
  // Its normal from products of absolute coordinates was rounding: an overlapping triangulation.
  EXPECT_EQ(test::error_of(
                [&] { build("mesh:" + dir.file("far_l.off"), 128, test::euclidean_metric(3)); }),
            "");
  EXPECT_NEAR(active_volume(build("mesh:" + dir.file("side.off"), 40, test::euclidean_metric(3))),
              1.0, 0.03);
}

TEST(BuildCanvas, VerticesNoFaceUsesDoNotWidenTheCanvas) {
  test::TempDir dir;
  test::write_text(dir.file("stray.off"),
                   "OFF\n9 6 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n0 0 1\n1 0 1\n1 1 1\n0 1 1\n"
                   "3 0 0\n4 0 3 2 1\n4 4 5 6 7\n4 0 1 5 4\n4 1 2 6 5\n4 2 3 7 6\n4 3 0 4 7\n");
  const Canvas canvas = build("mesh:" + dir.file("stray.off"), 32, test::euclidean_metric(3));
  EXPECT_EQ(canvas.dims, (std::array<int, 3>{32, 32, 32}));
  EXPECT_EQ(canvas.active_voxel_count, 32u * 32u * 32u);
}

TEST(BuildCanvas, ResolutionOutOfRangeIsRejected) {
  const DomainSpec box = parse_domain("box:0,0,0,1,1,1");
  for (int resolution : {0, 1, 1000000}) {
    CanvasOptions options;
    options.resolution = resolution;
    const std::string message = build_error(box, test::euclidean_metric(3), options);
    EXPECT_NE(message.find("resolution " + std::to_string(resolution)), std::string::npos)
        << message;
  }
}

TEST(BuildCanvas, HugeCanvasesAreRejectedInstantlyByTheMemoryEstimate) {
  CanvasOptions options;
  options.resolution = 65536;
  options.memory_budget = std::uint64_t{18} << 30;
  for (const std::string spec : {"box:0,0,0,1,1,1", "implicit:sphere:r=1"}) {
    const auto start = std::chrono::steady_clock::now();
    const std::string message = build_error(parse_domain(spec), test::euclidean_metric(3), options);
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    EXPECT_LT(seconds, 1.0) << spec;
    EXPECT_NE(message.find("active voxels needs ~"), std::string::npos) << message;
    EXPECT_NE(message.find("over the memory budget of 18 GiB (--memory-budget)"), std::string::npos)
        << message;
  }
  EXPECT_NE(build_error(parse_domain("box:0,0,0,1,1,1"), test::euclidean_metric(3), options)
                .find("canvas of ~2.81e+14 active voxels"),
            std::string::npos);
}

// A field that holds memory (a VDB file's grids) shares the budget with the canvas: the grids
// were checked against the whole budget, and the canvas against the same budget again.
class HeldMemoryMetric : public MetricField {
 public:
  explicit HeldMemoryMetric(std::uint64_t held) : held_(held) {}
  int dimension() const override { return 3; }
  Mat3 at(const Vec3&) const override { return Mat3::Identity(); }
  std::string description() const override { return "identity holding memory"; }
  std::uint64_t resident_bytes() const override { return held_; }

 private:
  std::uint64_t held_;
};

// What a caller's own types can claim: a metric of another dimension, a domain kind that no
// parser makes (a canvas of 4096 voxels was built from each).
class FourDimensionalMetric : public MetricField {
 public:
  int dimension() const override { return 4; }
  Mat3 at(const Vec3&) const override { return Mat3::Identity(); }
  std::string description() const override { return "four-dimensional"; }
};

TEST(BuildCanvas, AMetricOfAnotherDimensionAndAnUnknownDomainKindAreRefused) {
  CanvasOptions options;
  options.resolution = 16;
  EXPECT_NE(build_error(parse_domain("rect:0,0,1,1"), FourDimensionalMetric(), options)
                .find("metric 'four-dimensional' says it is 4D"),
            std::string::npos);
  DomainSpec unknown = parse_domain("box:0,0,0,1,1,1");
  unknown.kind = static_cast<DomainSpec::Kind>(42);
  EXPECT_NE(
      build_error(unknown, test::euclidean_metric(3), options).find("domain of unknown kind 42"),
      std::string::npos);
}

TEST(BuildCanvas, TheMetricFieldsMemoryCountsAgainstTheBudget) {
  const DomainSpec box = parse_domain("box:0,0,0,1,1,1");
  CanvasOptions options;
  options.resolution = 32;
  options.memory_budget = std::uint64_t{10} << 20;  // 10 MiB; the canvas needs ~4 MiB
  EXPECT_NO_THROW(build_canvas(box, HeldMemoryMetric(std::uint64_t{5} << 20), options));
  const std::string message = build_error(box, HeldMemoryMetric(std::uint64_t{7} << 20), options);
  EXPECT_NE(message.find("with the metric field's 7 MiB already held, over the memory budget "
                         "of 10 MiB (--memory-budget)"),
            std::string::npos)
      << message;
}

TEST(BuildCanvas, MemoryBudgetOverride) {
  const DomainSpec box = parse_domain("box:0,0,0,1,1,1");
  CanvasOptions options;
  options.resolution = 32;
  options.memory_budget = 100000;
  EXPECT_NE(build_error(box, test::euclidean_metric(3), options).find("budget of 97.7 KiB"),
            std::string::npos);
  options.memory_budget = std::uint64_t{1} << 30;
  EXPECT_EQ(build_canvas(box, test::euclidean_metric(3), options).active_voxel_count,
            32u * 32u * 32u);
  EXPECT_GT(default_memory_budget(), 0u);
  // The OpenCL engine on PoCL holds per slot the canvas (1 B of activity, 24 B of tensors unless
  // stored once), the float field (8 B) and its device buffers (17.7 B for a uniform metric,
  // 45.7 B for radial_shock_3d: rvor bench's bytes_per_voxel): the estimate covers at least that.
  EXPECT_GE(estimated_bytes_per_active_voxel(true), 1 + 8 + 17.7);
  EXPECT_GE(estimated_bytes_per_active_voxel(false), 25 + 8 + 45.7);
}

// An allocation the budget passed (here: a budget far above what the process may map) fails as
// rvor::Error naming what ran out. The tree being built must then be freed without allocating:
// ~Tree allocated, threw from a destructor, and the 2D case aborted (exit 134).
TEST(BuildCanvas, AnAllocationTheBudgetPassedFailsAsANamedError) {
  for (const char* spec : {"rect:-1,-1,1,1", "implicit:disk"}) {
    CanvasOptions options;
    options.resolution = 30000;  // ~14M leaves: gigabytes of tree
    options.memory_budget = std::uint64_t{1} << 50;
    const int code = test::exit_code_in_a_child(rlim_t{512} << 20, [&] {
      const std::string message =
          build_error(parse_domain(spec), test::euclidean_metric(2), options);
      return message.rfind("out of memory building the canvas (std::bad_alloc)", 0) == 0;
    });
    EXPECT_EQ(code, 0) << spec << ": 1: built, or another message; 134: aborted";
  }
}

// A uniform field's canvas stores its tensor once (Canvas::uniform_metric), so the estimate is
// smaller and a larger canvas fits the same budget.
TEST(BuildCanvas, UniformFieldsAreEstimatedWithoutTensorsPerVoxel) {
  const DomainSpec box = parse_domain("box:0,0,0,1,1,1");
  CanvasOptions options;
  options.resolution = 64;
  options.memory_budget = 64u * 64u * 64u * estimated_bytes_per_active_voxel(true) * 11 / 10;
  const Canvas canvas = build_canvas(box, *make_analytic_metric("euclidean", 3), options);
  EXPECT_TRUE(canvas.uniform_metric().has_value());
  // The same tensor from a field that does not say it is uniform: stored per slot.
  EXPECT_NE(build_error(box, test::euclidean_metric(3), options).find("over the memory budget"),
            std::string::npos);
}

TEST(BuildCanvas, SparseShapesAreEstimatedBelowTheirIndexBox) {
  CanvasOptions options;
  options.resolution = 128;
  // 80% of what the whole 128^3 index box needs: the sphere fills ~52% of it, and the estimate
  // from the bricks touching it stays below that.
  options.memory_budget = 128u * 128u * 128u * estimated_bytes_per_active_voxel(false) * 8 / 10;
  EXPECT_GT(build_canvas(parse_domain("implicit:sphere:r=1"), test::euclidean_metric(3), options)
                .active_voxel_count,
            1000000u);
  test::TempDir dir;
  test::write_box_off(dir.file("box.off"), Vec3(0, 0, 0), Vec3(1, 1, 1));
  options.memory_budget = 1000000;  // the coarse mesh estimate is over it
  const std::string message =
      build_error(parse_domain("mesh:" + dir.file("box.off")), test::euclidean_metric(3), options);
  // Coarse (64^3) voxels grown by one voxel: 66^3 / 64^3 of the true 128^3, 8 * 66^3.
  EXPECT_NE(message.find("canvas of ~2299968 active voxels"), std::string::npos) << message;
}

TEST(BuildCanvas, EmptyDomainsAreRejected) {
  EXPECT_NE(build_error(parse_domain("implicit:sphere:r=0"), test::euclidean_metric(3), {})
                .find("no voxel inside"),
            std::string::npos);
  DomainSpec flat;  // zero extent, built by hand (parse_domain refuses it)
  flat.kind = DomainSpec::Kind::Box;
  flat.bounds = Box{Vec3(0, 0, 0), Vec3(0, 0, 0)};
  EXPECT_NE(build_error(flat, test::euclidean_metric(3), {}).find("no voxel inside"),
            std::string::npos);
}

TEST(BuildCanvas, NonSpdMetricIsRejectedWithItsPosition) {
  const FunctionMetric bad(
      3,
      [](const Vec3& p) {
        Mat3 G = Mat3::Identity();
        if (p.x() > 0.5 && p.y() > 0.5 && p.z() > 0.5) G(1, 1) = -1;
        return G;
      },
      "bad-test-metric");
  CanvasOptions options;
  options.resolution = 16;
  const std::string message = build_error(parse_domain("box:0,0,0,1,1,1"), bad, options);
  EXPECT_NE(message.find("'bad-test-metric' at ("), std::string::npos) << message;
  EXPECT_NE(message.find("positive definite"), std::string::npos) << message;
  // The first failing brick in brick order: the (8,8,8) brick, first voxel (0.53125 = 8.5 h).
  EXPECT_NE(message.find("at (0.53125, 0.53125, 0.53125)"), std::string::npos) << message;
}

// Canvases keep tensors in float: a tensor that is SPD in double but not once rounded, or whose
// eigenvalues leave [1e-30, 1e30], is an error at its position (it used to fail later in the
// solve with "selling_decomposition: matrix [-nan ...]", or leave voxels silently unreached).
// The builder checks a tensor once while it repeats (a uniform region): each bad tensor comes
// after one, in the (8,8,8) brick, and is still checked.
TEST(BuildCanvas, TensorsThatFloatCannotHoldAreRejectedWithTheirPosition) {
  Mat3 nan_entry = Mat3::Identity();
  nan_entry(0, 1) = nan_entry(1, 0) = std::nan("");
  const std::pair<Mat3, const char*> cases[] = {
      {nan_entry, "not finite"},
      {1e-300 * Mat3::Identity(), "rounded to float"},
      {1e-40 * Mat3::Identity(), "outside [1e-30, 1e+30]"},
      {1e31 * Mat3::Identity(), "outside [1e-30, 1e+30]"},
      {1e300 * Mat3::Identity(), "does not fit in float"},
      {(Mat3() << 1, 1 - 1e-9, 0, 1 - 1e-9, 1, 0, 0, 0, 1).finished(), "rounded to float"},
      // Positive, in range, but z nearly singular next to the xy block: judged in 3D.
      {Vec3(1, 1, 1e-20).asDiagonal().toDenseMatrix(), "too anisotropic"}};
  for (const auto& [tensor, expected] : cases) {
    const FunctionMetric corner(
        3,
        [&tensor = tensor](const Vec3& p) {
          return p.x() > 0.5 && p.y() > 0.5 && p.z() > 0.5 ? tensor : Mat3::Identity();
        },
        "float-test-metric");
    CanvasOptions options;
    options.resolution = 16;
    const std::string message = build_error(parse_domain("box:0,0,0,1,1,1"), corner, options);
    EXPECT_NE(message.find("'float-test-metric' at (0.53125, 0.53125, 0.53125)"), std::string::npos)
        << message;
    EXPECT_NE(message.find(expected), std::string::npos) << message;
  }
}

TEST(BuildCanvas, TwoDimensionalMetricOnThreeDimensionalDomainIsRejected) {
  const std::string message =
      build_error(parse_domain("box:0,0,0,1,1,1"), test::euclidean_metric(2), {});
  EXPECT_NE(message.find("is 2D"), std::string::npos) << message;
}

}  // namespace
}  // namespace rvor
