// The field hash the engine uses to recognise the field it returned (host/src/opencl, internal):
// a field that differs from another in any one slot hashes differently, whatever changed there.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <random>
#include <utility>

#include "field_transfer.h"

namespace rvor {
namespace {

VoronoiField random_field(std::size_t slots, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> distance(0.0f, 3.0f);
  std::uniform_int_distribution<int32_t> label(-1, 999);
  VoronoiField field;
  for (std::size_t n = 0; n < slots; ++n) {
    field.distance.push_back(distance(rng));
    field.label.push_back(label(rng));
  }
  return field;
}

TEST(FieldHash, AnyOneSlotChangedChangesIt) {
  const VoronoiField field = random_field(4096, 3);
  const std::uint64_t hash = opencl::field_hash(field);
  std::mt19937 rng(11);
  std::uniform_int_distribution<std::size_t> slot(0, field.distance.size() - 1);
  for (int trial = 0; trial < 300; ++trial) {
    VoronoiField changed = field;
    const std::size_t s = slot(rng);
    switch (trial % 3) {
      case 0:  // one unit in the last place
        changed.distance[s] = std::nextafter(changed.distance[s], 10.0f);
        break;
      case 1:
        changed.label[s] = changed.label[s] + 1;
        break;
      default: {  // swapping two slots keeps the multiset of states: the slot must count
        const std::size_t t = (s + 1) % changed.distance.size();
        std::swap(changed.distance[s], changed.distance[t]);
        std::swap(changed.label[s], changed.label[t]);
        break;
      }
    }
    if (changed.distance == field.distance && changed.label == field.label) continue;
    EXPECT_NE(opencl::field_hash(changed), hash) << "trial " << trial << ", slot " << s;
  }
}

}  // namespace
}  // namespace rvor
