// Element quality in the metric: a metric G maps to Euclidean geometry by F = G^{1/2}, so each
// measure is the Euclidean one of the element's vertices mapped by F.
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <limits>

#include "dual/dual_internal.h"
#include "dual/parallel_for.h"

namespace rvor::dual {

namespace {

constexpr double kDegrees = 180.0 / M_PI;

double triangle_area(const Vec3& a, const Vec3& b, const Vec3& c) {
  return 0.5 * (b - a).cross(c - a).norm();
}

// Shape quality of the simplex with the given (already mapped) vertices.
double shape_quality(const std::vector<Vec3>& p) {
  if (p.size() == 3) {
    const double l2 =
        (p[1] - p[0]).squaredNorm() + (p[2] - p[1]).squaredNorm() + (p[0] - p[2]).squaredNorm();
    return l2 > 0 ? 4.0 * std::sqrt(3.0) * triangle_area(p[0], p[1], p[2]) / l2 : 0.0;
  }
  const double volume = std::abs((p[1] - p[0]).dot((p[2] - p[0]).cross(p[3] - p[0]))) / 6.0;
  const double faces = triangle_area(p[1], p[2], p[3]) + triangle_area(p[0], p[2], p[3]) +
                       triangle_area(p[0], p[1], p[3]) + triangle_area(p[0], p[1], p[2]);
  return faces > 0 ? 216.0 * std::sqrt(3.0) * volume * volume / (faces * faces * faces) : 0.0;
}

double angle_between(const Vec3& u, const Vec3& v) {
  const double n = u.norm() * v.norm();
  return n > 0 ? std::acos(std::clamp(u.dot(v) / n, -1.0, 1.0)) * kDegrees : 0.0;
}

// Triangle angles (3 vertices) or dihedral angles (4 vertices) of mapped vertices, degrees.
std::vector<double> angles(const std::vector<Vec3>& p) {
  std::vector<double> out;
  if (p.size() == 3) {
    for (int i = 0; i < 3; ++i)
      out.push_back(angle_between(p[(i + 1) % 3] - p[i], p[(i + 2) % 3] - p[i]));
    return out;
  }
  for (int i = 0; i < 4; ++i)
    for (int j = i + 1; j < 4; ++j) {  // dihedral angle at edge (i, j)
      int k = 0;
      while (k == i || k == j) ++k;
      const int l = 6 - i - j - k;
      const Vec3 e = (p[j] - p[i]).normalized();
      auto across = [&](int m) {
        const Vec3 d = p[m] - p[i];
        return Vec3(d - d.dot(e) * e);
      };
      out.push_back(angle_between(across(k), across(l)));
    }
  return out;
}

double edge_length(const StraightDual& dual, int32_t a, int32_t b) {
  const Vec3 d = dual.vertices[b] - dual.vertices[a];
  return 0.5 *
         (metric_length(dual.vertex_metrics[a], d) + metric_length(dual.vertex_metrics[b], d));
}

// `sqrt_metrics`: metric_sqrt of each vertex's metric (computed once, not once per element).
ElementQuality element_quality(const StraightDual& dual, const std::vector<Mat3>& sqrt_metrics,
                               const std::vector<int32_t>& v) {
  ElementQuality q;
  q.quality = std::numeric_limits<double>::infinity();
  Mat3 mean = Mat3::Zero();
  for (int32_t owner : v) {  // shape in each vertex's metric; the worst is kept
    const Mat3& F = sqrt_metrics[owner];
    std::vector<Vec3> mapped;
    for (int32_t w : v) mapped.push_back(F * dual.vertices[w]);
    q.quality = std::min(q.quality, shape_quality(mapped));
    mean += dual.vertex_metrics[owner] / static_cast<double>(v.size());
  }
  const Mat3 F = metric_sqrt(mean);
  std::vector<Vec3> mapped;
  for (int32_t w : v) mapped.push_back(F * dual.vertices[w]);
  const std::vector<double> a = angles(mapped);
  q.min_angle = *std::min_element(a.begin(), a.end());
  q.max_angle = *std::max_element(a.begin(), a.end());
  q.min_edge_length = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < v.size(); ++i)
    for (std::size_t j = i + 1; j < v.size(); ++j) {
      const double l = edge_length(dual, v[i], v[j]);
      q.min_edge_length = std::min(q.min_edge_length, l);
      q.max_edge_length = std::max(q.max_edge_length, l);
    }
  return q;
}

QualitySummary summarise(const StraightDual& dual) {
  QualitySummary s;
  s.elements = dual.quality.size();
  if (s.elements > 0) {
    s.min_quality = s.min_angle = std::numeric_limits<double>::infinity();
    for (const ElementQuality& q : dual.quality) {
      s.min_quality = std::min(s.min_quality, q.quality);
      s.mean_quality += q.quality / static_cast<double>(s.elements);
      s.min_angle = std::min(s.min_angle, q.min_angle);
      s.max_angle = std::max(s.max_angle, q.max_angle);
      ++s.quality_histogram[std::clamp(static_cast<int>(q.quality * 10.0), 0, 9)];
    }
  }
  if (!dual.edges.empty()) {
    s.min_edge_length = std::numeric_limits<double>::infinity();
    for (const auto& e : dual.edges) {
      const double l = edge_length(dual, e[0], e[1]);
      s.min_edge_length = std::min(s.min_edge_length, l);
      s.max_edge_length = std::max(s.max_edge_length, l);
      s.mean_edge_length += l / static_cast<double>(dual.edges.size());
    }
  }
  return s;
}

}  // namespace

void measure_quality(StraightDual& dual) {
  // Elements are independent: measured on all cores; the summary stays sequential (same sums).
  std::vector<Mat3> sqrt_metrics(dual.vertex_metrics.size());
  detail::parallel_for(sqrt_metrics.size(), 256, [&](std::size_t i) {
    sqrt_metrics[i] = metric_sqrt(dual.vertex_metrics[i]);
  });
  dual.quality.resize(dual.top_count());
  detail::parallel_for(dual.top_count(), 256, [&](std::size_t t) {
    const auto s = dual.top_simplex(t);
    dual.quality[t] = element_quality(
        dual, sqrt_metrics, std::vector<int32_t>(s.begin(), s.begin() + dual.dimension + 1));
  });
  dual.quality_summary = summarise(dual);
}

}  // namespace rvor::dual
