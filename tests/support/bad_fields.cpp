#include "support/bad_fields.h"

#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <limits>
#include <string>

#include "rvor/error.h"
#include "support/box_canvas.h"
#include "support/error_of.h"

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

void expect_offsets_past_int8_refused(Propagator& engine) {
  Mat3 G = Mat3::Identity();
  G.topLeftCorner<2, 2>() << 20574944.93148327, 40424819.7867313, 40424819.7867313,
      79425056.06851673;
  const Canvas canvas = make_uniform_box_canvas(2, Vec3(-1, -1, 0), Vec3(1, 1, 0), 16, G);
  VoronoiField field;
  const std::string message = error_of([&] { engine.solve(canvas, {Vec3(0.1, 0.2, 0)}, field); });
  EXPECT_NE(message.find("canvas voxel (0, 0, 0) at (-0.9375, -0.9375, 0): metric"),
            std::string::npos)
      << message;
  EXPECT_NE(message.find("is too anisotropic for rvor's stencils: its Selling stencil has an "
                         "offset of 167 voxels along x, past the 127 either engine stores"),
            std::string::npos)
      << message;
}

}  // namespace rvor::test
