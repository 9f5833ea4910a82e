#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <limits>
#include <string>

#include "rvor/atomic_file.h"
#include "rvor/canvas_output.h"
#include "rvor/error.h"
#include "rvor/spec_text.h"

namespace rvor {

namespace {

// How far beyond the index box (in voxels) a probe is taken where it is: a point farther out
// (1e300) is taken that far along the same direction from the box, so that its distances stay
// finite and their differences between voxels, of order voxels times that far, exact to far below
// a voxel's square in double.
constexpr double kFarthestProbe = 1e9;

// The search for the active voxel nearest to a point given in index coordinates: bricks in growing
// shells of the brick grid (each shell's surface only), until no farther shell can hold a nearer
// voxel. The search over voxels before took 1.6 s per probe at 384^3 in a torus's hole (every
// voxel of each cube read again at each shell), and it measured from the point moved onto the
// index box, which for a point beyond the box is not the nearest voxel to the point itself.
//
// Distances are compared less the point's squared distance to the box, the same for every voxel:
// with b the offset from the box's nearest point q to the point, a voxel v at x_a = |v_a - q_a| is
// at sum x_a^2 + 2 x_a |b_a| (b_a is 0 or points away from every voxel), which stays exact where
// the squares of the point's own coordinates would not.
class NearestActiveVoxel {
 public:
  NearestActiveVoxel(const Canvas& canvas, const Vec3& point) : canvas_(canvas) {
    const bool flat = canvas.dimension == 2;
    for (int a = 0; a < 3; ++a) {
      const double last = canvas.dims[a] - 1.0, p = flat && a == 2 ? 0.0 : point[a];
      box_point_[a] = std::clamp(p, 0.0, last);
      // An index coordinate past double's range (a far point on a fine canvas) keeps its side.
      beyond_[a] = std::min(std::abs(p - box_point_[a]), std::numeric_limits<double>::max());
      const int edge = a == 2 ? canvas.brick_edge_z() : Canvas::kBrickEdge;
      centre_brick_[a] = static_cast<int>(box_point_[a]) / edge;
      // Ties go to the voxel nearest the rounded point, as when the search ran over voxels.
      rounded_[a] = static_cast<int>(std::lround(std::clamp(p, -1.0, last + 1.0)));
    }
    const double farthest = beyond_.maxCoeff();
    if (farthest > kFarthestProbe) beyond_ *= kFarthestProbe / farthest;
  }

  int64_t find() {
    // A point in an active voxel: that voxel is nearest along every axis, and wins ties with the
    // rounded point's rule. Dense probes (one per voxel) read one voxel each, not a brick or more.
    if (beyond_.isZero()) {
      const int64_t own = canvas_.slot_of(rounded_[0], rounded_[1], rounded_[2]);
      if (own >= 0) return own;
    }
    const auto& grid = canvas_.brick_grid_dims;
    int last_shell = 0;
    for (int a = 0; a < 3; ++a)
      last_shell = std::max({last_shell, centre_brick_[a], grid[a] - 1 - centre_brick_[a]});
    for (int r = 0; r <= last_shell; ++r) {
      // The box point lies in [8b, 8b + 8) along each axis, b its brick: a voxel of shell r lies
      // more than 8 (r - 1) from it along one axis.
      const double gap = std::max(0, Canvas::kBrickEdge * (r - 1));
      if (best_ >= 0 && gap * gap > best_distance_) break;
      visit_shell(r);
    }
    return best_;
  }

 private:
  // The relative squared distance (above) of a voxel, or of a brick's nearest point, x_a from the
  // box point along each axis.
  double distance(const Vec3& x) const {
    double d = 0.0;
    for (int a = 0; a < 3; ++a) d += x[a] * x[a] + 2.0 * x[a] * beyond_[a];
    return d;
  }

  void visit_shell(int r) {
    const auto& grid = canvas_.brick_grid_dims;
    const int rk = canvas_.dimension == 3 ? r : 0;
    const int* b = centre_brick_.data();
    for (int bk = std::max(0, b[2] - rk); bk <= std::min(grid[2] - 1, b[2] + rk); ++bk)
      for (int bj = std::max(0, b[1] - r); bj <= std::min(grid[1] - 1, b[1] + r); ++bj) {
        const bool on_face = std::abs(bj - b[1]) == r || (rk > 0 && std::abs(bk - b[2]) == r);
        const int step = on_face || r == 0 ? 1 : 2 * r;  // inside the shell: its two ends only
        for (int bi = b[0] - r; bi <= b[0] + r; bi += step)
          if (bi >= 0 && bi < grid[0]) visit_brick(bi, bj, bk);
      }
  }

  void visit_brick(int bi, int bj, int bk) {
    const int32_t brick = canvas_.brick_at(bi, bj, bk);
    if (brick < 0) return;
    const VoxelIndex& o = canvas_.brick_origins[static_cast<std::size_t>(brick)];
    const int edge = Canvas::kBrickEdge;
    const std::array<int, 3> low{o.i, o.j, o.k};
    const std::array<int, 3> high{std::min(o.i + edge, canvas_.dims[0]) - 1,
                                  std::min(o.j + edge, canvas_.dims[1]) - 1,
                                  std::min(o.k + canvas_.brick_edge_z(), canvas_.dims[2]) - 1};
    Vec3 gap;  // from the box point to the brick, along each axis
    for (int a = 0; a < 3; ++a)
      gap[a] = std::max({low[a] - box_point_[a], 0.0, box_point_[a] - high[a]});
    if (best_ >= 0 && distance(gap) > best_distance_) return;
    const auto first = static_cast<int64_t>(brick) * canvas_.brick_volume();
    for (int k = low[2]; k <= high[2]; ++k)
      for (int j = low[1]; j <= high[1]; ++j)
        for (int i = low[0]; i <= high[0]; ++i) {
          const int64_t slot = first + (i - o.i) + edge * ((j - o.j) + edge * (k - o.k));
          if (canvas_.active[static_cast<std::size_t>(slot)]) offer(slot, i, j, k);
        }
  }

  // Nearer wins; at equal distance the voxel nearer the rounded point in Chebyshev distance, then
  // the first in (k, j, i) order.
  void offer(int64_t slot, int i, int j, int k) {
    const double d = distance((Vec3(i, j, k) - box_point_).cwiseAbs());
    const int ring =
        std::max({std::abs(i - rounded_[0]), std::abs(j - rounded_[1]), std::abs(k - rounded_[2])});
    const std::array<int, 4> key{ring, k, j, i};
    if (best_ >= 0 && (d > best_distance_ || (d == best_distance_ && key >= best_key_))) return;
    best_ = slot;
    best_distance_ = d;
    best_key_ = key;
  }

  const Canvas& canvas_;
  Vec3 box_point_;  // the index box's point nearest to the point (z = 0 in 2D)
  Vec3 beyond_;     // the point's distance from it along each axis, at most kFarthestProbe
  std::array<int, 3> centre_brick_{};  // the brick of box_point_
  std::array<int, 3> rounded_{};
  int64_t best_ = -1;
  double best_distance_ = 0.0;
  std::array<int, 4> best_key_{};
};

}  // namespace

std::vector<ProbeSample> probe_field(const Canvas& canvas, const VoronoiField& field,
                                     const std::vector<Vec3>& points) {
  std::vector<ProbeSample> samples;
  samples.reserve(points.size());
  require_field_for(canvas, field, "probe");
  for (std::size_t n = 0; n < points.size(); ++n) {
    if (!points[n].allFinite())
      throw Error("probe point " + std::to_string(n) + " has a coordinate that is not finite");
    const int64_t slot = NearestActiveVoxel(canvas, canvas.index_coordinates(points[n])).find();
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
