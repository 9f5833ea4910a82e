// VoronoiSession: chains of insertions into a field the session keeps with its propagator, on the
// test device's engine and on the CPU reference (rvor/voronoi_session.h).
#include <gtest/gtest.h>

#include <atomic>
#include <cmath>
#include <functional>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include "opencl/opencl_test_support.h"
#include "rvor/error.h"
#include "rvor/opencl_propagator.h"
#include "rvor/voronoi_session.h"
#include "support/box_canvas.h"
#include "support/error_of.h"

namespace rvor {
namespace {

const Vec3 kLo(-1, -1, -1), kHi(1, 1, 1);

Canvas sheared_box(int resolution = 32) {
  Mat3 G;
  G << 5, 2, 0, 2, 2, 0, 0, 0, 1;
  return test::make_uniform_box_canvas(3, kLo, kHi, resolution, G);
}

std::vector<Vec3> seeds_between(const std::vector<Vec3>& seeds, std::size_t begin,
                                std::size_t end) {
  return {seeds.begin() + static_cast<std::ptrdiff_t>(begin),
          seeds.begin() + static_cast<std::ptrdiff_t>(end)};
}

// Solves 6 seeds, then inserts one, then three at once, then the rest one by one.
void expect_insertions_equal_a_solve(std::unique_ptr<Propagator> propagator,
                                     std::unique_ptr<Propagator> all_at_once) {
  const Canvas canvas = sheared_box();
  const std::vector<Vec3> seeds = test::random_points(kLo, kHi, 3, 14, 41);
  VoronoiSession session(std::move(propagator));
  session.solve(canvas, seeds_between(seeds, 0, 6));
  session.insert(canvas, seeds_between(seeds, 6, 7));
  session.insert(canvas, seeds_between(seeds, 7, 10));
  for (std::size_t n = 10; n < seeds.size(); ++n)
    session.insert(canvas, seeds_between(seeds, n, n + 1));
  EXPECT_EQ(session.seeds(), seeds);
  VoronoiField expected;
  all_at_once->solve(canvas, seeds, expected);
  test::expect_same_field(canvas, expected, session.field());
}

TEST(VoronoiSession, InsertionsEqualASolveWithAllSeeds) {
  REQUIRE_ENGINE(RelaxationVariant::automatic);
  expect_insertions_equal_a_solve(std::move(engine), make_reference_propagator());
}

TEST(VoronoiSession, InsertionsEqualASolveWithAllSeedsOnTheReference) {
  expect_insertions_equal_a_solve(make_reference_propagator(), make_reference_propagator());
}

// The refusals of overlapping calls two threads met: an error other than the expected refusal is
// kept for the test's message.
struct OverlapRefusals {
  explicit OverlapRefusals(std::string rule) : rule(std::move(rule)) {}
  void record(const Error& error) {
    const std::lock_guard<std::mutex> lock(mutex);
    if (std::string(error.what()).find(rule) == std::string::npos)
      unexpected.push_back(error.what());
    ++count;
  }
  void expect_some_and_only_refusals() const {
    EXPECT_GE(count.load(), 1);
    EXPECT_TRUE(unexpected.empty()) << unexpected.front();
  }
  const std::string rule;
  std::atomic<int> count{0};
  std::vector<std::string> unexpected;
  std::mutex mutex;
};

// Two threads calling one propagator at once: each overlapping call is an rvor::Error naming the
// rule, the others solve correctly (they shared its canvas and field, and the process crashed).
// One thread makes a single solve of a canvas large enough to take a while; the other calls
// again and again until that solve has returned, so the two overlap at least once, whichever
// thread's call the propagator takes.
void expect_overlapping_calls_refused(Propagator& propagator) {
  const Canvas large = sheared_box(64);
  const Canvas flat =
      test::make_uniform_box_canvas(2, Vec3(-1, -1, 0), Vec3(1, 1, 0), 32, Mat3::Identity());
  const std::vector<Vec3> seeds3 = test::random_points(kLo, kHi, 3, 20, 7);
  const std::vector<Vec3> seeds2 = {Vec3(0.1, 0.2, 0), Vec3(-0.5, 0.4, 0)};
  VoronoiField expected3, expected2;
  make_reference_propagator()->solve(large, seeds3, expected3);
  make_reference_propagator()->solve(flat, seeds2, expected2);
  OverlapRefusals refusals("a propagator serves one call at a time");
  const auto call = [&](const Canvas& canvas, const std::vector<Vec3>& seeds,
                        const VoronoiField& expected) {
    VoronoiField field;
    try {
      propagator.solve(canvas, seeds, field);
    } catch (const Error& error) {
      refusals.record(error);
      return;
    }
    test::expect_same_field(canvas, expected, field);
  };
  std::atomic<bool> large_done{false};
  std::thread other([&] {
    call(large, seeds3, expected3);
    large_done = true;
  });
  while (!large_done) call(flat, seeds2, expected2);
  other.join();
  refusals.expect_some_and_only_refusals();
}

TEST(Propagators, OverlappingCallsFromTwoThreadsAreRefused) {
  REQUIRE_ENGINE(RelaxationVariant::automatic);
  expect_overlapping_calls_refused(*engine);
  expect_overlapping_calls_refused(*make_reference_propagator());
}

// Two threads inserting into one session: its propagator refused the second call, but only after
// both had appended their seeds to the session's list, so seeds() and field() parted (1851 of
// 110 592 labels differed from a solve of seeds(), batches of 300 seeds at 48^3) or the engine
// failed on a list the other thread changed. The session refuses an overlapping call first, and
// changes nothing. One thread makes a long insertion (again where refused); the other inserts
// single seeds until that has returned, so the two overlap at least once.
void expect_overlapping_session_calls_refused(std::unique_ptr<Propagator> propagator) {
  const Canvas canvas = sheared_box(64);
  const std::vector<Vec3> seeds = test::random_points(kLo, kHi, 3, 41, 9);
  VoronoiSession session(std::move(propagator));
  session.solve(canvas, {seeds[0]});
  OverlapRefusals refusals("a session serves one call at a time");
  const auto insert = [&](std::size_t begin, std::size_t end) {
    try {
      session.insert(canvas, seeds_between(seeds, begin, end));
      return true;
    } catch (const Error& error) {
      refusals.record(error);
      return false;
    }
  };
  std::atomic<bool> long_done{false};
  std::thread other([&] {
    while (!insert(1, 21)) continue;
    long_done = true;
  });
  for (std::size_t n = 21; !long_done; n = n + 1 < seeds.size() ? n + 1 : 21) insert(n, n + 1);
  other.join();
  refusals.expect_some_and_only_refusals();
  VoronoiField expected;
  make_reference_propagator()->solve(canvas, session.seeds(), expected);
  test::expect_same_field(canvas, expected, session.field());
}

TEST(VoronoiSession, OverlappingCallsFromTwoThreadsAreRefused) {
  REQUIRE_ENGINE(RelaxationVariant::automatic);
  expect_overlapping_session_calls_refused(std::move(engine));
  expect_overlapping_session_calls_refused(make_reference_propagator());
}

// A canvas whose bricks or arrays were edited without finalize() is refused by both engines, as
// finalize() would refuse it (they read past its arrays: SIGSEGV).
void expect_inconsistent_canvases_refused(Propagator& propagator) {
  const Canvas good = sheared_box();
  const std::vector<Vec3> seeds = {Vec3(0.5, 0.5, 0.5)};
  Canvas bad_table = good;
  bad_table.brick_table[0] = 9999;
  Canvas short_activity = good;
  short_activity.active.resize(10);
  for (const auto& [canvas, expected] : std::vector<std::pair<const Canvas*, std::string>>{
           {&bad_table, "brick table cell 0 holds brick 9999"},
           {&short_activity, "10 activity flags"}}) {
    VoronoiField field;
    const std::string message = test::error_of([&] { propagator.solve(*canvas, seeds, field); });
    EXPECT_NE(message.find(expected), std::string::npos) << message;
  }
}

TEST(Propagators, CanvasesEditedWithoutFinalizeAreRefused) {
  REQUIRE_ENGINE(RelaxationVariant::automatic);
  expect_inconsistent_canvases_refused(*engine);
  expect_inconsistent_canvases_refused(*make_reference_propagator());
}

// An insertion into the field a propagator returned last, with other old seeds than it solved
// for: refused by both engines (the reference returned a field that solves no seeds, silently).
void expect_other_old_seeds_refused(Propagator& propagator) {
  const Canvas canvas = sheared_box();
  const std::vector<Vec3> seeds = test::random_points(kLo, kHi, 3, 5, 11);
  VoronoiField field;
  propagator.solve(canvas, seeds_between(seeds, 0, 3), field);
  std::vector<Vec3> moved = seeds;
  moved[1] = Vec3(-0.3, 0.2, 0.1);
  VoronoiField copy = field;
  const std::string moved_error =
      test::error_of([&] { propagator.insert(canvas, moved, 3, copy); });
  EXPECT_NE(moved_error.find("the field is this propagator's solve of other seeds: seed 1 is not "
                             "the one it was solved with"),
            std::string::npos)
      << moved_error;
  copy = field;
  const std::string count_error =
      test::error_of([&] { propagator.insert(canvas, seeds, 2, copy); });
  EXPECT_NE(count_error.find("the field is not one solved for the first 2 seeds"),
            std::string::npos)
      << count_error;
  EXPECT_NO_THROW(propagator.insert(canvas, seeds, 3, field));
}

TEST(Propagators, InsertionsWithOtherOldSeedsThanTheFieldsAreRefused) {
  REQUIRE_ENGINE(RelaxationVariant::automatic);
  expect_other_old_seeds_refused(*engine);
  expect_other_old_seeds_refused(*make_reference_propagator());
}

TEST(VoronoiSession, InsertionBeforeASolveIsAnError) {
  VoronoiSession session(make_reference_propagator());
  const Canvas canvas = sheared_box();
  EXPECT_THROW(session.insert(canvas, {Vec3::Zero()}), Error);
  EXPECT_THROW(VoronoiSession(nullptr), Error);
}

// A failed solve leaves nothing to read (seeds() and field() still showed the solve before it,
// while insert() refused), and the next solve starts over.
TEST(VoronoiSession, AFailedSolveLeavesNoSeedsAndNoField) {
  VoronoiSession session(make_reference_propagator());
  const Canvas canvas = sheared_box();
  session.solve(canvas, {Vec3(0.1, 0.2, 0.3)});
  EXPECT_THROW(session.solve(canvas, {Vec3(3, 0, 0)}), Error);
  EXPECT_TRUE(session.seeds().empty());
  EXPECT_TRUE(session.field().distance.empty());
  EXPECT_THROW(session.insert(canvas, {Vec3::Zero()}), Error);
  session.solve(canvas, {Vec3(0.1, 0.2, 0.3)});
  EXPECT_EQ(session.seeds().size(), 1u);
}

// A seed outside the domain is refused before anything is written: the session keeps its seeds
// and field, and the next insertions continue them.
TEST(VoronoiSession, ARefusedInsertionLeavesTheSessionAsItWas) {
  REQUIRE_ENGINE(RelaxationVariant::automatic);
  const Canvas canvas = sheared_box();
  const std::vector<Vec3> seeds = test::random_points(kLo, kHi, 3, 9, 43);
  VoronoiSession session(std::move(engine));
  session.solve(canvas, seeds_between(seeds, 0, 7));
  const VoronoiField before = session.field();
  EXPECT_THROW(session.insert(canvas, {Vec3(3, 0, 0)}), Error);
  EXPECT_EQ(session.seeds().size(), 7u);
  EXPECT_EQ(session.field().label, before.label);
  session.insert(canvas, seeds_between(seeds, 7, 9));
  VoronoiField expected;
  make_reference_propagator()->solve(canvas, seeds, expected);
  test::expect_same_field(canvas, expected, session.field());
}

// A canvas changed in place (and finalized) between insertions is solved again with all seeds:
// the field was continued on it, and kept values no solve there gives (the insertion's result then
// differed from a solve with all seeds, which the session promises).
void expect_a_changed_canvas_is_solved_again(
    const std::function<std::unique_ptr<Propagator>()>& make) {
  Canvas canvas = sheared_box();
  const std::vector<Vec3> seeds = test::random_points(kLo, kHi, 3, 10, 47);
  VoronoiSession session(make());
  session.solve(canvas, seeds_between(seeds, 0, 9));
  test::slow_down_a_brick_between_sampled_slots(canvas);
  session.insert(canvas, seeds_between(seeds, 9, 10));
  EXPECT_EQ(session.seeds().size(), 10u);
  VoronoiField expected;
  make()->solve(canvas, seeds, expected);
  test::expect_same_field(canvas, expected, session.field());
}

TEST(VoronoiSession, ACanvasChangedBetweenInsertionsIsSolvedAgain) {
  REQUIRE_ENGINE(RelaxationVariant::automatic);
  expect_a_changed_canvas_is_solved_again([] {
    return make_opencl_propagator(test::engine_device(),
                                  test::with_variant(RelaxationVariant::automatic));
  });
}

TEST(VoronoiSession, ACanvasChangedBetweenInsertionsIsSolvedAgainOnTheReference) {
  expect_a_changed_canvas_is_solved_again([] { return make_reference_propagator(); });
}

// The session's own seeds inserted again: each new one ties with its twin, whose label it does
// not take (a solve with the doubled list labels by the first of two equal seeds).
void expect_own_seeds_inserted_again_change_no_label(std::unique_ptr<Propagator> propagator) {
  const Canvas canvas = sheared_box();
  VoronoiSession session(std::move(propagator));
  session.solve(canvas, test::random_points(kLo, kHi, 3, 4, 59));
  const VoronoiField before = session.field();
  session.insert(canvas, session.seeds());
  EXPECT_EQ(session.seeds().size(), 8u);
  EXPECT_EQ(session.field().label, before.label);
}

TEST(VoronoiSession, ItsOwnSeedsInsertedAgainChangeNoLabel) {
  REQUIRE_ENGINE(RelaxationVariant::automatic);
  expect_own_seeds_inserted_again_change_no_label(std::move(engine));
  expect_own_seeds_inserted_again_change_no_label(make_reference_propagator());
}

// An insertion of no seed changes nothing.
TEST(VoronoiSession, InsertingNoSeedKeepsTheField) {
  REQUIRE_ENGINE(RelaxationVariant::automatic);
  const Canvas canvas = sheared_box();
  VoronoiSession session(std::move(engine));
  session.solve(canvas, test::random_points(kLo, kHi, 3, 5, 53));
  const VoronoiField before = session.field();
  session.insert(canvas, {});
  EXPECT_EQ(session.seeds().size(), 5u);
  EXPECT_EQ(session.field().label, before.label);
  EXPECT_EQ(session.field().distance, before.distance);
}

// Two seeds a voxel apart under a uniform metric of anisotropy 3 (README, "Where the two engines
// differ"): the per-label update has several fixed points there, and the engines settle on
// different ones (cells of 7411 / 7392 voxels on brick_lanes, 9198 / 5605 on the reference). Each
// engine's own choice does not depend on the order: both seeds at once, or either seed solved
// and the other inserted, give the same labels and distances to 1e-4.
void expect_two_close_seeds_settle_alike_in_every_order(std::unique_ptr<Propagator> propagator) {
  Mat3 G;
  G << 5.655093547, 3.945991947, 0, 3.945991947, 4.344906453, 0, 0, 0, 1;
  const Canvas canvas = test::make_uniform_box_canvas(2, Vec3(-0.128596, -1.89078, 0),
                                                      Vec3(2.15755, 0.752208, 0), 131, G);
  const Vec3 a(0.7961052, -0.158253, 0), b(0.8163789, -0.1665257, 0);
  VoronoiField both;
  propagator->solve(canvas, {a, b}, both);
  for (const bool a_first : {true, false}) {
    SCOPED_TRACE(a_first ? "a, then b inserted" : "b, then a inserted");
    const VoronoiField chain =
        test::insert_one_by_one(*propagator, canvas, {a_first ? a : b, a_first ? b : a});
    std::size_t labels = 0, distances = 0;
    for (std::size_t slot = 0; slot < canvas.slot_count(); ++slot) {
      if (!canvas.active[slot]) continue;
      const int32_t label =
          a_first || chain.label[slot] < 0 ? chain.label[slot] : 1 - chain.label[slot];
      labels += label != both.label[slot];
      distances +=
          !(std::abs(chain.distance[slot] - both.distance[slot]) <= 1e-4f * both.distance[slot]);
    }
    EXPECT_EQ(labels, 0u);
    EXPECT_EQ(distances, 0u);
  }
}

TEST(VoronoiSession, EachEngineSettlesTwoCloseSeedsAlikeInEveryOrder) {
  REQUIRE_ENGINE(RelaxationVariant::automatic);
  expect_two_close_seeds_settle_alike_in_every_order(std::move(engine));
  expect_two_close_seeds_settle_alike_in_every_order(make_reference_propagator());
}

// The chain farthest-point seeding runs: each new seed at the centre of the voxel farthest from
// the seeds so far (a Voronoi vertex, where several seeds tie), in fields with shocks. Cells stay
// 10 or more voxels across: where they are only a few stencils wide, the scheme's fixed point
// depends on the order of updates (docs/scheme.md, "Convergence"), solves and chains alike.
std::vector<Vec3> farthest_point_chain(VoronoiSession& session, const Canvas& canvas,
                                       int insertions) {
  std::size_t first = canvas.slot_count() / 3;
  while (!canvas.active[first]) first = (first + 1) % canvas.slot_count();
  session.solve(canvas, {canvas.world_of(first)});
  for (int n = 0; n < insertions; ++n) {
    std::size_t farthest = first;
    for (std::size_t slot = 0; slot < canvas.slot_count(); ++slot)
      if (canvas.active[slot] && std::isfinite(session.field().distance[slot]) &&
          session.field().distance[slot] > session.field().distance[farthest])
        farthest = slot;
    session.insert(canvas, {canvas.world_of(farthest)});
  }
  return session.seeds();
}

TEST(VoronoiSession, FarthestPointChainsEqualASolveWithAllSeeds) {
  REQUIRE_ENGINE(RelaxationVariant::automatic);
  const struct {
    const char *domain, *metric;
    int resolution;
  } cases[] = {{"rect:-1,-1,1,1", "swirl", 128},
               {"rect:-1,-1,1,1", "unidimensional_shock", 128},
               {"box:1,1,1,11,11,11", "radial_shock_3d", 40},
               {"implicit:torus:R=0.6,r=0.25", "hyperbolic_shock", 48}};
  for (const auto& c : cases) {
    SCOPED_TRACE(c.metric);
    const Canvas canvas = test::domain_canvas(c.domain, c.metric, c.resolution);
    VoronoiSession session(make_opencl_propagator(
        test::engine_device(), test::with_variant(RelaxationVariant::automatic)));
    const std::vector<Vec3> seeds = farthest_point_chain(session, canvas, 60);
    VoronoiField all;
    make_reference_propagator()->solve(canvas, seeds, all);
    test::expect_same_field(canvas, all, session.field());
  }
}

}  // namespace
}  // namespace rvor
