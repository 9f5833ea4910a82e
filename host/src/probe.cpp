#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "rvor/atomic_file.h"
#include "rvor/canvas_output.h"
#include "rvor/error.h"
#include "rvor/spec_text.h"

namespace rvor {

namespace {

// The active voxel nearest (in index space) to continuous index coordinates c: searched in
// growing cubic shells around the containing voxel, stopping once no farther shell can be closer.
// A point beyond the index box is first moved onto it (its far-away coordinates would overflow the
// squared distances).
int64_t nearest_active_slot(const Canvas& canvas, const Vec3& point) {
  Vec3 c;
  for (int a = 0; a < 3; ++a) c[a] = std::clamp(point[a], -1.0, canvas.dims[a] + 0.0);
  const int ci = static_cast<int>(std::lround(c.x()));
  const int cj = static_cast<int>(std::lround(c.y()));
  const int ck = canvas.dimension == 3 ? static_cast<int>(std::lround(c.z())) : 0;
  const int max_radius = std::max({canvas.dims[0], canvas.dims[1], canvas.dims[2]}) + 2;
  int64_t best = -1;
  double best_distance = std::numeric_limits<double>::infinity();
  for (int r = 0; r <= max_radius; ++r) {
    // Every voxel of shell r is at least r - 1 away from c (c lies within its rounded voxel).
    if (best >= 0 && r - 1 > std::sqrt(best_distance)) break;
    const int rk = canvas.dimension == 3 ? r : 0;
    for (int k = ck - rk; k <= ck + rk; ++k)
      for (int j = cj - r; j <= cj + r; ++j)
        for (int i = ci - r; i <= ci + r; ++i) {
          const bool on_shell =
              std::abs(i - ci) == r || std::abs(j - cj) == r || std::abs(k - ck) == rk;
          if (!on_shell) continue;
          const int64_t slot = canvas.slot_of(i, j, k);
          if (slot < 0) continue;
          const double d =
              (Vec3(i, j, k) - Vec3(c.x(), c.y(), canvas.dimension == 3 ? c.z() : 0)).squaredNorm();
          if (d < best_distance) best_distance = d, best = slot;
        }
  }
  return best;
}

}  // namespace

std::vector<ProbeSample> probe_field(const Canvas& canvas, const VoronoiField& field,
                                     const std::vector<Vec3>& points) {
  std::vector<ProbeSample> samples;
  samples.reserve(points.size());
  require_field_for(canvas, field, "probe");
  for (std::size_t n = 0; n < points.size(); ++n) {
    if (!points[n].allFinite())
      throw Error("probe point " + std::to_string(n) + " has a coordinate that is not finite");
    const int64_t slot = nearest_active_slot(canvas, canvas.index_coordinates(points[n]));
    if (slot < 0)
      throw Error("probe point " + std::to_string(n) + ": the canvas has no active voxel");
    samples.push_back({points[n], canvas.world_of(static_cast<std::size_t>(slot)),
                       field.distance[slot], field.label[slot]});
  }
  return samples;
}

void write_probe_csv(const std::string& path, const std::vector<ProbeSample>& samples) {
  write_file_atomically(path, [&](std::ostream& out) {
    out << "x,y,z,distance,label\n";
    for (const ProbeSample& s : samples)
      out << exact_text(s.voxel_centre.x()) << "," << exact_text(s.voxel_centre.y()) << ","
          << exact_text(s.voxel_centre.z()) << "," << exact_text(s.distance) << "," << s.label
          << "\n";
  });
}

}  // namespace rvor
