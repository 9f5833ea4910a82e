// Per-seed local distance fields (local_fields.h): stars from the nerve, one single-source
// reference solve per seed on a cropped canvas active on the star.
#include "rvor/local_fields.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>
#include <functional>
#include <mutex>
#include <string>
#include <unordered_map>
#include <utility>

#include "dual_internal.h"
#include "parallel_for.h"
#include "reference_solver.h"
#include "rvor/error.h"
#include "rvor/memory_budget.h"
#include "rvor/spec_text.h"
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
// axis by the margin plus a fraction of its extent, clipped to the canvas. The mask (star_mask.h)
// is cut by the box where a simplex's margin reaches beyond it: mostly the caps of the edges'
// capsules beyond the neighbours, where the seed's field is not needed (an edge's geodesic runs
// between its seeds). Boxes grown to every simplex's margin (tried 2026-12-05, code not kept) held
// 15% more voxels (kept fields and the solves' memory) and took longer, for edges of nearly the
// same lengths (3D hyperbolic_shock 48^3 and radial_shock_3d 96^3: at most 2% apart).
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

// The longest a voxel-length step can measure in the metric, per unit of index length.
double largest_scale(const Mat3& G, int dimension) {
  return std::sqrt(metric_eigenvalues(G, dimension).maxCoeff());
}

// The distance within which each seed's field is solved. Each nerve edge (a, b) has a bound
// D(a, b) of d(a, b): at its nearest witness, a canvas simplex with a vertex p_a labeled a and
// p_b labeled b and u(w) the largest distance of its vertices, d(a, b) <= u(p_a) + d(p_a, p_b) +
// u(p_b) <= 2 u(w) + sqrt(dim) voxels (the cell's diagonal) at the largest metric scale of the
// witness's vertex of largest distance (the slot it records; a shock between the vertices is left
// to the margin).
// That step matters where the metric is large: with 2 u(w) alone, u_a(b) exceeded D on 80% of the
// edges of 3D hyperbolic_shock (48^3, 400 seeds), by 11% at the median and 94% at the 90th
// percentile. The geodesic from a to b stays within D(a, b) of a. A curved face of the triangle
// (v, x, y) traced towards the apex v is made of geodesics to v from the points q of the curved
// edge xy, and by the triangle inequality (any metric) d(v, q) <= min(d(v, x) + d(x, q),
// d(v, y) + d(y, q)) <= max(D(v, x), D(v, y)) + D(x, y) / 2; the points of a geodesic from q to v
// are closer to v still. Faces try each seed of their triangle as apex, so every vertex of every
// nerve triangle (in 3D also those of no tetrahedron) takes that bound. The limit is the largest
// bound over the seed's edges and triangles, at least 1.1 * 2 u(w) over its edges (the earlier
// limit), plus the margin (voxels) for the discretisation, at the largest metric scale of the seed
// and of the witnesses of the edges of its triangles (where the distances above are measured).
std::vector<double> distance_limits(const Canvas& canvas, const Nerve& nerve,
                                    const std::vector<Mat3>& seed_metrics,
                                    const LocalFieldOptions& options) {
  const double diagonal = std::sqrt(static_cast<double>(canvas.dimension)) * canvas.voxel_size;
  std::vector<double> bound(seed_metrics.size(), 0.0), scale(seed_metrics.size());
  for (std::size_t s = 0; s < seed_metrics.size(); ++s)
    scale[s] = largest_scale(seed_metrics[s], canvas.dimension);
  std::vector<double> edge_bound(nerve.edges.size()), witness_scale(nerve.edges.size(), 0.0);
  for (std::size_t e = 0; e < nerve.edges.size(); ++e) {
    const NerveSimplex& edge = nerve.edges[e];
    if (edge.nearest.slot >= 0)
      witness_scale[e] = largest_scale(
          canvas.metric_at(static_cast<std::size_t>(edge.nearest.slot)), canvas.dimension);
    const double twice_u = 2.0 * static_cast<double>(edge.nearest.distance);
    edge_bound[e] = twice_u + diagonal * witness_scale[e];
    for (int v = 0; v < 2; ++v) {
      const auto s = static_cast<std::size_t>(edge.seeds[v]);
      bound[s] = std::max({bound[s], 1.1 * twice_u, edge_bound[e]});
      scale[s] = std::max(scale[s], witness_scale[e]);
    }
  }
  for (const NerveSimplex& triangle : nerve.triangles) {
    std::array<std::size_t, 3> opposite{};  // the edge opposite each vertex
    bool complete = true;
    for (std::size_t v = 0; v < 3; ++v) {
      const NerveSimplex* e =
          nerve.find({triangle.seeds[(v + 1) % 3], triangle.seeds[(v + 2) % 3]});
      if (!e)
        complete = false;  // not in a nerve, which is closed under faces
      else
        opposite[v] = static_cast<std::size_t>(e - nerve.edges.data());
    }
    if (!complete) continue;
    for (std::size_t v = 0; v < 3; ++v) {
      const auto s = static_cast<std::size_t>(triangle.seeds[v]);
      const double adjacent =
          std::max(edge_bound[opposite[(v + 1) % 3]], edge_bound[opposite[(v + 2) % 3]]);
      bound[s] = std::max(bound[s], adjacent + 0.5 * edge_bound[opposite[v]]);
      for (std::size_t e : opposite) scale[s] = std::max(scale[s], witness_scale[e]);
    }
  }
  std::vector<double> limits(seed_metrics.size());
  for (std::size_t s = 0; s < seed_metrics.size(); ++s)
    limits[s] = bound[s] + options.margin * canvas.voxel_size * scale[s];
  return limits;
}

// The simplices of each seed's star in index coordinates, each with its margin (voxels, plus a
// fraction of its longest edge: room for geodesics that bend). Every edge goes to both its seeds,
// for its geodesic descends both fields. A top simplex over which the metric is nearly uniform
// goes only to the apexes of its triangles (a face is traced towards its smallest seed first,
// curved_dual.cpp): its smallest seed, and in 3D its second smallest, the apex of the triangle
// opposite the smallest; there geodesics are nearly straight and the others never trace one
// through it. Where the metric varies more (LocalFieldOptions::apex_only_distortion), it goes to
// all its seeds, whose edge geodesics may bend through it. An edge takes a wider margin in a
// seed's star (LocalFieldOptions::edge_relative_margin) unless the star holds every top simplex
// around it and they close around it (EdgeSurroundings): otherwise its capsule alone holds, on
// some side, the stencils that its segment's values read.
// Per nerve edge (key: its seeds): the distortion between its seeds' metrics, and what surrounds
// it: the top simplices around it, how many of them each of its seeds holds, and (3D) the degree
// of each vertex of its link, the edges opposite it in its tetrahedra.
struct EdgeSurroundings {
  double distortion = 1.0;  // between its seeds' metrics
  int tops = 0;
  std::array<int, 2> held{0, 0};
  std::vector<std::pair<int32_t, int>> link_degrees;

  void add_link_vertex(int32_t v) {
    for (auto& [vertex, degree] : link_degrees)
      if (vertex == v) {
        ++degree;
        return;
      }
    link_degrees.emplace_back(v, 1);
  }
  // Whether the tops close around the edge: two triangles in 2D, a cycle of tetrahedra in 3D.
  bool interior(int dimension) const {
    if (dimension == 2) return tops == 2;
    if (link_degrees.size() < 3) return false;
    for (const auto& entry : link_degrees)
      if (entry.second != 2) return false;
    return true;
  }
};

std::uint64_t edge_key(int32_t a, int32_t b) {
  return static_cast<std::uint64_t>(static_cast<std::uint32_t>(std::min(a, b))) << 32 |
         static_cast<std::uint32_t>(std::max(a, b));
}

std::vector<std::vector<detail::StarSimplex>> star_simplices(const Canvas& canvas,
                                                             const Nerve& nerve,
                                                             const std::vector<Vec3>& seeds,
                                                             const std::vector<Mat3>& seed_metrics,
                                                             const LocalFieldOptions& options) {
  std::vector<std::vector<detail::StarSimplex>> stars(seeds.size());
  auto star_of = [&](const NerveSimplex& simplex, double relative_margin) {
    detail::StarSimplex star;
    for (int v = 0; v < simplex.vertex_count; ++v) {
      Vec3 x = canvas.index_coordinates(seeds[static_cast<std::size_t>(simplex.seeds[v])]);
      if (canvas.dimension == 2) x.z() = 0.0;
      star.vertices.push_back(x);
    }
    double longest = 0.0;
    for (const Vec3& p : star.vertices)
      for (const Vec3& q : star.vertices) longest = std::max(longest, (p - q).norm());
    star.margin = options.margin + relative_margin * longest;
    return star;
  };
  // The edges of a top simplex are nerve edges: the nerve is closed under faces.
  std::unordered_map<std::uint64_t, EdgeSurroundings> surroundings;
  for (const NerveSimplex& edge : nerve.edges)
    surroundings[edge_key(edge.seeds[0], edge.seeds[1])].distortion =
        distortion(seed_metrics[static_cast<std::size_t>(edge.seeds[0])],
                   seed_metrics[static_cast<std::size_t>(edge.seeds[1])]);
  for (const NerveSimplex& top : nerve.top_simplices()) {
    double spread = 1.0;  // the largest distortion between two of its seeds' metrics
    for (int u = 0; u < top.vertex_count; ++u)
      for (int v = u + 1; v < top.vertex_count; ++v)
        spread = std::max(spread, surroundings[edge_key(top.seeds[u], top.seeds[v])].distortion);
    const int apexes = std::max(1, top.vertex_count - 2);
    const int owners = spread <= options.apex_only_distortion ? apexes : top.vertex_count;
    const detail::StarSimplex star = star_of(top, options.relative_margin);
    for (int v = 0; v < owners; ++v)  // seeds ascending (nerve.h)
      stars[static_cast<std::size_t>(top.seeds[v])].push_back(star);
    for (int u = 0; u < top.vertex_count; ++u)
      for (int v = u + 1; v < top.vertex_count; ++v) {
        EdgeSurroundings& around = surroundings[edge_key(top.seeds[u], top.seeds[v])];
        ++around.tops;
        around.held[0] += u < owners ? 1 : 0;
        around.held[1] += v < owners ? 1 : 0;
        for (int w = 0; w < top.vertex_count; ++w)
          if (w != u && w != v && top.vertex_count == 4) around.add_link_vertex(top.seeds[w]);
      }
  }
  for (const NerveSimplex& edge : nerve.edges) {
    const auto found = surroundings.find(edge_key(edge.seeds[0], edge.seeds[1]));
    for (int side = 0; side < 2; ++side) {
      const bool surrounded = found != surroundings.end() &&
                              found->second.held[side] == found->second.tops &&
                              found->second.interior(canvas.dimension);
      stars[static_cast<std::size_t>(edge.seeds[side])].push_back(
          star_of(edge, surrounded ? options.relative_margin : options.edge_relative_margin));
    }
  }
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
               canvas.world_of(VoxelIndex{box.lo[0], box.lo[1], box.lo[2]}), dims, origins,
               canvas.uniform_metric());
  const bool per_slot = !out.uniform_metric();
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
    if (per_slot)
      std::memcpy(out.mutable_metric(slot), canvas.metric_of(static_cast<std::size_t>(source)),
                  6 * sizeof(float));
  }
  out.finalize();
  return out;
}

// The solved values of a crop (its bricks are the box's, in the same order and layout) as a
// LocalField that keeps the bricks holding one.
LocalField kept_bricks(const Canvas& cropped, const IndexBox& box, const detail::ExactField& exact,
                       double limit) {
  LocalField local;
  local.lo = box.lo;
  local.dims = cropped.dims;
  local.brick_dims = cropped.brick_grid_dims;
  local.brick_edge_z = cropped.brick_edge_z();
  local.brick_start.assign(cropped.brick_count(), -1);
  const std::size_t volume = static_cast<std::size_t>(cropped.brick_volume());
  for (std::size_t brick = 0; brick < cropped.brick_count(); ++brick)
    for (std::size_t slot = brick * volume; slot < (brick + 1) * volume; ++slot) {
      if (!cropped.active[slot] || !(exact.distance[slot] <= limit)) continue;
      if (local.brick_start[brick] < 0) {
        local.brick_start[brick] = static_cast<int32_t>(local.values.size());
        local.values.resize(local.values.size() + volume, std::numeric_limits<float>::infinity());
      }
      local.values[static_cast<std::size_t>(local.brick_start[brick]) + slot - brick * volume] =
          static_cast<float>(exact.distance[slot]);
    }
  return local;
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
  return kept_bricks(cropped, box, exact, limit);
}

// Bytes a seed's solve holds per voxel of its star box while it runs: the cropped canvas (whole
// bricks), the reference solver's state, stencils, reverse stencil graph and single-source terms,
// and the double field. Measured: peak resident memory of `rvor voronoi --domain
// box:1,1,1,11,11,11 --metric radial_shock_3d --random-seeds 10 --dual curved` less the same run
// with `--dual straight` and the fields kept, over the two largest boxes (two solves in flight on
// 2 cores): 240 B at --resolution 96 (boxes of 590k voxels, with single-source terms), 165 B at
// 192 (3.3M, without). A third more, for what the measure does not see.
constexpr double kSolveBytesPerBoxVoxel = 320;

double box_voxels(const IndexBox& box) {
  double voxels = 1;
  for (int a = 0; a < 3; ++a) voxels *= box.hi[a] - box.lo[a] + 1;
  return voxels;
}

// How many seeds' solves may run at once: the fields kept (a float per voxel of every star box)
// and the largest solves in flight, beside the canvas and its field, within the budget. Throws
// rvor::Error when one solve does not fit.
std::size_t solves_within_budget(const Canvas& canvas, const std::vector<IndexBox>& boxes,
                                 const std::vector<std::vector<detail::StarSimplex>>& stars,
                                 std::uint64_t budget_option) {
  const double budget = static_cast<double>(resolved_memory_budget(budget_option));
  const double held = static_cast<double>(canvas.active_voxel_count) *
                      static_cast<double>(canvas_and_field_bytes_per_active_voxel(
                          canvas.uniform_metric().has_value()));
  double kept = 0;
  std::vector<double> solves;  // bytes of each seed's solve, largest first
  for (std::size_t s = 0; s < boxes.size(); ++s) {
    if (stars[s].empty()) continue;  // not solved (compute_local_fields)
    kept += sizeof(float) * box_voxels(boxes[s]);
    solves.push_back(kSolveBytesPerBoxVoxel * box_voxels(boxes[s]));
  }
  if (solves.empty()) return 1;
  std::sort(solves.begin(), solves.end(), std::greater<double>());
  if (held + kept + solves[0] > budget)
    throw Error("curved dual: the seeds' local fields need ~" + format_bytes(kept) + " kept and ~" +
                format_bytes(solves[0]) + " for the largest seed's solve, beside ~" +
                format_bytes(held) + " for the canvas and its field, over the memory budget of " +
                format_bytes(budget) +
                " (--memory-budget): use --dual straight, a coarser --resolution, or a larger "
                "budget");
  std::size_t threads = 1;
  double in_flight = solves[0];
  while (threads < solves.size() && held + kept + in_flight + solves[threads] <= budget)
    in_flight += solves[threads++];
  return threads;
}

}  // namespace

namespace {

// Margins and the distortion bound as LocalFieldOptions documents them: a negative margin or a
// huge one sized a vector past max_size (std::length_error), NaN was taken.
void require_valid_options(const LocalFieldOptions& options) {
  const auto require = [](bool valid, const char* name, double value, const char* rule) {
    if (!valid)
      throw Error(std::string("local fields: LocalFieldOptions::") + name + " is " +
                  exact_text(value) + ", not " + rule);
  };
  require(options.margin >= 0 && options.margin <= 1000, "margin", options.margin,
          "a voxel count from 0 to 1000");
  for (const auto& [name, value] :
       {std::pair<const char*, double>{"relative_margin", options.relative_margin},
        {"edge_relative_margin", options.edge_relative_margin}})
    require(value >= 0 && value <= 10, name, value, "a fraction of an edge from 0 to 10");
  // +inf is meaningful: every top simplex to its apexes' stars only.
  require(options.apex_only_distortion >= 0, "apex_only_distortion", options.apex_only_distortion,
          "a distortion >= 0");
}

}  // namespace

// compute_local_fields itself; the public entry point names a failed allocation.
static LocalFields compute_local_fields_itself(const Canvas& canvas, const Nerve& nerve,
                                               const std::vector<Vec3>& given_seeds,
                                               const LocalFieldOptions& options) {
  require_valid_options(options);
  const auto t0 = std::chrono::steady_clock::now();
  const std::vector<Vec3> seeds =
      dual::checked_dual_seeds(canvas, nerve, given_seeds, "local fields");
  const std::vector<Mat3> seed_metrics = dual::seed_metrics(canvas, seeds);
  const std::vector<IndexBox> boxes = star_boxes(canvas, nerve, seeds, options);
  const std::vector<double> limits = distance_limits(canvas, nerve, seed_metrics, options);
  const std::vector<std::vector<detail::StarSimplex>> stars =
      star_simplices(canvas, nerve, seeds, seed_metrics, options);

  LocalFields out;
  out.canvas_hash = canvas.content_hash();
  out.seeds = seeds;
  out.fields.resize(seeds.size());
  // One seed per task: solves are independent and each is large enough to amortise a thread.
  const std::size_t to_solve = static_cast<std::size_t>(
      std::count_if(stars.begin(), stars.end(), [](const auto& star) { return !star.empty(); }));
  std::size_t solved = 0;
  std::mutex progress_mutex;
  detail::parallel_for(
      seeds.size(), 1,
      [&](std::size_t s) {
        // A seed without Delaunay neighbours (a lone seed, or one whose cell is empty: it shares
        // its voxel with another) needs no geodesics: its field stays empty, +inf everywhere.
        if (stars[s].empty()) return;
        out.fields[s] = solve_local(canvas, boxes[s], stars[s], seeds[s], limits[s]);
        const std::lock_guard<std::mutex> lock(progress_mutex);
        ++solved;
        if (options.progress) options.progress(solved, to_solve);
      },
      solves_within_budget(canvas, boxes, stars, options.memory_budget));
  for (const LocalField& f : out.fields) {
    out.voxels += f.values.size();
    for (float u : f.values) out.solved_voxels += std::isfinite(u) ? 1 : 0;
  }
  out.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return out;
}

LocalFields compute_local_fields(const Canvas& canvas, const Nerve& nerve,
                                 const std::vector<Vec3>& given_seeds,
                                 const LocalFieldOptions& options) {
  return naming_out_of_memory("computing the local fields", [&] {
    return compute_local_fields_itself(canvas, nerve, given_seeds, options);
  });
}

}  // namespace rvor
