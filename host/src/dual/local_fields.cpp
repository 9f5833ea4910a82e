// Per-seed local distance fields (local_fields.h): stars from the nerve, one single-source
// reference solve per seed on a cropped canvas active on the star.
#include "rvor/local_fields.h"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>
#include <string>

#include "dual_internal.h"
#include "parallel_for.h"
#include "reference_solver.h"
#include "rvor/error.h"
#include "star_mask.h"

namespace rvor {

namespace {

struct IndexBox {
  std::array<int, 3> lo{std::numeric_limits<int>::max(), std::numeric_limits<int>::max(),
                        std::numeric_limits<int>::max()};
  std::array<int, 3> hi{std::numeric_limits<int>::min(), std::numeric_limits<int>::min(),
                        std::numeric_limits<int>::min()};  // inclusive

  void add(const VoxelIndex& v) { add(IndexBox{{v.i, v.j, v.k}, {v.i, v.j, v.k}}); }
  void add(const IndexBox& b) {
    for (int a = 0; a < 3; ++a) {
      lo[a] = std::min(lo[a], b.lo[a]);
      hi[a] = std::max(hi[a], b.hi[a]);
    }
  }
  bool empty() const { return lo[0] > hi[0]; }
};

// The bounding box of every seed's star: its voxel and its nerve neighbours' voxels, grown on each
// axis by the margin plus a fraction of its extent (at least the simplices' margins), clipped to
// the canvas.
std::vector<IndexBox> star_boxes(const Canvas& canvas, const Nerve& nerve,
                                 const std::vector<Vec3>& seeds, const LocalFieldOptions& options) {
  std::vector<VoxelIndex> voxels;
  for (const Vec3& s : seeds) voxels.push_back(canvas.voxel_containing(s));
  std::vector<IndexBox> stars(seeds.size());
  for (std::size_t s = 0; s < seeds.size(); ++s) stars[s].add(voxels[s]);
  for (const NerveSimplex& e : nerve.edges) {
    const auto a = static_cast<std::size_t>(e.seeds[0]), b = static_cast<std::size_t>(e.seeds[1]);
    stars[a].add(voxels[b]);
    stars[b].add(voxels[a]);
  }
  for (IndexBox& box : stars)
    for (int a = 0; a < canvas.dimension; ++a) {
      const int grow =
          options.margin +
          static_cast<int>(std::ceil(options.relative_margin * (box.hi[a] - box.lo[a])));
      box.lo[a] = std::max(0, box.lo[a] - grow);
      box.hi[a] = std::min(canvas.dims[a] - 1, box.hi[a] + grow);
    }
  return stars;
}

// The distance within which each seed's field is solved: every geodesic from a to a neighbour b
// (and, in a uniform metric, every point of a triangle of a's star) is within d(a, b) of a, and
// d(a, b) <= u_a(w) + u_b(w) ~ 2 u(w) at the edge's nearest witness w (the labeled distance there;
// exact for Gabriel edges, an upper bound for the others). Grown by 10% and the margin (voxels,
// at the seed's largest metric scale) for geodesics that bend and the witness's discretisation.
std::vector<double> distance_limits(const Canvas& canvas, const Nerve& nerve,
                                    const std::vector<Vec3>& seeds,
                                    const LocalFieldOptions& options) {
  std::vector<double> reach(seeds.size(), 0.0);
  for (const NerveSimplex& e : nerve.edges)
    for (int s = 0; s < 2; ++s) {
      double& r = reach[static_cast<std::size_t>(e.seeds[s])];
      r = std::max(r, 2.0 * static_cast<double>(e.nearest.distance));
    }
  std::vector<double> limits(seeds.size());
  for (std::size_t s = 0; s < seeds.size(); ++s) {
    const Mat3 G = dual::seed_metric(canvas, seeds, s);
    const double scale = std::sqrt(Eigen::SelfAdjointEigenSolver<Mat3>(G).eigenvalues().maxCoeff());
    limits[s] = 1.1 * reach[s] + options.margin * canvas.voxel_size * scale;
  }
  return limits;
}

// The simplices of each seed's star in index coordinates: its top simplices and its edges (an
// edge without a top simplex still needs its segment), each with the margin plus a fraction of
// its longest edge (room for geodesics that bend).
std::vector<std::vector<detail::StarSimplex>> star_simplices(const Canvas& canvas,
                                                             const Nerve& nerve,
                                                             const std::vector<Vec3>& seeds,
                                                             const LocalFieldOptions& options) {
  std::vector<std::vector<detail::StarSimplex>> stars(seeds.size());
  auto add = [&](const NerveSimplex& simplex) {
    detail::StarSimplex star;
    for (int v = 0; v < simplex.vertex_count; ++v) {
      Vec3 x = canvas.index_coordinates(seeds[static_cast<std::size_t>(simplex.seeds[v])]);
      if (canvas.dimension == 2) x.z() = 0.0;
      star.vertices.push_back(x);
    }
    double longest = 0.0;
    for (const Vec3& p : star.vertices)
      for (const Vec3& q : star.vertices) longest = std::max(longest, (p - q).norm());
    star.margin = options.margin + options.relative_margin * longest;
    for (int v = 0; v < simplex.vertex_count; ++v)
      stars[static_cast<std::size_t>(simplex.seeds[v])].push_back(star);
  };
  for (const NerveSimplex& top : nerve.top_simplices()) add(top);
  for (const NerveSimplex& edge : nerve.edges) add(edge);
  return stars;
}

// A copy of the canvas restricted to the box (same voxel size; its voxel (0,0,0) is the box's
// lowest voxel), every brick of the box allocated, active where the canvas is and the mask (dense
// over the box, x fastest) is set.
Canvas crop(const Canvas& canvas, const IndexBox& box, const std::vector<uint8_t>& mask) {
  std::array<int, 3> dims{};
  for (int a = 0; a < 3; ++a) dims[a] = box.hi[a] - box.lo[a] + 1;
  const int ez = canvas.brick_edge_z(), e = Canvas::kBrickEdge;
  std::vector<VoxelIndex> origins;
  for (int k = 0; k < dims[2]; k += ez)
    for (int j = 0; j < dims[1]; j += e)
      for (int i = 0; i < dims[0]; i += e) origins.push_back({i, j, k});
  Canvas out;
  out.allocate(canvas.dimension, canvas.voxel_size,
               canvas.world_of(VoxelIndex{box.lo[0], box.lo[1], box.lo[2]}), dims, origins);
  for (std::size_t slot = 0; slot < out.slot_count(); ++slot) {
    const VoxelIndex v = out.voxel_of(slot);
    if (v.i >= dims[0] || v.j >= dims[1] || v.k >= dims[2]) continue;  // brick padding
    if (!mask[static_cast<std::size_t>(v.i) +
              static_cast<std::size_t>(dims[0]) *
                  (static_cast<std::size_t>(v.j) + static_cast<std::size_t>(dims[1]) * v.k)])
      continue;
    const int64_t source = canvas.slot_of(v.i + box.lo[0], v.j + box.lo[1], v.k + box.lo[2]);
    if (source < 0) continue;
    out.active[slot] = 1;
    std::memcpy(&out.metric[6 * slot], &canvas.metric[6 * static_cast<std::size_t>(source)],
                6 * sizeof(float));
  }
  out.finalize();
  return out;
}

LocalField solve_local(const Canvas& canvas, const IndexBox& box,
                       const std::vector<detail::StarSimplex>& star, const Vec3& seed,
                       double limit) {
  std::array<int, 3> dims{};
  for (int a = 0; a < 3; ++a) dims[a] = box.hi[a] - box.lo[a] + 1;
  const Canvas cropped = crop(canvas, box, detail::star_mask(box.lo, dims, canvas.dimension, star));
  detail::ReferenceSolver solver(cropped);
  solver.set_distance_limit(limit);
  detail::ExactField exact;
  solver.solve(cropped, {seed}, exact);
  LocalField local;
  local.lo = box.lo;
  for (int a = 0; a < 3; ++a) local.dims[a] = cropped.dims[a];
  local.distance.assign(static_cast<std::size_t>(local.dims[0]) * local.dims[1] * local.dims[2],
                        std::numeric_limits<float>::infinity());
  for (std::size_t slot = 0; slot < cropped.slot_count(); ++slot) {
    if (!cropped.active[slot]) continue;
    const VoxelIndex v = cropped.voxel_of(slot);
    local.distance[static_cast<std::size_t>(v.i) +
                   static_cast<std::size_t>(local.dims[0]) *
                       (static_cast<std::size_t>(v.j) +
                        static_cast<std::size_t>(local.dims[1]) * v.k)] =
        exact.distance[slot] <= limit ? static_cast<float>(exact.distance[slot])
                                      : std::numeric_limits<float>::infinity();
  }
  return local;
}

}  // namespace

LocalFields compute_local_fields(const Canvas& canvas, const Nerve& nerve,
                                 const std::vector<Vec3>& given_seeds,
                                 const LocalFieldOptions& options) {
  const auto t0 = std::chrono::steady_clock::now();
  const std::vector<Vec3> seeds =
      dual::checked_dual_seeds(canvas, nerve, given_seeds, "local fields");
  const std::vector<IndexBox> boxes = star_boxes(canvas, nerve, seeds, options);
  const std::vector<double> limits = distance_limits(canvas, nerve, seeds, options);
  const std::vector<std::vector<detail::StarSimplex>> stars =
      star_simplices(canvas, nerve, seeds, options);

  LocalFields out;
  out.fields.resize(seeds.size());
  // One seed per task: solves are independent and each is large enough to amortise a thread.
  detail::parallel_for(seeds.size(), 1, [&](std::size_t s) {
    // A seed without Delaunay neighbours (a lone seed, or one whose cell is empty: it shares its
    // voxel with another) needs no geodesics: its field stays empty, +inf everywhere.
    if (stars[s].empty()) return;
    out.fields[s] = solve_local(canvas, boxes[s], stars[s], seeds[s], limits[s]);
  });
  for (const LocalField& f : out.fields) {
    out.voxels += f.distance.size();
    for (float u : f.distance) out.solved_voxels += std::isfinite(u) ? 1 : 0;
  }
  out.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return out;
}

}  // namespace rvor
