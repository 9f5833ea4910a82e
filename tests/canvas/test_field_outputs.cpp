// The functions that read a solved field next to its canvas refuse a field of another canvas with
// an error naming themselves (they read past its arrays before, or crashed).
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <string>
#include <vector>

#include "canvas_test_support.h"
#include "rvor/canvas_output.h"
#include "rvor/canvas_png.h"
#include "rvor/field_summary.h"
#include "support/box_canvas.h"
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

TEST(FieldOutputs, LabelsBeyondTheSeedsAndNonFiniteProbesAreErrors) {
  const Canvas canvas =
      test::make_uniform_box_canvas(2, Vec3(-1, -1, 0), Vec3(1, 1, 0), 16, Mat3::Identity());
  VoronoiField field;
  field.distance.assign(canvas.slot_count(), 1.0f);
  field.label.assign(canvas.slot_count(), 3);
  EXPECT_NE(test::error_of([&] { summarize_field(canvas, field, 2); }).find("has label 3"),
            std::string::npos);
  const std::string message =
      test::error_of([&] { probe_field(canvas, field, {Vec3(std::nan(""), 0, 0)}); });
  EXPECT_NE(message.find("probe point 0 has a coordinate that is not finite"), std::string::npos)
      << message;
  // A finite point far away is taken to the nearest voxel (documented), not refused.
  EXPECT_EQ(probe_field(canvas, field, {Vec3(1e300, 0, 0)}).size(), 1u);
}

}  // namespace
}  // namespace rvor
