// The functions that read a solved field next to its canvas refuse a field of another canvas with
// an error naming themselves (they read past its arrays before, or crashed).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <functional>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "canvas_test_support.h"
#include "rvor/canvas_output.h"
#include "rvor/canvas_png.h"
#include "rvor/field_summary.h"
#include "support/box_canvas.h"
#include "support/run_command.h"
#include "support/temp_dir.h"

namespace rvor {
namespace {

TEST(FieldOutputs, AFieldOfAnotherCanvasIsAnError) {
  const Canvas canvas =
      test::make_uniform_box_canvas(2, Vec3(-1, -1, 0), Vec3(1, 1, 0), 32, Mat3::Identity());
  const Canvas smaller =
      test::make_uniform_box_canvas(2, Vec3(-1, -1, 0), Vec3(1, 1, 0), 8, Mat3::Identity());
  VoronoiField field;
  field.distance.assign(smaller.slot_count(), 1.0f);
  field.label.assign(smaller.slot_count(), 0);
  test::TempDir dir;
  const std::vector<std::pair<std::string, std::function<void()>>> calls = {
      {"field summary", [&] { summarize_field(canvas, field, 1); }},
      {"probe", [&] { probe_field(canvas, field, {Vec3(0, 0, 0)}); }},
      {"cannot write", [&] { write_canvas_vtu(dir.file("c.vtu"), canvas, field); }},
      {"cannot write", [&] { write_canvas_png(dir.file("c.png"), canvas, field, {}, nullptr); }},
      {"field summary", [&] { summarize_field(canvas, VoronoiField{}, 1); }}};
  for (const auto& [who, call] : calls) {
    const std::string message = test::error_of(call);
    EXPECT_EQ(message.find(who), 0u) << message;
    EXPECT_NE(message.find(": the field does not match the canvas"), std::string::npos) << message;
  }
}

// Unreached voxels next to reached ones (no stencil leads them to a seed) are told apart from
// those in pieces of the canvas without seeds: the advice differs (resolution, or seeds).
TEST(FieldSummary, UnreachedVoxelsBesideReachedOnesAreCountedApart) {
  Canvas canvas =
      test::make_uniform_box_canvas(2, Vec3(-1, -1, 0), Vec3(1, 1, 0), 16, Mat3::Identity());
  VoronoiField field = test::constant_field(canvas, 1.0f, 0);
  const auto set_unreached = [&](int i, int j) {
    const auto slot = static_cast<std::size_t>(canvas.slot_of(i, j, 0));
    field.distance[slot] = std::numeric_limits<float>::infinity();
    field.label[slot] = -1;
  };
  for (int j = 0; j < 16; ++j) {  // column 10 cut out: columns 11 to 15 form a piece of their own
    canvas.active[static_cast<std::size_t>(canvas.slot_of(10, j, 0))] = 0;
    for (int i = 11; i < 16; ++i) set_unreached(i, j);
  }
  set_unreached(0, 0);  // a corner, and a pair beside the cut
  set_unreached(9, 7);
  set_unreached(8, 7);
  const FieldSummary summary = summarize_field(canvas, field, 1);
  EXPECT_EQ(summary.unreached_voxels, 5u * 16u + 3u);
  EXPECT_EQ(summary.unreached_beside_reached, 3u);
}

TEST(FieldOutputs, LabelsBeyondTheSeedsAndNonFiniteProbesAreErrors) {
  const Canvas canvas =
      test::make_uniform_box_canvas(2, Vec3(-1, -1, 0), Vec3(1, 1, 0), 16, Mat3::Identity());
  VoronoiField field = test::constant_field(canvas, 1.0f, 3);
  EXPECT_NE(test::error_of([&] { summarize_field(canvas, field, 2); }).find("has label 3"),
            std::string::npos);
  const std::string message =
      test::error_of([&] { probe_field(canvas, field, {Vec3(std::nan(""), 0, 0)}); });
  EXPECT_NE(message.find("probe point 0 has a coordinate that is not finite"), std::string::npos)
      << message;
  // A finite point far away is taken to the nearest voxel (documented), not refused.
  EXPECT_EQ(probe_field(canvas, field, {Vec3(1e300, 0, 0)}).size(), 1u);
}

// The squared index distance from a point to its nearest active voxel, by brute force.
double nearest_squared_distance(const Canvas& canvas, const Vec3& index_point) {
  double best = std::numeric_limits<double>::infinity();
  for (std::size_t slot = 0; slot < canvas.slot_count(); ++slot) {
    if (!canvas.active[slot]) continue;
    const VoxelIndex v = canvas.voxel_of(slot);
    best = std::min(best, (Vec3(v.i, v.j, v.k) - index_point).squaredNorm());
  }
  return best;
}

// Probes answer the nearest active voxel wherever they lie: inside the canvas, in a hole of it,
// on voxel boundaries (ties), and beyond it, measured from the point itself (moved onto the
// canvas's index box first, (0, 0, 5) over a ring took a voxel of its inner rim, 0.14 farther
// than one on its top).
TEST(FieldOutputs, ProbesTakeTheNearestActiveVoxelInsideAndOutsideTheCanvas) {
  for (const int dimension : {2, 3}) {
    const int resolution = dimension == 3 ? 40 : 96;
    Canvas canvas = test::make_uniform_box_canvas(dimension, Vec3(-1, -1, -0.25), Vec3(1, 1, 0.25),
                                                  resolution, Mat3::Identity());
    for (std::size_t slot = 0; slot < canvas.slot_count(); ++slot) {  // a ring: a hole, and a top
      const Vec3 x = canvas.world_of(slot);
      const double r = std::hypot(x.x(), x.y());
      canvas.active[slot] = canvas.active[slot] && r > 0.6 && r < 0.9 && x.z() < 0.1;
    }
    canvas.finalize();
    const VoronoiField field = test::constant_field(canvas, 1.0f, 0);
    std::vector<Vec3> points = {Vec3(0, 0, 5),     Vec3(0, 0, 0),     Vec3(0.3, 0.2, 0),
                                Vec3(-7, 0.5, -3), Vec3(40, -30, 20), Vec3(0.75, 0, 0.5),
                                Vec3(0, 0, -1e6)};
    std::mt19937 random(7);
    std::uniform_real_distribution<double> coordinate(-3, 3);
    for (int n = 0; n < 200; ++n)
      points.emplace_back(coordinate(random), coordinate(random), coordinate(random));
    // Points on voxel faces, edges and corners: equally near two or more voxels.
    const double h = canvas.voxel_size;
    for (int n = 0; n < 100; ++n)
      points.push_back(canvas.origin + h * Vec3(std::round(coordinate(random) / h * 2) / 2 + 0.5,
                                                std::round(coordinate(random) / h) + 0.5,
                                                std::round(coordinate(random) / h) - 0.5));
    const std::vector<ProbeSample> samples = probe_field(canvas, field, points);
    for (std::size_t n = 0; n < points.size(); ++n) {
      Vec3 p = canvas.index_coordinates(points[n]);
      if (dimension == 2) p.z() = 0.0;
      const double best = nearest_squared_distance(canvas, p);
      const double taken = (canvas.index_coordinates(samples[n].voxel_centre) - p).squaredNorm();
      // Equally near voxels (a point on a face between them) may differ by rounding alone.
      EXPECT_LE(taken, best * (1 + 1e-12))
          << dimension << "D, point " << n << " (" << points[n].transpose() << ")";
    }
    // Beyond a billion voxels a point is taken along its direction, here the same voxel.
    EXPECT_EQ(probe_field(canvas, field, {Vec3(1e300, 0.3, 0.1)})[0].voxel_centre,
              probe_field(canvas, field, {Vec3(1e6, 0.3, 0.1)})[0].voxel_centre);
  }
}

// Coordinates far from the origin keep every digit of the voxel centre (9 significant digits
// wrote 10000000.53125 as 10000000.5), and the values read back exactly.
TEST(FieldOutputs, ProbeCsvNumbersReadBackExactly) {
  test::TempDir dir;
  const ProbeSample sample{Vec3(1e7, 0, 0), Vec3(10000000.53125, -0.1, 1.0 / 3.0), 0.1f, 7};
  write_probe_csv(dir.file("probe.csv"), {sample});
  std::ifstream in(dir.file("probe.csv"));
  std::string header, row;
  std::getline(in, header);
  std::getline(in, row);
  EXPECT_EQ(row, "10000000.53125,-0.1,0.3333333333333333,0.1,7");
  double x = 0, y = 0, z = 0;
  float distance = 0;
  ASSERT_EQ(std::sscanf(row.c_str(), "%lf,%lf,%lf,%f", &x, &y, &z, &distance), 4);
  EXPECT_EQ(Vec3(x, y, z), sample.voxel_centre);
  EXPECT_EQ(distance, sample.distance);
}

// A canvas.vtu with Int32 connectivity (where it fits) and one with Int64 read back by VTK as the
// same grid: points, connectivity, labels and distances, 2D and 3D, with the field's labels and
// distances (their sums). The Int64 form is the one a
// canvas of over 2^31 corner entries gets.
TEST(FieldOutputs, VtuIndexWidthsReadBackAlike) {
  const std::string script =
      "import sys, vtk\n"
      "from vtk.util.numpy_support import vtk_to_numpy as n\n"
      "def load(f):\n"
      "    r = vtk.vtkXMLUnstructuredGridReader(); r.SetFileName(f); r.Update()\n"
      "    return r.GetOutput()\n"
      "a, b = load(sys.argv[1]), load(sys.argv[2])\n"
      "same = lambda x, y: x.shape == y.shape and (x == y).all()\n"
      "print(a.GetNumberOfCells(), a.GetNumberOfPoints(),\n"
      "      same(n(a.GetPoints().GetData()), n(b.GetPoints().GetData())),\n"
      "      same(n(a.GetCells().GetConnectivityArray()), "
      "n(b.GetCells().GetConnectivityArray())),\n"
      "      same(n(a.GetCellData().GetArray('label')), n(b.GetCellData().GetArray('label'))),\n"
      "      same(n(a.GetCellData().GetArray('distance')), "
      "n(b.GetCellData().GetArray('distance'))),\n"
      "      int(n(a.GetCellData().GetArray('label')).sum()),\n"
      "      float(n(a.GetCellData().GetArray('distance')).astype('float64').sum()))\n";
  test::TempDir dir;
  for (const int dimension : {2, 3}) {
    SCOPED_TRACE(std::to_string(dimension) + "D");
    Canvas canvas = test::make_uniform_box_canvas(dimension, Vec3(-1, -1, -1), Vec3(1, 1, 1), 12,
                                                  Mat3::Identity());
    canvas.active[0] = 0;  // a corner shared by fewer cells
    canvas.finalize();
    VoronoiField field;
    field.distance.resize(canvas.slot_count());
    field.label.resize(canvas.slot_count());
    for (std::size_t slot = 0; slot < canvas.slot_count(); ++slot) {
      field.distance[slot] = 0.5f * static_cast<float>(slot);
      field.label[slot] = static_cast<int32_t>(slot % 7);
    }
    write_canvas_vtu(dir.file("narrow.vtu"), canvas, field);
    write_canvas_vtu(dir.file("wide.vtu"), canvas, field, VtuIndices::int64);
    EXPECT_NE(test::read_text(dir.file("narrow.vtu")).find("type=\"Int32\" Name=\"connectivity\""),
              std::string::npos);
    EXPECT_NE(test::read_text(dir.file("wide.vtu")).find("type=\"Int64\" Name=\"connectivity\""),
              std::string::npos);
    const test::CommandResult result = test::run_python_script(
        dir.file("compare.py"), script, dir.file("narrow.vtu") + " " + dir.file("wide.vtu"));
    ASSERT_EQ(result.exit_code, 0) << result.err;
    // The cell data as the field holds it (halves and small integers: the sums are exact).
    long label_sum = 0;
    double distance_sum = 0;
    for (std::size_t slot = 0; slot < canvas.slot_count(); ++slot)
      if (canvas.active[slot]) label_sum += field.label[slot], distance_sum += field.distance[slot];
    char sums[64];
    std::snprintf(sums, sizeof sums, " %ld %.1f\n", label_sum, distance_sum);
    const std::size_t cells = canvas.active_voxel_count;
    const std::size_t points = dimension == 3 ? 13 * 13 * 13 - 1 : 13 * 13 - 1;
    EXPECT_EQ(result.out,
              std::to_string(cells) + " " + std::to_string(points) + " True True True True" + sums);
  }
}

// A canvas far from the origin (at 1e5, voxels of 0.01875) would have its corners rounded to floats
// 0.0078 apart: its points are written as doubles, and VTK reads every corner column apart at the
// voxel size. Near the origin they stay floats (half the bytes).
TEST(FieldOutputs, VtuPointsFarFromTheOriginStayApart) {
  const std::string script =
      "import sys, vtk\n"
      "from vtk.util.numpy_support import vtk_to_numpy as n\n"
      "r = vtk.vtkXMLUnstructuredGridReader(); r.SetFileName(sys.argv[1]); r.Update()\n"
      "p = n(r.GetOutput().GetPoints().GetData()).astype('float64')\n"
      "xs = sorted(set(p[:, 0].tolist()))\n"
      "steps = [b - a for a, b in zip(xs, xs[1:])]\n"
      "print(len(xs), '%.6f %.6f' % (min(steps), max(steps)))\n";
  test::TempDir dir;
  for (const double at : {0.0, 1e5}) {
    SCOPED_TRACE("canvas at " + std::to_string(at));
    const Canvas canvas = test::make_uniform_box_canvas(
        2, Vec3(at, at, 0), Vec3(at + 0.3, at + 0.3, 0), 16, Mat3::Identity());
    VoronoiField field = test::constant_field(canvas, 1.0f, 0);
    write_canvas_vtu(dir.file("far.vtu"), canvas, field);
    const std::string type = at > 0 ? "Float64" : "Float32";
    EXPECT_NE(test::read_text(dir.file("far.vtu")).find("<Points>\n<DataArray type=\"" + type),
              std::string::npos);
    const test::CommandResult result =
        test::run_python_script(dir.file("columns.py"), script, dir.file("far.vtu"));
    ASSERT_EQ(result.exit_code, 0) << result.err;
    EXPECT_EQ(result.out, "17 0.018750 0.018750\n");
  }
}

}  // namespace
}  // namespace rvor
