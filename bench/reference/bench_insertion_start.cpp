// The host side of an insertion's exact start (rvor/nearest_seeds.h, insertion_start_lists): the
// search for the bricks the new seeds may lower and their candidate lists, at 256^3 with 1000
// seeds solved, for 1 and 1000 new seeds. Each iteration takes other new seeds, so that the
// search meets the solved distances out of the caches, as an insertion does.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "rvor/nearest_seeds.h"
#include "rvor/seeds.h"
#include "support/box_canvas.h"

namespace {

constexpr std::size_t kSolvedSeeds = 1000;

struct SolvedBox {
  rvor::Canvas canvas;
  std::vector<rvor::Vec3> seeds;  // the solved ones first
  std::vector<float> distance;    // the least exact distance to them: the solved field's values
};

// Euclidean box [-1,1]^3 at 256^3: u0 of the nearest solved seed per voxel, from the exact start's
// lists, stands in for the solved field (it is that field but next to bisectors).
const SolvedBox& solved_box() {
  static const SolvedBox box = [] {
    SolvedBox b{rvor::test::make_uniform_box_canvas(3, rvor::Vec3(-1, -1, -1), rvor::Vec3(1, 1, 1),
                                                    256, rvor::Mat3::Identity()),
                {},
                {}};
    b.seeds = rvor::random_seeds(b.canvas, kSolvedSeeds, 1);
    const rvor::BrickSeedLists lists = rvor::nearest_seed_candidates(b.canvas, b.seeds);
    b.distance.assign(b.canvas.slot_count(), std::numeric_limits<float>::infinity());
    const std::size_t volume = static_cast<std::size_t>(b.canvas.brick_volume());
    for (std::size_t slot = 0; slot < b.canvas.slot_count(); ++slot) {
      const std::size_t brick = slot / volume;
      const rvor::Vec3 x = b.canvas.world_of(slot);
      double least = std::numeric_limits<double>::infinity();
      for (std::uint32_t c = lists.begin[brick]; c < lists.begin[brick + 1]; ++c)
        least = std::min(least, (x - b.seeds[lists.seeds[c]]).norm());
      b.distance[slot] = static_cast<float>(least);
    }
    return b;
  }();
  return box;
}

void BM_InsertionStartLists(benchmark::State& state) {
  const SolvedBox& box = solved_box();
  const auto inserted = static_cast<std::size_t>(state.range(0));
  const std::vector<rvor::Vec3> pool =
      rvor::random_seeds(box.canvas, std::max<std::size_t>(4096, 4 * inserted), 2);
  std::vector<rvor::Vec3> seeds = box.seeds;
  std::size_t next = 0, bricks = 0;
  for (auto _ : state) {
    seeds.resize(kSolvedSeeds);
    for (std::size_t n = 0; n < inserted; ++n) seeds.push_back(pool[(next + n) % pool.size()]);
    next += inserted;
    const rvor::BrickSeedLists lists = rvor::insertion_start_lists(
        box.canvas, seeds, kSolvedSeeds, box.distance, rvor::ExactStartReach::every_brick);
    for (std::size_t b = 0; b + 1 < lists.begin.size(); ++b)
      bricks += lists.begin[b] != lists.begin[b + 1];
  }
  state.counters["listed_bricks"] = static_cast<double>(bricks) / state.iterations();
}

BENCHMARK(BM_InsertionStartLists)
    ->ArgName("new_seeds")
    ->Arg(1)
    ->Arg(1000)
    ->Unit(benchmark::kMicrosecond);

}  // namespace
