#include "support/bad_fields.h"

#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <limits>
#include <string>

#include "rvor/error.h"

namespace rvor::test {

namespace {

struct Corruption {
  const char* what;
  std::function<void(float& distance, std::int32_t& label)> apply;
  const char* message;  // what the error must say about the slot
};

std::vector<Corruption> corruptions(std::int32_t first_new) {
  const float inf = std::numeric_limits<float>::infinity();
  return {
      {"a new seed's label", [=](float&, std::int32_t& l) { l = first_new; }, "has label"},
      {"a label far past the seeds", [](float&, std::int32_t& l) { l = 1 << 30; }, "has label"},
      {"label -2", [](float&, std::int32_t& l) { l = -2; }, "has label -2"},
      {"a NaN distance", [](float& d, std::int32_t&) { d = std::nanf(""); }, "distance NaN"},
      {"a negative distance", [](float& d, std::int32_t&) { d = -0.5f; }, "below 0"},
      {"no label", [](float&, std::int32_t& l) { l = -1; }, "without a label"},
      {"no distance", [=](float& d, std::int32_t&) { d = inf; }, "without a distance"},
  };
}

}  // namespace

void expect_corrupted_fields_refused(Propagator& engine, const Canvas& canvas,
                                     const std::vector<Vec3>& seeds, std::size_t first_new,
                                     const VoronoiField& solved) {
  std::size_t slot = 0;  // the last labelled slot
  for (std::size_t s = 0; s < solved.label.size(); ++s)
    if (solved.label[s] >= 0) slot = s;
  for (const Corruption& corruption : corruptions(static_cast<std::int32_t>(first_new))) {
    SCOPED_TRACE(corruption.what);
    VoronoiField field = solved;
    corruption.apply(field.distance[slot], field.label[slot]);
    try {
      engine.insert(canvas, seeds, first_new, field);
      ADD_FAILURE() << "no error";
    } catch (const Error& e) {
      const std::string message = e.what();
      EXPECT_NE(message.find("slot " + std::to_string(slot)), std::string::npos) << message;
      EXPECT_NE(message.find(corruption.message), std::string::npos) << message;
    }
  }
}

}  // namespace rvor::test
