// Assembles the straight dual from the nerve and runs its checks (topology, exact geometry,
// quality), then condenses them into DualChecks and per-element flags.
#include <algorithm>
#include <chrono>

#include "dual/dual_internal.h"
#include "rvor/error.h"

namespace rvor {

namespace {

template <std::size_t N>
std::vector<std::array<int32_t, N>> seed_tuples(const std::vector<NerveSimplex>& simplices) {
  std::vector<std::array<int32_t, N>> out;
  out.reserve(simplices.size());
  for (const NerveSimplex& s : simplices) {
    std::array<int32_t, N> t{};
    std::copy(s.seeds.begin(), s.seeds.begin() + N, t.begin());
    out.push_back(t);
  }
  return out;
}

template <std::size_t N>
void sort_unique(std::vector<std::array<int32_t, N>>& v) {
  std::sort(v.begin(), v.end());
  v.erase(std::unique(v.begin(), v.end()), v.end());
}

// The size-N faces of the given simplices (top_size vertices each), sorted and distinct.
template <std::size_t N, typename Simplices, typename SeedsOf>
std::vector<std::array<int32_t, N>> faces_of(const Simplices& simplices, int top_size,
                                             SeedsOf seeds_of) {
  std::vector<std::array<int32_t, N>> faces;
  for (const auto& simplex : simplices) {
    const std::array<int32_t, 4>& t = seeds_of(simplex);
    for (unsigned mask = 0; mask < (1u << top_size); ++mask) {
      if (__builtin_popcount(mask) != static_cast<int>(N)) continue;
      std::array<int32_t, N> f{};
      int m = 0;
      for (int v = 0; v < top_size; ++v)
        if (mask & (1u << v)) f[m++] = t[v];
      faces.push_back(f);
    }
  }
  sort_unique(faces);
  return faces;
}

// The size-N faces of the top simplices, and the nerve's size-N simplices that no witnessed top
// simplex contains (near the boundary, a simplex is witnessed without its Voronoi vertex).
template <std::size_t N>
std::vector<std::array<int32_t, N>> lower_simplices(const std::vector<std::array<int32_t, 4>>& tops,
                                                    const std::vector<NerveSimplex>& witnessed,
                                                    const std::vector<NerveSimplex>& nerve_tops,
                                                    int top_size) {
  std::vector<std::array<int32_t, N>> faces = faces_of<N>(
      tops, top_size, [](const std::array<int32_t, 4>& t) -> const auto& { return t; });
  const std::vector<std::array<int32_t, N>> nerve_faces = faces_of<N>(
      nerve_tops, top_size, [](const NerveSimplex& t) -> const auto& { return t.seeds; });
  for (const auto& t : seed_tuples<N>(witnessed))
    if (!std::binary_search(nerve_faces.begin(), nerve_faces.end(), t)) faces.push_back(t);
  sort_unique(faces);
  return faces;
}

void set_simplices(const Nerve& nerve, const dual::LocalDelaunay& local, StraightDual& dual) {
  const int top_size = dual.dimension + 1;
  const auto& nerve_tops = nerve.top_simplices();
  dual.edges = lower_simplices<2>(local.top, nerve.edges, nerve_tops, top_size);
  if (dual.dimension == 3) {
    dual.triangles = lower_simplices<3>(local.top, nerve.triangles, nerve_tops, top_size);
    dual.tetrahedra = local.top;
  } else {
    dual.triangles.clear();
    for (const auto& t : local.top) dual.triangles.push_back({t[0], t[1], t[2]});
  }
  dual.flags.assign(dual.top_count(), 0);
  for (std::size_t t = 0; t < local.top.size(); ++t)
    if (local.near_degenerate[t]) {
      dual.flags[t] |= kDualNearDegenerate;
      ++dual.checks.near_degenerate;
    }
  dual.checks.near_degenerate_removed = local.removed;
  dual.checks.near_degenerate_added = local.added;
}

// Inverted: orientation (consistent across manifold facets) against its component's majority.
void mark_inverted(const dual::Topology& topo, const std::vector<int>& orientation,
                   StraightDual& dual) {
  // Per component: positive minus negative elements.
  std::vector<long> balance(orientation.size(), 0);
  for (std::size_t t = 0; t < orientation.size(); ++t)
    balance[topo.component[t]] += orientation[t] * topo.parity[t];
  for (std::size_t t = 0; t < orientation.size(); ++t) {
    const int majority = balance[topo.component[t]] >= 0 ? 1 : -1;
    if (orientation[t] * topo.parity[t] != majority) {
      dual.checks.inverted_elements.push_back(t);
      dual.flags[t] |= kDualInverted;
    }
  }
  dual.checks.inverted = dual.checks.inverted_elements.size();
}

void mark_intersecting(const std::vector<std::array<std::size_t, 2>>& pairs, StraightDual& dual) {
  for (const auto& p : pairs) {
    dual.flags[p[0]] |= kDualIntersecting;
    dual.flags[p[1]] |= kDualIntersecting;
  }
  for (std::size_t t = 0; t < dual.flags.size(); ++t)
    if (dual.flags[t] & kDualIntersecting) dual.checks.intersecting_elements.push_back(t);
  dual.checks.intersecting = dual.checks.intersecting_elements.size();
  dual.checks.intersecting_pairs = pairs.size();
  dual.checks.intersecting_element_pairs.assign(
      pairs.begin(), pairs.begin() + std::min(pairs.size(), DualChecks::kMaxListed));
}

void apply_topology(const dual::Topology& topo, StraightDual& dual) {
  DualChecks& c = dual.checks;
  for (std::size_t t = 0; t < dual.flags.size(); ++t)
    if (topo.on_non_manifold_facet[t]) dual.flags[t] |= kDualNonManifold;
  c.non_manifold = topo.non_manifold_facets.size() + topo.non_manifold_boundary;
  c.non_manifold_facets.assign(
      topo.non_manifold_facets.begin(),
      topo.non_manifold_facets.begin() +
          std::min(topo.non_manifold_facets.size(), DualChecks::kMaxListed));
  c.euler_characteristic = topo.euler_characteristic;
  c.boundary_euler_characteristic = topo.boundary_euler_characteristic;
  c.dangling = topo.dangling;
  c.unused_vertices = topo.unused_vertices;
}

// The complex has the canvas's topology, as far as Euler characteristics tell: a ball where the
// domain is one, but a solid torus for a torus and two balls for two components (a ball's
// characteristics made valid duals of these "NOT a triangulation"). A 3-manifold's boundary has
// twice its characteristic (a pinched vertex or edge breaks that); a surface's boundary circles 0.
bool is_embedded_triangulation(const StraightDual& dual) {
  const DualChecks& c = dual.checks;
  const int boundary = dual.dimension == 3 ? 2 * c.euler_characteristic : 0;
  return dual.top_count() > 0 && c.inverted == 0 && c.intersecting == 0 && c.non_manifold == 0 &&
         c.euler_characteristic == c.domain_euler_characteristic &&
         c.boundary_euler_characteristic == boundary;
}

}  // namespace

// build_straight_dual itself; the public entry point names a failed allocation.
static StraightDual build_straight_dual_itself(const Canvas& canvas, const Nerve& nerve,
                                               const std::vector<Vec3>& given_seeds,
                                               const StraightDualOptions& options) {
  const auto start = std::chrono::steady_clock::now();
  const std::vector<Vec3> seeds =
      dual::checked_dual_seeds(canvas, nerve, given_seeds, "straight dual");
  StraightDual dual;
  dual.dimension = canvas.dimension;
  dual.vertices = seeds;
  dual.vertex_metrics = dual::seed_metrics(canvas, seeds);
  set_simplices(nerve,
                options.decide_near_degenerate ? dual::resolve_near_degenerate(canvas, nerve, seeds)
                                               : dual::witnessed_as_is(nerve),
                dual);
  dual.checks.degenerate_witnesses = nerve.degenerate_witness_count;

  const dual::Topology topo = dual::analyse_topology(dual);
  const std::vector<int> orientation = dual::orientation_signs(dual);
  mark_inverted(topo, orientation, dual);
  mark_intersecting(dual::intersecting_pairs(dual, orientation), dual);
  apply_topology(topo, dual);
  dual.checks.domain_euler_characteristic = dual::canvas_euler_characteristic(canvas);
  dual.checks.is_triangulation = is_embedded_triangulation(dual);
  dual::measure_quality(dual);
  dual.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return dual;
}

StraightDual build_straight_dual(const Canvas& canvas, const Nerve& nerve,
                                 const std::vector<Vec3>& given_seeds,
                                 const StraightDualOptions& options) {
  return naming_out_of_memory("building the straight dual", [&] {
    return build_straight_dual_itself(canvas, nerve, given_seeds, options);
  });
}

namespace dual {

Mat3 seed_metric(const Canvas& canvas, const std::vector<Vec3>& seeds, std::size_t seed) {
  const int64_t slot = canvas.slot_of(canvas.voxel_containing(seeds[seed]));
  if (slot < 0) throw Error("dual: seed " + std::to_string(seed) + " is not in an active voxel");
  return canvas.metric_at(static_cast<std::size_t>(slot));
}

std::vector<Mat3> seed_metrics(const Canvas& canvas, const std::vector<Vec3>& seeds) {
  std::vector<Mat3> metrics;
  for (std::size_t i = 0; i < seeds.size(); ++i) metrics.push_back(seed_metric(canvas, seeds, i));
  return metrics;
}

}  // namespace dual

}  // namespace rvor
