// The `dual` object of report.json.
#include <nlohmann/json.hpp>

#include "rvor/dual.h"

namespace rvor {

namespace {

nlohmann::json quality_json(const QualitySummary& q) {
  return {{"elements", q.elements},
          {"min", q.min_quality},
          {"mean", q.mean_quality},
          {"histogram", q.quality_histogram},
          {"histogram_bins", "10 bins of width 0.1 on [0, 1]"},
          {"min_angle_degrees", q.min_angle},
          {"max_angle_degrees", q.max_angle},
          {"edge_length",
           {{"min", q.min_edge_length}, {"mean", q.mean_edge_length}, {"max", q.max_edge_length}}}};
}

}  // namespace

std::string dual_report_json(const StraightDual& dual) {
  const DualChecks& c = dual.checks;
  const nlohmann::json j = {{"dimension", dual.dimension},
                            {"vertices", dual.vertices.size()},
                            {"edges", dual.edges.size()},
                            {"triangles", dual.triangles.size()},
                            {"tetrahedra", dual.tetrahedra.size()},
                            {"inverted", c.inverted},
                            {"intersecting", c.intersecting},
                            {"intersecting_pairs", c.intersecting_pairs},
                            {"non_manifold", c.non_manifold},
                            {"degenerate_witnesses", c.degenerate_witnesses},
                            {"near_degenerate", c.near_degenerate},
                            {"near_degenerate_removed", c.near_degenerate_removed},
                            {"near_degenerate_added", c.near_degenerate_added},
                            {"dangling", c.dangling},
                            {"unused_vertices", c.unused_vertices},
                            {"euler_characteristic", c.euler_characteristic},
                            {"boundary_euler_characteristic", c.boundary_euler_characteristic},
                            {"domain_euler_characteristic", c.domain_euler_characteristic},
                            {"is_triangulation", c.is_triangulation},
                            {"seconds", dual.seconds},
                            {"quality", quality_json(dual.quality_summary)}};
  return j.dump(2);
}

}  // namespace rvor
