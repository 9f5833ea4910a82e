#include <gtest/gtest.h>
#include <sys/stat.h>

#include "canvas_test_support.h"

#include <cmath>
#include <csignal>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iterator>
#include <limits>
#include <string>
#include <utility>
#include <vector>

#include "rvor/canvas_builder.h"
#include "rvor/error.h"
#include "rvor/metric_field.h"
#include "rvor/vdb_io.h"
#include "support/box_canvas.h"
#include "support/limited_child.h"
#include "support/temp_dir.h"

namespace rvor {
namespace {

using test::error_of;

// A Voronoi field with finite values, unreached voxels (+inf, -1) and negative labels.
VoronoiField sample_field(const Canvas& canvas) {
  VoronoiField field = test::constant_field(canvas, std::numeric_limits<float>::infinity(), -1);
  for (std::size_t slot = 0; slot < canvas.slot_count(); ++slot) {
    if (!canvas.active[slot] || slot % 11 == 0) continue;
    field.distance[slot] = static_cast<float>(canvas.world_of(slot).norm());
    field.label[slot] = static_cast<int32_t>(slot % 7);
  }
  return field;
}

void expect_voronoi_round_trip(const Canvas& canvas) {
  test::TempDir dir;
  const VoronoiField field = sample_field(canvas);
  write_voronoi_vdb(dir.file("voronoi.vdb"), canvas, field);
  const VoronoiField read = read_voronoi_vdb(dir.file("voronoi.vdb"), canvas);
  EXPECT_EQ(read.distance, field.distance);
  EXPECT_EQ(read.label, field.label);
  std::size_t files = 0;
  for (const auto& entry : std::filesystem::directory_iterator(dir.path()))
    files += !entry.is_directory();
  EXPECT_EQ(files, 1u);  // no temporary left behind
}

TEST(VdbIo, VoronoiRoundTrip3D) {
  expect_voronoi_round_trip(
      test::make_uniform_box_canvas(3, Vec3(-1, 0, 0), Vec3(1, 0.5, 0.7), 20, Mat3::Identity()));
}

TEST(VdbIo, VoronoiRoundTrip2D) {
  expect_voronoi_round_trip(
      test::make_uniform_box_canvas(2, Vec3(0, 0, 0), Vec3(1, 3, 0), 30, Mat3::Identity()));
}

TEST(VdbIo, VoronoiFileHasTheCanvasPlacement) {
  test::TempDir dir;
  const Canvas canvas =
      test::make_uniform_box_canvas(3, Vec3(0, 0, 0), Vec3(1, 1, 1), 8, Mat3::Identity());
  write_voronoi_vdb(dir.file("v.vdb"), canvas, sample_field(canvas));
  const Canvas other =
      test::make_uniform_box_canvas(3, Vec3(0, 0, 0), Vec3(1, 1, 1), 16, Mat3::Identity());
  EXPECT_NE(
      error_of([&] { read_voronoi_vdb(dir.file("v.vdb"), other); }).find("voxel size and origin"),
      std::string::npos);
  VoronoiField wrong;
  EXPECT_NE(error_of([&] { write_voronoi_vdb(dir.file("w.vdb"), canvas, wrong); }).find("w.vdb"),
            std::string::npos);
}

// A field of another canvas with the same voxel size and origin is refused: its gaps were filled
// with +inf and its extra voxels dropped, silently.
TEST(VdbIo, AFieldOfAnotherCanvasOfTheSamePlacementIsRefused) {
  test::TempDir dir;
  const Canvas cube =
      test::make_uniform_box_canvas(3, Vec3(0, 0, 0), Vec3(1, 1, 1), 8, Mat3::Identity());
  const Canvas tall =
      test::make_uniform_box_canvas(3, Vec3(0, 0, 0), Vec3(1, 1, 2), 16, Mat3::Identity());
  ASSERT_EQ(tall.voxel_size, cube.voxel_size);
  write_voronoi_vdb(dir.file("cube.vdb"), cube, sample_field(cube));
  write_voronoi_vdb(dir.file("tall.vdb"), tall, sample_field(tall));
  EXPECT_NE(error_of([&] {
              read_voronoi_vdb(dir.file("cube.vdb"), tall);
            }).find("holds a field of 512 voxels, the canvas has 1024 active ones"),
            std::string::npos);
  EXPECT_NE(error_of([&] {
              read_voronoi_vdb(dir.file("tall.vdb"), cube);
            }).find("holds a field of 1024 voxels, the canvas has 512 active ones"),
            std::string::npos);
}

Mat3 linear_in_x(const Vec3& p) {
  Mat3 G;
  G << 2 + p.x(), 0.25, 0.1, 0.25, 3 - 0.5 * p.x(), 0.2, 0.1, 0.2, 4;
  return G;
}

TEST(VdbIo, MetricRoundTripUniform) {
  test::TempDir dir;
  Mat3 G;
  G << 3, 0.5, 0.25, 0.5, 2, -0.125, 0.25, -0.125, 1.5;
  const Canvas canvas = test::make_uniform_box_canvas(3, Vec3(0, 0, 0), Vec3(1, 2, 1), 16, G);
  write_metric_vdb(dir.file("metric.vdb"), canvas);
  const auto field = load_vdb_metric(dir.file("metric.vdb"));
  EXPECT_EQ(field->dimension(), 3);
  EXPECT_EQ(field->description(), "vdb:" + dir.file("metric.vdb"));
  // Inside, and up to half a voxel beyond the outermost voxel centres (the domain's surface).
  for (const Vec3& p : {Vec3(0.5, 1, 0.5), Vec3(0.13, 1.71, 0.02), Vec3(0, 0, 0), Vec3(1, 2, 1)})
    EXPECT_TRUE(field->at(p).isApprox(G, 1e-6)) << p.transpose() << "\n" << field->at(p);
  ASSERT_TRUE(field->natural_domain().has_value());
  EXPECT_TRUE(field->natural_domain()->hi.isApprox(Vec3(1, 2, 1), 1e-9));
}

TEST(VdbIo, MetricRoundTripLinearInX) {
  test::TempDir dir;
  const Canvas canvas = test::make_box_canvas(3, Vec3(-1, 0, 0), Vec3(1, 1, 1), 32, linear_in_x);
  write_metric_vdb(dir.file("metric.vdb"), canvas);
  const auto field = load_vdb_metric(dir.file("metric.vdb"));
  // Trilinear interpolation reproduces a linear field between voxel centres.
  for (const Vec3& p : {Vec3(-0.9, 0.3, 0.4), Vec3(0.123, 0.5, 0.77), Vec3(0.95, 0.9, 0.1)})
    EXPECT_TRUE(field->at(p).isApprox(linear_in_x(p), 1e-5)) << p.transpose();
}

TEST(VdbIo, CanvasBuiltOnAVdbMetricReproducesIt) {
  test::TempDir dir;
  const Canvas canvas = test::make_box_canvas(3, Vec3(-1, 0, 0), Vec3(1, 1, 1), 24, linear_in_x);
  write_metric_vdb(dir.file("metric.vdb"), canvas);
  const auto field = load_vdb_metric(dir.file("metric.vdb"));
  CanvasOptions options;
  options.resolution = 24;
  const Canvas rebuilt = build_canvas(parse_domain("box:-1,0,0,1,1,1"), *field, options);
  ASSERT_EQ(rebuilt.slot_count(), canvas.slot_count());
  for (std::size_t slot = 0; slot < canvas.slot_count(); ++slot)
    for (int n = 0; n < 6; ++n)
      ASSERT_NEAR(rebuilt.metric_of(slot)[n], canvas.metric_of(slot)[n], 1e-5) << slot << " " << n;
  EXPECT_NE(rebuilt.description.find("vdb:"), std::string::npos);
}

TEST(VdbIo, MetricRoundTrip2D) {
  test::TempDir dir;
  const auto planar = [](const Vec3& p) {
    Mat3 G = Mat3::Identity();
    G(0, 0) = 2 + p.x();
    G(0, 1) = G(1, 0) = 0.5;
    G(1, 1) = 3;
    return G;
  };
  const Canvas canvas = test::make_box_canvas(2, Vec3(0, 0, 0), Vec3(2, 1, 0), 32, planar);
  write_metric_vdb(dir.file("metric2d.vdb"), canvas);
  const auto field = load_vdb_metric(dir.file("metric2d.vdb"));
  EXPECT_EQ(field->dimension(), 2);
  EXPECT_TRUE(field->at(Vec3(0.7, 0.4, 0)).isApprox(planar(Vec3(0.7, 0.4, 0)), 1e-5));
  EXPECT_TRUE(field->at(Vec3(1.3, 0.6, 5)).isApprox(planar(Vec3(1.3, 0.6, 0)), 1e-5));  // z ignored
}

// Every stored tensor is checked when the file is read, not only those a canvas samples; and a
// domain that reaches beyond the stored values is named, not read as the background 0 tensor.
TEST(VdbIo, BadStoredTensorsAndUncoveredPointsAreNamed) {
  test::TempDir dir;
  Canvas canvas = test::make_box_canvas(3, Vec3(0, 0, 0), Vec3(1, 1, 1), 16, linear_in_x);
  std::size_t slot = 0;
  while (!canvas.active[slot]) ++slot;
  canvas.mutable_metric(slot + 37)[0] = -1.0f;  // m11 < 0 at one voxel
  write_metric_vdb(dir.file("bad.vdb"), canvas);
  const std::string bad = error_of([&] { load_vdb_metric(dir.file("bad.vdb")); });
  EXPECT_NE(bad.find("bad.vdb at voxel"), std::string::npos) << bad;
  EXPECT_NE(bad.find("not symmetric positive definite"), std::string::npos) << bad;

  const Canvas good = test::make_box_canvas(3, Vec3(0, 0, 0), Vec3(1, 1, 1), 16, linear_in_x);
  write_metric_vdb(dir.file("good.vdb"), good);
  const auto field = load_vdb_metric(dir.file("good.vdb"));
  CanvasOptions options;
  options.resolution = 16;
  const std::string uncovered =
      error_of([&] { build_canvas(parse_domain("box:0,0,0,2,1,1"), *field, options); });
  EXPECT_NE(uncovered.find("does not cover"), std::string::npos) << uncovered;
}

TEST(VdbIo, MissingFilesAndGridsAreNamed) {
  test::TempDir dir;
  const std::string missing = error_of([&] { load_vdb_metric(dir.file("none.vdb")); });
  EXPECT_NE(missing.find("none.vdb"), std::string::npos) << missing;

  const Canvas canvas =
      test::make_uniform_box_canvas(3, Vec3(0, 0, 0), Vec3(1, 1, 1), 8, Mat3::Identity());
  write_voronoi_vdb(dir.file("voronoi.vdb"), canvas, sample_field(canvas));
  const std::string no_metric = error_of([&] { load_vdb_metric(dir.file("voronoi.vdb")); });
  EXPECT_NE(no_metric.find("voronoi.vdb has no grid 'm11'"), std::string::npos) << no_metric;

  write_metric_vdb(dir.file("metric.vdb"), canvas);
  const std::string no_distance =
      error_of([&] { read_voronoi_vdb(dir.file("metric.vdb"), canvas); });
  EXPECT_NE(no_distance.find("metric.vdb has no grid 'distance'"), std::string::npos)
      << no_distance;

  test::write_text(dir.file("garbage.vdb"), "not a vdb file");
  EXPECT_NE(error_of([&] { load_vdb_metric(dir.file("garbage.vdb")); }).find("garbage.vdb"),
            std::string::npos);
}

// Writing the field's grids runs out of memory (a limit far below what a 2D canvas's leaves take:
// a 2D brick is an 8^3 OpenVDB leaf): the failure leaves write_voronoi_vdb as an exception, not an
// abort. (Unlike the canvas's tree, whose ~Tree aborted at such a failure, the grids' leaves are
// freed first, with the vector fill_active builds them in, so their trees' teardown finds room.)
TEST(VdbIo, AWriteThatRunsOutOfMemoryFailsAsAnException) {
  const Canvas canvas =
      test::make_uniform_box_canvas(2, Vec3(-1, -1, 0), Vec3(1, 1, 0), 4096, Mat3::Identity());
  VoronoiField field = test::constant_field(canvas, 1.0f, 0);
  test::TempDir dir;
  const int code = test::exit_code_in_a_child(rlim_t{256} << 20, [&] {
    try {
      write_voronoi_vdb(dir.file("field.vdb"), canvas, field);
    } catch (const std::exception&) {
      return true;
    }
    return false;  // written: the limit did not bite
  });
  EXPECT_EQ(code, 0) << "1: written within the limit; 134: aborted";
}

// The file is read more than once: a pipe (`--metric-vdb <(cat m.vdb)`) failed with
// "basic_ios::clear: iostream error", naming nothing.
TEST(VdbIo, APipeIsRefusedAsNotARegularFile) {
  test::TempDir dir;
  ASSERT_EQ(mkfifo(dir.file("pipe.vdb").c_str(), 0600), 0);
  const std::string pipe = error_of([&] { load_vdb_metric(dir.file("pipe.vdb")); });
  EXPECT_NE(
      pipe.find("cannot read VDB file " + dir.file("pipe.vdb") + ": not a regular file (a pipe: "),
      std::string::npos)
      << pipe;
  const std::string device = error_of([&] { load_vdb_metric("/dev/null"); });
  EXPECT_NE(device.find("/dev/null: not a regular file (a device"), std::string::npos) << device;
}

// Writes the identity metric of the unit box at `resolution` to `path`; returns its size.
std::string file_bytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

std::uintmax_t write_identity_metric_vdb(const std::string& path, int resolution) {
  write_metric_vdb(path, test::make_uniform_box_canvas(3, Vec3(0, 0, 0), Vec3(1, 1, 1), resolution,
                                                       Mat3::Identity()));
  return std::filesystem::file_size(path);
}

// The file is read whole before its voxels can be counted, so one larger than the memory budget
// is refused before it is read.
TEST(VdbIo, AFileLargerThanTheBudgetIsRefusedBeforeItIsRead) {
  test::TempDir dir;
  const auto size = write_identity_metric_vdb(dir.file("metric.vdb"), 16);
  const std::string message = error_of([&] { load_vdb_metric(dir.file("metric.vdb"), size / 2); });
  EXPECT_NE(message.find("over the memory budget"), std::string::npos) << message;
  EXPECT_NE(message.find("even before its grids are decompressed"), std::string::npos) << message;
  EXPECT_NO_THROW(load_vdb_metric(dir.file("metric.vdb"), 64 * size));
}

// OpenVDB's writer records each grid's active voxel count (file_voxel_count), and the budget
// takes it before any value is read: a small file of constant grids took ten times its size
// before the count after reading refused it. A file whose records claim more voxels than its
// grids hold is refused with the recorded count, though its values would fit.
TEST(VdbIo, RecordedVoxelCountsAreCheckedBeforeTheValuesAreRead) {
  test::TempDir dir;
  const auto size = write_identity_metric_vdb(dir.file("metric.vdb"), 16);
  EXPECT_NO_THROW(load_vdb_metric(dir.file("metric.vdb"), 64 * size));
  std::string bytes = file_bytes(dir.file("metric.vdb"));
  const std::string key = "file_voxel_count";
  int patched = 0;
  for (std::size_t at = bytes.find(key); at != std::string::npos; at = bytes.find(key, at + 1)) {
    // The type name "int64" and the value's size (8) follow, each after a 32-bit length.
    const std::size_t value = at + key.size() + 4 + 5 + 4;
    const std::int64_t claimed = 1000000000;
    std::memcpy(&bytes[value], &claimed, sizeof claimed);
    ++patched;
  }
  ASSERT_EQ(patched, 6);
  std::ofstream(dir.file("claimed.vdb"), std::ios::binary) << bytes;
  const std::string message =
      error_of([&] { load_vdb_metric(dir.file("claimed.vdb"), 64 * size); });
  EXPECT_NE(message.find("its six grids record (as written) 6e+09 active voxels"),
            std::string::npos)
      << message;
}

// OpenVDB's reader trusts the sizes inside a grid's voxel data, and single flipped bits there
// corrupted its heap: the process aborted (these six of 378 random flips of this file, with
// Debian 12's OpenVDB 10.0). The file is read in a child process first, whose death becomes an
// error, so none of them takes the caller down.
TEST(VdbIo, AFileThatKillsOpenVdbsReaderIsAnErrorNotACrash) {
  test::TempDir dir;
  write_identity_metric_vdb(dir.file("metric.vdb"), 16);
  const std::string bytes = file_bytes(dir.file("metric.vdb"));
  const std::pair<std::size_t, int> flips[] = {{32680, 0}, {9428, 2}, {67525, 5},
                                               {67763, 2}, {9331, 5}, {67723, 1}};
  int died = 0;
  for (const auto& [offset, bit] : flips) {
    ASSERT_LT(offset, bytes.size());
    std::string flipped = bytes;
    flipped[offset] = static_cast<char>(flipped[offset] ^ (1 << bit));
    std::ofstream(dir.file("flipped.vdb"), std::ios::binary) << flipped;
    try {
      load_vdb_metric(dir.file("flipped.vdb"));
    } catch (const Error& e) {
      died += std::string(e.what()).find("OpenVDB's reader died on its voxel data") !=
              std::string::npos;
    }
  }
  EXPECT_GT(died, 0) << "no flip killed the reader: the file's layout changed";
}

// The child's verdict comes through its pipe, not its exit status, which a caller that ignores
// SIGCHLD (or reaps its children itself) never gets: there the guard turned itself off and the
// damaged file killed the process.
TEST(VdbIo, TheReadIsGuardedWhenTheCallerIgnoresItsChildren) {
  test::TempDir dir;
  write_identity_metric_vdb(dir.file("metric.vdb"), 16);
  std::string bytes = file_bytes(dir.file("metric.vdb"));
  ASSERT_GT(bytes.size(), 32680u);
  bytes[32680] = static_cast<char>(bytes[32680] ^ 1);  // one of the flips above
  std::ofstream(dir.file("flipped.vdb"), std::ios::binary) << bytes;
  const auto previous = std::signal(SIGCHLD, SIG_IGN);
  const std::string message = error_of([&] { load_vdb_metric(dir.file("flipped.vdb")); });
  std::signal(SIGCHLD, previous);
  EXPECT_NE(message.find("OpenVDB's reader died on its voxel data"), std::string::npos) << message;
}

// A file cut short: OpenVDB read a string length past its end and allocated that garbage length;
// its message, a string of that many blanks, reached gigabytes.
TEST(VdbIo, ATruncatedFileIsNamedAsSuchInOneShortMessage) {
  test::TempDir dir;
  const auto size = write_identity_metric_vdb(dir.file("metric.vdb"), 8);
  for (const std::uintmax_t cut : {std::uintmax_t{1}, std::uintmax_t{16}, size / 2, size - 60}) {
    std::filesystem::copy_file(dir.file("metric.vdb"), dir.file("cut.vdb"),
                               std::filesystem::copy_options::overwrite_existing);
    std::filesystem::resize_file(dir.file("cut.vdb"), size - cut);
    const std::string message = error_of([&] { load_vdb_metric(dir.file("cut.vdb")); });
    EXPECT_NE(message.find("cannot read VDB file " + dir.file("cut.vdb")), std::string::npos)
        << "cut " << cut << ": " << message.substr(0, 300);
    EXPECT_LT(message.size(), 400u) << "cut " << cut;
  }
}

// A canvas without placement (a default Canvas: voxel size 0) is an rvor::Error; OpenVDB's own
// exception escaped ("Non-zero scale values required").
TEST(VdbIo, ACanvasWithoutPlacementIsRefused) {
  const Canvas unplaced;
  const VoronoiField field;
  for (const auto& call : std::vector<std::function<void()>>{
           [&] { write_voronoi_vdb("/tmp/never-written.vdb", unplaced, field); },
           [&] { write_metric_vdb("/tmp/never-written.vdb", unplaced); },
           [&] { read_voronoi_vdb("/tmp/never-read.vdb", unplaced); }}) {
    try {
      call();
      ADD_FAILURE() << "no error";
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find("the canvas has no placement"), std::string::npos)
          << e.what();
    }
  }
}

}  // namespace
}  // namespace rvor
