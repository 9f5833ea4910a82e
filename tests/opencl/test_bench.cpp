// rvor bench's library function and its OpenVDB FastSweeping baseline: consistent numbers on a
// small case, FastSweeping distances and labels against the exact nearest seed, the CLI's JSON.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "fastsweeping_baseline.h"
#include "rvor/benchmark.h"
#include "rvor/canvas_builder.h"
#include "rvor/domain.h"
#include "rvor/error.h"
#include "rvor/metric_field.h"
#include "rvor/opencl_propagator.h"
#include "rvor/seeds.h"
#include "support/run_command.h"

namespace rvor {
namespace {

#define REQUIRE_OPENCL_DEVICE()                              \
  try {                                                      \
    make_opencl_propagator("auto");                          \
  } catch (const Error& e) {                                 \
    GTEST_SKIP() << "no usable OpenCL device: " << e.what(); \
  }

struct NearestSeeds {
  double first = std::numeric_limits<double>::infinity();
  double second = std::numeric_limits<double>::infinity();
  int label = -1;
};

NearestSeeds nearest_seeds(const Vec3& p, const std::vector<Vec3>& seeds) {
  NearestSeeds n;
  for (std::size_t s = 0; s < seeds.size(); ++s) {
    const double d = (p - seeds[s]).norm();
    if (d < n.first) {
      n.second = n.first;
      n.first = d;
      n.label = static_cast<int>(s);
    } else {
      n.second = std::min(n.second, d);
    }
  }
  return n;
}

Canvas unit_box_canvas(int resolution) {
  CanvasOptions options;
  options.resolution = resolution;
  return build_canvas(parse_domain("box:-1,-1,-1,1,1,1"), *make_analytic_metric("euclidean", 3),
                      options);
}

TEST(FastSweepingBaseline, DistanceIsEuclideanAndLabelIsNearestSeedAwayFromBisectors) {
  const Canvas canvas = unit_box_canvas(32);
  const std::vector<Vec3> seeds = random_seeds(canvas, 20, 7);
  const baseline::FastSweepingRun run = baseline::fast_sweeping_voronoi(canvas, seeds);
  const double h = canvas.voxel_size;
  double worst_error = 0, total_error = 0;
  std::size_t checked_labels = 0, wrong_labels = 0;
  for (std::size_t slot = 0; slot < canvas.slot_count(); ++slot) {
    if (!canvas.active[slot]) continue;
    const NearestSeeds exact = nearest_seeds(canvas.world_of(slot), seeds);
    const double error = std::abs(run.field.distance[slot] - exact.first);
    worst_error = std::max(worst_error, error);
    total_error += error;
    // First-order sweeping overestimates oblique distances by up to about a voxel, which moves
    // bisectors by as much: labels are only checked three voxels away from them.
    if (exact.second - exact.first < 3 * h) continue;
    ++checked_labels;
    if (run.field.label[slot] != exact.label) ++wrong_labels;
  }
  EXPECT_LT(worst_error, 1.5 * h);
  EXPECT_LT(total_error / double(canvas.active_voxel_count), h);
  EXPECT_GT(checked_labels, canvas.active_voxel_count / 4);
  EXPECT_EQ(wrong_labels, 0u);
  EXPECT_GT(run.sweep_seconds, 0);
  EXPECT_GT(run.swept_voxels, canvas.active_voxel_count / 2);
}

// The euclidean box at `resolution` with `seeds` seeds.
BenchCase small_case(int resolution, std::size_t seeds) {
  BenchCase c;
  c.resolution = resolution;
  c.seeds = seeds;
  return c;
}

// Insertions through Propagator::insert with a copy of the solved field (--checked-insert) run
// and are timed. (Both paths give the same field and counts: only their times tell them apart.)
TEST(RunBenchmarkCase, CheckedInsertionsAreTimedToo) {
  REQUIRE_OPENCL_DEVICE();
  BenchCase c = small_case(24, 10);
  c.inserted_seeds = 3;
  c.checked_insert = true;
  c.reference = c.fastsweeping = false;
  const BenchResult r = run_benchmark_case(c);
  ASSERT_TRUE(r.insert_mean_seconds && r.insert_mean_rounds);
  EXPECT_GT(*r.insert_mean_seconds, 0);
  EXPECT_GE(*r.insert_mean_rounds, 1.0);
}

// On the reference (--device cpu) an insertion is timed, but it pops a queue: no rounds to report
// (it gave its pops as rounds, and 0 s in them).
TEST(RunBenchmarkCase, ReferenceInsertionsHaveNoRounds) {
  BenchCase c = small_case(24, 10);
  c.device = "cpu";
  c.inserted_seeds = 3;
  c.reference = c.fastsweeping = false;
  const BenchResult r = run_benchmark_case(c);
  ASSERT_TRUE(r.insert_mean_seconds);
  EXPECT_FALSE(r.insert_mean_rounds);
  EXPECT_FALSE(r.insert_mean_round_seconds);
}

// Insertions of several seeds each (--insert-batch), the last taking what is left.
TEST(RunBenchmarkCase, InsertionsInBatches) {
  REQUIRE_OPENCL_DEVICE();
  BenchCase c = small_case(24, 10);
  c.inserted_seeds = 5;
  c.insert_batch = 2;
  c.reference = c.fastsweeping = false;
  const BenchResult r = run_benchmark_case(c);
  EXPECT_EQ(r.insertions, 3u);  // 2, 2 and 1 seeds
  ASSERT_TRUE(r.insert_mean_seconds && r.insert_max_seconds);
  EXPECT_GT(*r.insert_mean_seconds, 0);
  EXPECT_GE(*r.insert_max_seconds, *r.insert_mean_seconds);
}

TEST(RunBenchmarkCase, SmallCaseGivesConsistentPositiveNumbers) {
  REQUIRE_OPENCL_DEVICE();
  BenchCase c = small_case(32, 20);
  c.inserted_seeds = 2;
  const BenchResult r = run_benchmark_case(c);
  EXPECT_EQ(r.active_voxels, 32u * 32 * 32);
  EXPECT_NEAR(r.max_anisotropy, 1.0, 1e-9);
  EXPECT_GT(r.seconds, 0);
  EXPECT_NEAR(r.voxels_per_second * r.seconds, double(r.active_voxels), 1e-6 * r.active_voxels);
  EXPECT_GE(r.updates_per_voxel, 1.0);
  EXPECT_NEAR(r.updates_per_voxel, double(r.voxel_updates) / double(r.active_voxels), 1e-12);
  // Every brick gets values, so it is relaxed at least once; a relaxation evaluates each of its
  // 512 voxels at most once per sweep, and every brick of this box is full.
  EXPECT_GE(r.visits_per_relaxation, 1u);
  EXPECT_GE(r.relaxations_per_brick, 1.0);
  EXPECT_LE(r.updates_per_voxel,
            static_cast<double>(r.visits_per_relaxation) * r.relaxations_per_brick);
  // A uniform metric: state 8 + stamps 8 B per slot, a scratch of one brick colour class (8 B / 8),
  // an activity bit, one stencil and small tables (device_canvas.h).
  EXPECT_GE(r.bytes_per_voxel, 17.0);
  EXPECT_LT(r.bytes_per_voxel, 18.0);
  ASSERT_TRUE(r.insert_mean_seconds && r.insert_max_seconds && r.insert_fraction);
  EXPECT_GT(*r.insert_mean_seconds, 0);
  EXPECT_GE(*r.insert_max_seconds, *r.insert_mean_seconds);
  EXPECT_NEAR(*r.insert_fraction, *r.insert_mean_seconds / r.seconds, 1e-9 * *r.insert_fraction);
  ASSERT_TRUE(r.insert_mean_round_seconds);
  EXPECT_GT(*r.insert_mean_round_seconds, 0);
  EXPECT_LT(*r.insert_mean_round_seconds, *r.insert_mean_seconds);
  ASSERT_TRUE(r.insert_mean_rounds);
  EXPECT_GE(*r.insert_mean_rounds, 1.0);
  ASSERT_TRUE(r.fastsweeping_voxels_per_second && r.fastsweeping_ratio);
  EXPECT_GT(*r.fastsweeping_voxels_per_second, 0);
  EXPECT_NEAR(*r.fastsweeping_ratio, r.voxels_per_second / *r.fastsweeping_voxels_per_second,
              1e-9 * *r.fastsweeping_ratio);
  EXPECT_GT(*r.fastsweeping_label_agreement, 0.9);  // isotropic: the same cells up to bisectors
  ASSERT_TRUE(r.cpu_reference_voxels_per_second && r.reference_ratio);
  EXPECT_GT(*r.cpu_reference_voxels_per_second, 0);
  // Agreement with the reference is test_opencl's subject; here only that it was measured.
  EXPECT_TRUE(r.reference_max_relative_difference && r.reference_label_mismatches);
}

TEST(RunBenchmarkCase, VaryingMetricStaysUnder64BytesPerVoxel) {
  REQUIRE_OPENCL_DEVICE();
  BenchCase c = small_case(32, 20);
  c.domain = "box:1,1,1,11,11,11";
  c.metric = "radial_shock_3d";
  c.reference = false;
  c.fastsweeping = false;
  const BenchResult r = run_benchmark_case(c);
  // Per slot: state 8 + stamps 8 + stencil record 28 (6 float weights, a shape index); a scratch
  // of one brick colour class (8 B / 8), an activity bit, the shape table (18 B per distinct
  // offset set: ~0.6 B per voxel at 32^3) and small tables.
  EXPECT_GE(r.bytes_per_voxel, 45.0);
  EXPECT_LT(r.bytes_per_voxel, 48.0);
}

TEST(RunBenchmarkCase, OptionalBaselinesCanBeSkipped) {
  BenchCase c = small_case(16, 5);
  c.device = "cpu";
  c.fastsweeping = false;
  const BenchResult r = run_benchmark_case(c);
  EXPECT_FALSE(r.fastsweeping_voxels_per_second);
  EXPECT_EQ(r.device_bytes, 0u);
  ASSERT_TRUE(r.reference_ratio);
  EXPECT_EQ(*r.reference_ratio, 1.0);  // the engine is the reference
}

TEST(BenchCommand, JsonHasTheRequiredKeysPerCase) {
  REQUIRE_OPENCL_DEVICE();
  const test::CommandResult result = test::run_command(
      test::rvor_binary() + " bench --resolution 24 --seeds 10 --insert 1 --json --quiet");
  ASSERT_EQ(result.exit_code, 0) << result.err;
  const nlohmann::json report = nlohmann::json::parse(result.out);
  ASSERT_EQ(report.at("cases").size(), 2u);
  const std::vector<std::string> required = {"metric",
                                             "resolution",
                                             "seeds",
                                             "device",
                                             "voxels_per_second",
                                             "updates_per_voxel",
                                             "relaxations_per_brick",
                                             "visits_per_relaxation",
                                             "bytes_per_voxel",
                                             "fastsweeping_voxels_per_second",
                                             "cpu_reference_voxels_per_second",
                                             "variant",
                                             "front_step",
                                             "repeat"};
  for (const nlohmann::json& c : report["cases"]) {
    for (const std::string& key : required) EXPECT_TRUE(c.contains(key)) << key;
    EXPECT_EQ(c.at("resolution"), 24);
    EXPECT_EQ(c.at("seeds"), 10);
    EXPECT_GT(c.at("voxels_per_second").get<double>(), 0);
    EXPECT_GT(c.at("fastsweeping_voxels_per_second").get<double>(), 0);
    EXPECT_GT(c.at("cpu_reference_voxels_per_second").get<double>(), 0);
    EXPECT_EQ(c.at("inserted_seeds"), 1);
    EXPECT_EQ(c.at("checked_insert"), false);
    EXPECT_EQ(c.at("insert_batch"), 1);
    EXPECT_EQ(c.at("insertions"), 1);
    EXPECT_GT(c.at("insert_fraction").get<double>(), 0);
    EXPECT_GT(c.at("insert_mean_round_seconds").get<double>(), 0);
    EXPECT_GE(c.at("insert_mean_rounds").get<double>(), 1.0);
  }
  // Insertions take the exact start under the isotropic metric, not under radial_shock_3d's.
  EXPECT_EQ(report["cases"][0].at("insert_exact_start"), true);
  EXPECT_EQ(report["cases"][1].at("insert_exact_start"), false);
  EXPECT_EQ(report["cases"][1].at("metric"), "radial_shock_3d");
  EXPECT_GE(report["cases"][1].at("max_anisotropy").get<double>(), 10.0);
}

// --max-sweeps sets the brick variants' sweeps per relaxation, which the JSON reports as asked
// (max_sweeps) and as run (visits_per_relaxation); automatic is null.
TEST(BenchCommand, MaxSweepsIsTheSweepsPerRelaxation) {
  REQUIRE_OPENCL_DEVICE();
  const std::string command = test::rvor_binary() +
                              " bench --metric euclidean --resolution 16 --seeds 5 --no-reference "
                              "--no-fastsweeping --repeat 1 --json --quiet --variant brick_lanes";
  for (const int sweeps : {0, 3}) {
    const test::CommandResult result = test::run_command(
        command + (sweeps ? " --max-sweeps " + std::to_string(sweeps) : std::string()));
    ASSERT_EQ(result.exit_code, 0) << result.err;
    const nlohmann::json c = nlohmann::json::parse(result.out).at("cases").at(0);
    if (sweeps == 0) {
      EXPECT_TRUE(c.at("max_sweeps").is_null());
      EXPECT_EQ(c.at("visits_per_relaxation"), 4);  // automatic: axis offsets
    } else {
      EXPECT_EQ(c.at("max_sweeps"), sweeps);
      EXPECT_EQ(c.at("visits_per_relaxation"), sweeps);
    }
  }
}

TEST(BenchCommand, UnknownVariantIsAOneLineError) {
  const test::CommandResult result =
      test::run_command(test::rvor_binary() + " bench --variant fastest --resolution 8");
  EXPECT_NE(result.exit_code, 0);
  EXPECT_NE(result.err.find("--variant"), std::string::npos) << result.err;
}

}  // namespace
}  // namespace rvor
