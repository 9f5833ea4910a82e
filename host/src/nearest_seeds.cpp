#include "rvor/nearest_seeds.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numeric>
#include <string>

#include <utility>

#include "rvor/error.h"

namespace rvor {

namespace {

// Points of R^d (z = 0 in 2D), split at medians along the axes in turn: nearest distance and
// radius queries in O(log n + k).
class PointTree {
 public:
  PointTree(std::vector<Vec3> points, int dimension)
      : points_(std::move(points)), order_(points_.size()), dimension_(dimension) {
    std::iota(order_.begin(), order_.end(), 0);
    build(0, order_.size(), 0);
  }

  double nearest_distance(const Vec3& q) const {
    double best = std::numeric_limits<double>::infinity();
    nearest(q, 0, order_.size(), 0, best);
    return std::sqrt(best);
  }

  // Appends the indices of the points within `radius` of q (unordered).
  void within(const Vec3& q, double radius, std::vector<std::int32_t>& found) const {
    collect(q, radius, 0, order_.size(), 0, found);
  }

 private:
  static constexpr std::size_t kLeafSize = 8;

  int next_axis(int axis) const { return (axis + 1) % dimension_; }
  const Vec3& point(std::size_t position) const { return points_[order_[position]]; }

  void build(std::size_t lo, std::size_t hi, int axis) {
    if (hi - lo <= kLeafSize) return;
    const std::size_t mid = lo + (hi - lo) / 2;
    std::nth_element(
        order_.begin() + lo, order_.begin() + mid, order_.begin() + hi,
        [&](std::int32_t a, std::int32_t b) { return points_[a][axis] < points_[b][axis]; });
    build(lo, mid, next_axis(axis));
    build(mid + 1, hi, next_axis(axis));
  }

  void nearest(const Vec3& q, std::size_t lo, std::size_t hi, int axis, double& best2) const {
    if (hi - lo <= kLeafSize) {
      for (std::size_t i = lo; i < hi; ++i) best2 = std::min(best2, (point(i) - q).squaredNorm());
      return;
    }
    const std::size_t mid = lo + (hi - lo) / 2;
    best2 = std::min(best2, (point(mid) - q).squaredNorm());
    const double d = q[axis] - point(mid)[axis];
    if (d < 0) {
      nearest(q, lo, mid, next_axis(axis), best2);
      if (d * d < best2) nearest(q, mid + 1, hi, next_axis(axis), best2);
    } else {
      nearest(q, mid + 1, hi, next_axis(axis), best2);
      if (d * d < best2) nearest(q, lo, mid, next_axis(axis), best2);
    }
  }

  void collect(const Vec3& q, double radius, std::size_t lo, std::size_t hi, int axis,
               std::vector<std::int32_t>& found) const {
    const double radius2 = radius * radius;
    if (hi - lo <= kLeafSize) {
      for (std::size_t i = lo; i < hi; ++i)
        if ((point(i) - q).squaredNorm() <= radius2) found.push_back(order_[i]);
      return;
    }
    const std::size_t mid = lo + (hi - lo) / 2;
    if ((point(mid) - q).squaredNorm() <= radius2) found.push_back(order_[mid]);
    const double split = point(mid)[axis];
    if (q[axis] - radius <= split) collect(q, radius, lo, mid, next_axis(axis), found);
    if (q[axis] + radius >= split) collect(q, radius, mid + 1, hi, next_axis(axis), found);
  }

  std::vector<Vec3> points_;
  std::vector<std::int32_t> order_;
  int dimension_;
};

std::size_t first_active_slot(const Canvas& canvas) {
  std::size_t slot = 0;
  while (!canvas.active[slot]) ++slot;
  return slot;
}

// sqrt of the metric's diagonal, per axis (1 along z in 2D): with a diagonal metric |q|_G is the
// Euclidean length of the scaled q, and a brick's voxel centres scale to an axis-aligned box.
Vec3 axis_scales(const Canvas& canvas) {
  const Mat3 G = canvas.metric_at(first_active_slot(canvas));
  return Vec3(std::sqrt(G(0, 0)), std::sqrt(G(1, 1)),
              canvas.dimension == 3 ? std::sqrt(G(2, 2)) : 1.0);
}

// The seeds in the coordinates scaled by axis_scales (index units), where the metric is Euclidean,
// in a tree.
struct ScaledSeeds {
  ScaledSeeds(const Canvas& canvas, const std::vector<Vec3>& seeds)
      : scales(axis_scales(canvas)),
        points(scaled(canvas, seeds, scales)),
        tree(points, canvas.dimension),
        dimension(canvas.dimension) {}

  // The box of the voxel centres of the brick at `origin`.
  std::pair<Vec3, Vec3> brick_box(const VoxelIndex& origin) const {
    const double edge = Canvas::kBrickEdge - 1;
    const Vec3 lo = scales.cwiseProduct(Vec3(origin.i, origin.j, origin.k));
    return {lo, lo + scales.cwiseProduct(Vec3(edge, edge, dimension == 3 ? edge : 0.0))};
  }

  static std::vector<Vec3> scaled(const Canvas& canvas, const std::vector<Vec3>& seeds,
                                  const Vec3& scales) {
    std::vector<Vec3> points;
    points.reserve(seeds.size());
    for (const Vec3& seed : seeds)
      points.push_back(scales.cwiseProduct(seed_index_point(canvas, seed)));
    return points;
  }

  Vec3 scales;
  std::vector<Vec3> points;
  PointTree tree;
  int dimension;
};

// The greatest distance of the brick's active voxels in a solved field (+inf where one is
// unlabelled, world units).
double greatest_distance(const Canvas& canvas, std::size_t brick,
                         const std::vector<float>& distance) {
  const std::size_t first = brick * static_cast<std::size_t>(canvas.brick_volume());
  double greatest = 0.0;
  for (std::size_t slot = first; slot < first + canvas.brick_volume(); ++slot)
    if (canvas.active[slot]) greatest = std::max<double>(greatest, distance[slot]);
  return greatest;
}

// The least and the greatest distance from y to the points of the box [lo, hi].
std::pair<double, double> box_distances(const Vec3& y, const Vec3& lo, const Vec3& hi) {
  double least = 0.0, greatest = 0.0;
  for (int a = 0; a < 3; ++a) {
    const double outside = std::max({0.0, lo[a] - y[a], y[a] - hi[a]});
    const double farthest = std::max(std::abs(y[a] - lo[a]), std::abs(y[a] - hi[a]));
    least += outside * outside;
    greatest += farthest * farthest;
  }
  return {std::sqrt(least), std::sqrt(greatest)};
}

}  // namespace

Vec3 seed_index_point(const Canvas& canvas, const Vec3& seed) {
  Vec3 p = canvas.index_coordinates(seed);
  if (canvas.dimension == 2) p.z() = 0.0;
  return p;
}

bool has_uniform_metric(const Canvas& canvas) {
  if (canvas.uniform_metric()) return true;
  const float* first = nullptr;
  for (std::size_t slot = 0; slot < canvas.slot_count(); ++slot) {
    if (!canvas.active[slot]) continue;
    const float* m = canvas.metric_of(slot);
    if (!first)
      first = m;
    else if (!std::equal(m, m + 6, first))
      return false;
  }
  return true;
}

bool fills_index_box(const Canvas& canvas) {
  const std::size_t box =
      static_cast<std::size_t>(canvas.dims[0]) * canvas.dims[1] * canvas.dims[2];
  return canvas.active_voxel_count == box;
}

bool first_metric_is_diagonal(const Canvas& canvas) {
  if (canvas.active_voxel_count == 0) return false;
  const float* m = canvas.metric_of(first_active_slot(canvas));  // .sol: m11 m12 m22 m13 m23 m33
  return m[1] == 0.0f && m[3] == 0.0f && m[4] == 0.0f;           // a 2D canvas stores m13 = m23 = 0
}

bool is_face_connected(const Canvas& canvas) {
  if (canvas.active_voxel_count == 0) return true;
  const int volume = canvas.brick_volume(), edge = Canvas::kBrickEdge;
  const int strides[3] = {1, edge, edge * edge};
  std::vector<std::uint8_t> reached(canvas.slot_count(), 0);
  std::vector<std::size_t> stack{first_active_slot(canvas)};
  reached[stack.back()] = 1;
  std::size_t count = 1;
  while (!stack.empty()) {
    const std::size_t slot = stack.back();
    stack.pop_back();
    const int local = static_cast<int>(slot % volume);
    const int coordinate[3] = {local % edge, (local / edge) % edge, local / (edge * edge)};
    for (int axis = 0; axis < canvas.dimension; ++axis)
      for (const int step : {-1, 1}) {
        const int moved = coordinate[axis] + step;
        std::int64_t next = static_cast<std::int64_t>(slot) + step * strides[axis];
        if (moved < 0 || moved >= edge) {  // across a brick face: through the brick table
          VoxelIndex v = canvas.voxel_of(slot);
          (axis == 0 ? v.i : axis == 1 ? v.j : v.k) += step;
          next = canvas.slot_of(v);
        }
        if (next < 0 || !canvas.active[next] || reached[next]) continue;
        reached[next] = 1;
        ++count;
        stack.push_back(static_cast<std::size_t>(next));
      }
  }
  return count == canvas.active_voxel_count;
}

ExactStartReach exact_start_reach(const Canvas& canvas, bool uniform_diagonal_metric) {
  if (!uniform_diagonal_metric || canvas.active_voxel_count == 0) return ExactStartReach::none;
  const bool every_brick =
      fills_index_box(canvas) || (canvas.convex_domain && is_face_connected(canvas));
  return every_brick ? ExactStartReach::every_brick
                     : ExactStartReach::quarters_that_see_their_seeds;
}

ExactStartReach exact_start_reach(const Canvas& canvas) {
  return exact_start_reach(canvas, first_metric_is_diagonal(canvas) && has_uniform_metric(canvas));
}

namespace {

// nearest_seed_candidates with the seeds' tree built (`scaled`, not empty).
BrickSeedLists candidate_lists(const Canvas& canvas, const ScaledSeeds& scaled,
                               const std::vector<std::uint8_t>* only_bricks) {
  BrickSeedLists lists;
  lists.begin.assign(canvas.brick_count() + 1, 0);
  std::vector<std::int32_t> found;
  std::vector<std::pair<double, double>> reach;  // least and greatest distance to the brick
  for (std::size_t brick = 0; brick < canvas.brick_count(); ++brick) {
    lists.begin[brick + 1] = static_cast<std::uint32_t>(lists.seeds.size());
    if (only_bricks && !(*only_bricks)[brick]) continue;
    const auto [lo, hi] = scaled.brick_box(canvas.brick_origins[brick]);
    const Vec3 centre = 0.5 * (lo + hi);
    const Vec3 extent = hi - lo;
    // Every voxel of the brick is within half its diameter of the centre, so no voxel's nearest
    // seed lies farther from the centre than the centre's nearest plus the diameter.
    const double radius = scaled.tree.nearest_distance(centre) + extent.norm();
    found.clear();
    scaled.tree.within(centre, radius * (1.0 + 1e-9) + 1e-9, found);  // rounding drops no seed
    // Of those, a seed whose least distance to the brick exceeds another's greatest is nearest
    // to none of its voxels.
    reach.clear();
    double least_greatest = std::numeric_limits<double>::infinity();
    for (const std::int32_t s : found) {
      reach.push_back(box_distances(scaled.points[s], lo, hi));
      least_greatest = std::min(least_greatest, reach.back().second);
    }
    std::size_t kept = 0;
    for (std::size_t n = 0; n < found.size(); ++n)
      if (reach[n].first <= least_greatest * (1.0 + 1e-9) + 1e-9) found[kept++] = found[n];
    found.resize(kept);
    std::sort(found.begin(), found.end());
    lists.seeds.insert(lists.seeds.end(), found.begin(), found.end());
    if (lists.seeds.size() > std::numeric_limits<std::uint32_t>::max())
      throw Error("nearest seeds: over 2^32 candidate entries (" +
                  std::to_string(scaled.points.size()) + " seeds on " +
                  std::to_string(canvas.brick_count()) + " bricks)");
    lists.begin[brick + 1] = static_cast<std::uint32_t>(lists.seeds.size());
  }
  lists.seen.assign(lists.seeds.size(), canvas.dimension == 3 ? 0xff : 0x0f);
  return lists;
}

// bricks_seeds_may_lower with the seeds' tree built (`scaled`).
std::vector<std::uint8_t> bricks_may_lower(const Canvas& canvas, const std::vector<Vec3>& seeds,
                                           const ScaledSeeds& scaled,
                                           const std::vector<float>& distance) {
  std::vector<std::uint8_t> lowered(canvas.brick_count(), 0);
  std::vector<std::uint8_t> visited(canvas.brick_count(), 0);
  std::vector<std::int32_t> queue;
  const auto visit = [&](std::int32_t brick) {
    if (brick >= 0 && !visited[brick]) {
      visited[brick] = 1;
      queue.push_back(brick);
    }
  };
  const auto brick_of = [](int i) { return i >= 0 ? i / Canvas::kBrickEdge : -1; };
  for (const Vec3& seed : seeds) {
    const VoxelIndex v = canvas.voxel_containing(seed);
    visit(canvas.brick_at(brick_of(v.i), brick_of(v.j), brick_of(v.k)));
  }
  while (!queue.empty()) {
    const std::int32_t brick = queue.back();
    queue.pop_back();
    const VoxelIndex& o = canvas.brick_origins[brick];
    const auto [lo, hi] = scaled.brick_box(o);
    // No seed is nearer to a voxel of the brick than the centre's nearest less the radius.
    const double least = scaled.tree.nearest_distance(0.5 * (lo + hi)) - 0.5 * (hi - lo).norm();
    if (!(least * canvas.voxel_size <= greatest_distance(canvas, brick, distance) * (1.0 + 1e-5)))
      continue;
    lowered[brick] = 1;
    const int b[3] = {o.i / Canvas::kBrickEdge, o.j / Canvas::kBrickEdge, o.k / Canvas::kBrickEdge};
    for (int axis = 0; axis < canvas.dimension; ++axis)  // through the faces
      for (const int step : {-1, 1}) {
        int n[3] = {b[0], b[1], b[2]};
        n[axis] += step;
        visit(canvas.brick_at(n[0], n[1], n[2]));
      }
  }
  return lowered;
}

// Clears the seen bits where the reach asks for it (exact_start_lists).
void mark_reach(const Canvas& canvas, const std::vector<Vec3>& seeds, ExactStartReach reach,
                BrickSeedLists& lists) {
  if (reach != ExactStartReach::every_brick) mark_where_seeds_are_seen(canvas, seeds, lists);
}

}  // namespace

BrickSeedLists nearest_seed_candidates(const Canvas& canvas, const std::vector<Vec3>& seeds,
                                       const std::vector<std::uint8_t>* only_bricks) {
  if (canvas.active_voxel_count == 0) throw Error("nearest seeds: the canvas has no active voxel");
  if (seeds.empty()) {
    BrickSeedLists lists;
    lists.begin.assign(canvas.brick_count() + 1, 0);
    return lists;
  }
  return candidate_lists(canvas, ScaledSeeds(canvas, seeds), only_bricks);
}

BrickSeedLists exact_start_lists(const Canvas& canvas, const std::vector<Vec3>& seeds,
                                 ExactStartReach reach,
                                 const std::vector<std::uint8_t>* only_bricks) {
  BrickSeedLists lists = nearest_seed_candidates(canvas, seeds, only_bricks);
  mark_reach(canvas, seeds, reach, lists);
  return lists;
}

std::vector<std::uint8_t> bricks_seeds_may_lower(const Canvas& canvas,
                                                 const std::vector<Vec3>& seeds,
                                                 const std::vector<float>& distance) {
  if (seeds.empty() || canvas.active_voxel_count == 0)
    return std::vector<std::uint8_t>(canvas.brick_count(), 0);
  return bricks_may_lower(canvas, seeds, ScaledSeeds(canvas, seeds), distance);
}

// The new seeds' tree serves both the search and the lists.
BrickSeedLists insertion_start_lists(const Canvas& canvas, const std::vector<Vec3>& seeds,
                                     std::size_t first_new, const std::vector<float>& distance,
                                     ExactStartReach reach) {
  const std::vector<Vec3> new_seeds(seeds.begin() + static_cast<std::ptrdiff_t>(first_new),
                                    seeds.end());
  if (new_seeds.empty() || canvas.active_voxel_count == 0)
    return nearest_seed_candidates(canvas, new_seeds);  // its checks and empty lists
  const ScaledSeeds scaled(canvas, new_seeds);
  const std::vector<std::uint8_t> bricks = bricks_may_lower(canvas, new_seeds, scaled, distance);
  BrickSeedLists lists = candidate_lists(canvas, scaled, &bricks);
  mark_reach(canvas, new_seeds, reach, lists);
  for (std::int32_t& label : lists.seeds) label += static_cast<std::int32_t>(first_new);
  return lists;
}

}  // namespace rvor
