#pragma once
// Fixtures of the canvas tests: metric fields given by a lambda, and closed or open box meshes
// written in every supported format.
#include <functional>
#include <string>
#include <utility>
#include <vector>

#include "rvor/error.h"
#include "rvor/metric_field.h"
#include "support/error_of.h"

namespace rvor::test {

class FunctionMetric : public MetricField {
 public:
  FunctionMetric(int dimension, std::function<Mat3(const Vec3&)> function,
                 std::string name = "test-metric")
      : dimension_(dimension), function_(std::move(function)), name_(std::move(name)) {}
  int dimension() const override { return dimension_; }
  Mat3 at(const Vec3& p) const override { return function_(p); }
  std::string description() const override { return name_; }

 private:
  int dimension_;
  std::function<Mat3(const Vec3&)> function_;
  std::string name_;
};

inline FunctionMetric euclidean_metric(int dimension) {
  return FunctionMetric(
      dimension, [](const Vec3&) { return Mat3::Identity(); }, "euclidean");
}

// Box [lo, hi] as a surface mesh. `drop_last_face` leaves one side open.
void write_box_off(const std::string& path, const Vec3& lo, const Vec3& hi,
                   bool drop_last_face = false);  // quads
// Several boxes in one OFF file, each with its own 8 vertices (OFF vertices are not welded);
// `flip_first_face` reverses the orientation of the first box's first quad.
void write_boxes_off(const std::string& path, const std::vector<std::pair<Vec3, Vec3>>& boxes,
                     bool flip_first_face = false);
// One closed surface: the box [0,4]^3 holding the chamber [1,3]^3, which opens to the x = 0 face
// through a square neck of width `neck` (x in [0,1], y and z in [2 - neck/2, 2 + neck/2]).
void write_bottle_off(const std::string& path, double neck);
// Whether point p lies in that bottle's solid (not in the chamber, the neck or outside).
bool in_bottle(const Vec3& p, double neck);
void write_box_obj(const std::string& path, const Vec3& lo, const Vec3& hi);  // v/vt/vn, negative
void write_box_stl_ascii(const std::string& path, const Vec3& lo, const Vec3& hi);
void write_box_stl_binary(const std::string& path, const Vec3& lo, const Vec3& hi);

}  // namespace rvor::test
