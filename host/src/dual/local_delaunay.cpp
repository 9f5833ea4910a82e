// Near-degenerate top simplices of the nerve, decided with the metric at their witness.
//
// The canvas orders two seeds only when their distances differ by more than about a voxel: where
// d+2 seeds are that close to cospherical (a Voronoi edge shorter than a voxel or two), the Kuhn
// simplices witness both triangulations of the configuration, or the wrong one. There the labels
// carry no more information, but the metric does: with G frozen at the witness, the empty-sphere
// test in G decides which simplices of the configuration are Delaunay. For a uniform metric this
// is the exact anisotropic Delaunay triangulation; for a varying one it is the locally uniform
// approximation, decided only where G is within the canvas's resolution of every seed's metric
// over the configuration's sphere (elsewhere the frozen metric errs by more than the canvas does,
// and the simplex is kept as witnessed). Simplices whose Voronoi vertex the canvas places without
// ambiguity are kept as witnessed.
#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <iterator>
#include <limits>
#include <map>
#include <optional>
#include <set>

#include "dual/dual_internal.h"
#include "dual/parallel_for.h"
#include "rvor/metric.h"

namespace rvor::dual {

namespace {

using Top = std::array<int32_t, 4>;

// A circumsphere in the metric G: centre (world) and radius (G-length).
struct Sphere {
  Vec3 centre = Vec3::Zero();
  double radius = 0.0;
};

// Solves 2 (p_i - p_0)^T G c = |p_i - p_0|_G^2 for i = 1..d (2D: c_z = 0), the centre being
// p_0 + c; none when the points are (nearly) flat. Relative to p_0: |p_i|_G^2 - |p_0|_G^2 lost
// the centre to cancellation far from the origin (seeds near 10^6: squares of 10^13 for
// differences of 10^-2, the centre off by about a voxel, and the decisions then added
// overlapping triangles).
std::optional<Sphere> circumsphere(const std::vector<Vec3>& seeds, const Top& t, int d,
                                   const Mat3& G) {
  const Vec3& p0 = seeds[t[0]];
  Eigen::Matrix3d A = Eigen::Matrix3d::Identity();
  Vec3 b = Vec3::Zero();
  for (int r = 0; r < d; ++r) {
    const Vec3 p = seeds[t[r + 1]] - p0;
    A.row(r) = 2.0 * (G * p).transpose();
    b[r] = p.dot(G * p);
  }
  if (d == 2) A.row(2) = Vec3(0, 0, 1).transpose();
  // Closed-form 3x3 inverse (this runs for every top simplex); flat: det small against the rows.
  const double scale = A.row(0).norm() * A.row(1).norm() * A.row(2).norm();
  const double det = A.determinant();
  if (!(std::abs(det) > 1e-12 * scale)) return std::nullopt;
  Sphere s;
  const Vec3 c = A.inverse() * b;
  s.centre = p0 + c;
  s.radius = metric_length(G, c);
  return s;
}

// How much farther (G-length) the nearest of `others` is from the centre than the radius.
double empty_margin(const std::vector<Vec3>& seeds, const Top& t, int d, const Sphere& s,
                    const Mat3& G, const std::vector<int32_t>& others) {
  double margin = std::numeric_limits<double>::infinity();
  for (int32_t e : others) {
    if (std::find(t.begin(), t.begin() + d + 1, e) != t.begin() + d + 1) continue;
    margin = std::min(margin, metric_length(G, seeds[e] - s.centre) - s.radius);
  }
  return margin;
}

template <typename T>
void sort_unique(std::vector<T>& v) {
  std::sort(v.begin(), v.end());
  v.erase(std::unique(v.begin(), v.end()), v.end());
}

// What the empty-sphere test says about one witnessed top simplex.
struct Decision {
  bool kept = true;
  bool near_degenerate = false;
  // Set when seeds lie within kSearchVoxels of its circumsphere: the sorted configuration, and
  // the sphere, metric and voxel diameter its Delaunay simplices are decided with, and whether its
  // circumsphere is empty of the ring's seeds outside the configuration.
  std::vector<int32_t> configuration;
  bool empty_outside = true;
  Sphere sphere;
  Mat3 G = Mat3::Identity();
  double voxel = 0.0;
};

// One configuration decided: its Delaunay triangulation (sorted), and the simplices of it to add,
// each with its near-degenerate mark.
struct Found {
  std::vector<Top> triangulation;
  std::vector<std::pair<Top, bool>> added;
};

class Resolver {
 public:
  Resolver(const Canvas& canvas, const Nerve& nerve, const std::vector<Vec3>& seeds)
      : canvas_(canvas), seeds_(seeds), d_(canvas.dimension), neighbours_(seeds.size()) {
    for (const NerveSimplex& e : nerve.edges) {
      neighbours_[e.seeds[0]].push_back(e.seeds[1]);
      neighbours_[e.seeds[1]].push_back(e.seeds[0]);
    }
  }

  // Decisions and configurations are independent per simplex: both run on all cores, and are
  // combined in the nerve's order (a configuration is decided from the first of its simplices),
  // so the result does not depend on the thread schedule.
  // A witnessed simplex in a configuration is kept when the configuration's triangulation has it
  // (cospherical seeds: one triangulation of them, not every simplex that passes the test in
  // floating point); elsewhere when its circumsphere is empty.
  LocalDelaunay run(const std::vector<NerveSimplex>& tops) {
    std::vector<Decision> decisions(tops.size());
    detail::parallel_for(tops.size(), 64, [&](std::size_t i) { decisions[i] = decide(tops[i]); });
    std::map<std::vector<int32_t>, std::size_t> job_of;
    std::vector<const Decision*> jobs;
    for (const Decision& d : decisions)
      if (!d.configuration.empty() &&
          static_cast<int>(d.configuration.size()) <= kMaxConfiguration &&
          job_of.emplace(d.configuration, jobs.size()).second)
        jobs.push_back(&d);
    std::vector<Found> found(jobs.size());
    detail::parallel_for(jobs.size(), 16, [&](std::size_t j) { found[j] = configure(*jobs[j]); });
    std::vector<Top> added, near_degenerate;
    for (const Found& f : found)
      for (const auto& [c, near] : f.added) {
        added.push_back(c);
        if (near) near_degenerate.push_back(c);
      }
    LocalDelaunay out;
    std::vector<Top> kept;
    for (std::size_t i = 0; i < tops.size(); ++i) {
      const Decision& d = decisions[i];
      const auto job = job_of.find(d.configuration);
      const std::vector<Top>* triangulation =
          job == job_of.end() ? nullptr : &found[job->second].triangulation;
      const bool keep =
          triangulation ? d.empty_outside && std::binary_search(triangulation->begin(),
                                                                triangulation->end(), tops[i].seeds)
                        : d.kept;
      if (keep)
        kept.push_back(tops[i].seeds);
      else
        ++out.removed;
      if (d.near_degenerate) near_degenerate.push_back(tops[i].seeds);
    }
    assemble(std::move(kept), std::move(added), std::move(near_degenerate), out);
    return out;
  }

 private:
  static void assemble(std::vector<Top> kept, std::vector<Top> added,
                       std::vector<Top> near_degenerate, LocalDelaunay& out) {
    sort_unique(kept);
    sort_unique(added);
    sort_unique(near_degenerate);
    out.added = 0;
    for (const Top& t : added) out.added += !std::binary_search(kept.begin(), kept.end(), t);
    std::set_union(kept.begin(), kept.end(), added.begin(), added.end(),
                   std::back_inserter(out.top));
    for (const Top& t : out.top)
      out.near_degenerate.push_back(
          std::binary_search(near_degenerate.begin(), near_degenerate.end(), t));
  }

  // Keeps s unless some seed near it lies inside its circumsphere in the witness's metric; near-
  // degenerate configurations also contribute their other Delaunay simplices.
  Decision decide(const NerveSimplex& s) const {
    Decision d;
    const Top t = s.seeds;
    if (s.farthest.slot < 0) return d;  // no witness voxel, no metric to decide with: as given
    d.G = canvas_.metric_at(static_cast<std::size_t>(s.farthest.slot));
    d.voxel = voxel_diameter(d.G);
    const std::vector<int32_t> ring = ring_of(t.begin(), t.begin() + d_ + 1);
    const std::optional<Sphere> sphere = circumsphere(seeds_, t, d_, d.G);
    const double margin = sphere ? empty_margin(seeds_, t, d_, *sphere, d.G, ring)
                                 : -std::numeric_limits<double>::infinity();
    d.near_degenerate = margin < kFlagVoxels * d.voxel;
    d.kept = margin >= 0.0;
    if (sphere && margin < kSearchVoxels * d.voxel) {
      d.sphere = *sphere;
      d.configuration = configuration(t, *sphere, d.G, d.voxel);
      if (!frozen_metric_resolves(d)) {  // the canvas's labels are the better guess: as witnessed
        d.configuration.clear();
        d.kept = true;
        return d;
      }
      d.empty_outside =
          empty_margin(seeds_, t, d_, *sphere, d.G, without(ring, d.configuration)) >= 0.0;
    }
    return d;
  }

  // The seeds within kSearchVoxels of t's circumsphere that the nerve joins to t through such
  // seeds, t's own included, sorted (so that the subsets below come out sorted). Grown through the
  // neighbours of every seed added, not t's ring alone: the simplices witnessed on exactly
  // cospherical seeds share their sphere, so they all get the same configuration, triangulated
  // once; each with the subset its own ring reached, their triangulations overlapped (a regular
  // hexagon on a fine canvas). Growth stops past kMaxConfiguration seeds (not decided).
  std::vector<int32_t> configuration(const Top& t, const Sphere& sphere, const Mat3& G,
                                     double voxel) const {
    std::vector<int32_t> near(t.begin(), t.begin() + d_ + 1);
    for (std::size_t i = 0; i < near.size() && near.size() <= std::size_t{kMaxConfiguration}; ++i)
      for (int32_t e : neighbours_[near[i]])
        if (std::find(near.begin(), near.end(), e) == near.end() &&
            metric_length(G, seeds_[e] - sphere.centre) - sphere.radius < kSearchVoxels * voxel)
          near.push_back(e);
    std::sort(near.begin(), near.end());
    return near;
  }

  // Whether G, frozen at the witness, measures the configuration's sphere as the seeds' own
  // metrics do, to within the search band: a length r in G is between r / psi and r psi in a
  // metric at distortion psi from G, so the sphere's radius is off by up to (psi - 1) r. Under a
  // strongly varying metric with coarse seeds (hyperbolic_shock, 150 seeds at 512^2: radii ~15
  // voxel diameters, seeds' metrics typically 4x the witness's in length, by a temporary count
  // not kept) that is tens of voxels,
  // and the frozen test both removed witnessed simplices and added overlapping ones; uniform
  // metrics (psi = 1) are always decided.
  bool frozen_metric_resolves(const Decision& d) const {
    double psi = 1.0;
    for (int32_t e : d.configuration)
      psi =
          std::max(psi, distortion(seed_metric(canvas_, seeds_, static_cast<std::size_t>(e)), d.G));
    return (psi - 1.0) * d.sphere.radius <= kSearchVoxels * d.voxel;
  }

  // The Delaunay simplices (in G) on the seeds nearly cospherical with the decided simplex, whose
  // Voronoi vertex lies in the domain near its own: the configuration's Delaunay triangulation
  // in the coordinates F x (F = G^(1/2)), which CGAL computes with exact predicates, so that
  // cospherical seeds get one triangulation; its simplices must be empty of the seeds around.
  Found configure(const Decision& d) const {
    const std::vector<int32_t>& near = d.configuration;
    const std::vector<int32_t> around = without(ring_of(near.begin(), near.end()), near);
    const Mat3 F = metric_sqrt(d.G);
    std::vector<Vec3> mapped;  // from the first seed, which keeps them exact far from the origin
    for (int32_t e : near) mapped.push_back(F * (seeds_[e] - seeds_[near.front()]));
    Found found;
    for (const Top& local : delaunay_of(mapped, d_)) {
      Top c{-1, -1, -1, -1};
      for (int m = 0; m <= d_; ++m) c[m] = near[local[m]];  // sorted, as `near` is
      found.triangulation.push_back(c);
      // CGAL's flat simplices (an icosahedron's four coplanar cospherical seeds, rounded off their
      // plane) have no circumsphere in floating point: they are inscribed in the configuration's
      // (dropped, they left a hole in its triangulation).
      const Sphere s = circumsphere(seeds_, c, d_, d.G).value_or(d.sphere);
      if (metric_length(d.G, s.centre - d.sphere.centre) > 0.5 * d.sphere.radius) continue;
      if (!in_domain(s.centre)) continue;
      const double outside = empty_margin(seeds_, c, d_, s, d.G, around);
      if (outside < 0.0) continue;
      const double margin = std::min(outside, empty_margin(seeds_, c, d_, s, d.G, near));
      found.added.emplace_back(c, margin < kFlagVoxels * d.voxel);
    }
    sort_unique(found.triangulation);
    return found;
  }

  // The seeds of `all` (sorted) that are not in `some` (sorted).
  static std::vector<int32_t> without(const std::vector<int32_t>& all,
                                      const std::vector<int32_t>& some) {
    std::vector<int32_t> rest;
    std::set_difference(all.begin(), all.end(), some.begin(), some.end(), std::back_inserter(rest));
    return rest;
  }

  // The seeds given and their nerve neighbours, sorted, distinct.
  template <typename It>
  std::vector<int32_t> ring_of(It first, It last) const {
    std::vector<int32_t> ring(first, last);
    for (It v = first; v != last; ++v)
      ring.insert(ring.end(), neighbours_[*v].begin(), neighbours_[*v].end());
    std::sort(ring.begin(), ring.end());
    ring.erase(std::unique(ring.begin(), ring.end()), ring.end());
    return ring;
  }

  // The G-length of a voxel diagonal along the metric's longest axis: the canvas cannot order
  // distances that differ by less than about this.
  double voxel_diameter(const Mat3& G) const {
    // Closed form (computeDirect): this runs for every top simplex.
    double largest = 0.0;
    if (d_ == 3) {
      Eigen::SelfAdjointEigenSolver<Mat3> eigen;
      largest = eigen.computeDirect(G, Eigen::EigenvaluesOnly).eigenvalues().maxCoeff();
    } else {
      Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> eigen;
      const Eigen::Matrix2d G2 = G.topLeftCorner<2, 2>();
      largest = eigen.computeDirect(G2, Eigen::EigenvaluesOnly).eigenvalues().maxCoeff();
    }
    return canvas_.voxel_size * std::sqrt(d_ * largest);
  }

  bool in_domain(const Vec3& x) const { return canvas_.slot_of(canvas_.voxel_containing(x)) >= 0; }

  // Seeds within kSearchVoxels voxel diameters of a circumsphere make a configuration the
  // canvas may have got wrong (measured: its errors stay below half a voxel diameter); within
  // kFlagVoxels, the canvas cannot order them and the simplex is flagged near-degenerate.
  static constexpr double kSearchVoxels = 1.0;
  static constexpr double kFlagVoxels = 0.5;
  // Larger configurations are left as witnessed (12 bounded the enumeration of subsets that
  // CGAL's triangulation replaced; a 16- or 20-gon of cocircular seeds needs more).
  static constexpr int kMaxConfiguration = 32;

  const Canvas& canvas_;
  const std::vector<Vec3>& seeds_;
  int d_;
  std::vector<std::vector<int32_t>> neighbours_;
};

}  // namespace

LocalDelaunay resolve_near_degenerate(const Canvas& canvas, const Nerve& nerve,
                                      const std::vector<Vec3>& seeds) {
  return Resolver(canvas, nerve, seeds).run(nerve.top_simplices());
}

namespace {

// Calls visit(face) for every face of `top` (its d+1 seeds, sorted) with 2 or more seeds, itself
// included, as sorted seed lists.
template <typename Visit>
void for_each_face(const Top& top, int dimension, Visit&& visit) {
  const int n = dimension + 1;
  for (unsigned mask = 1; mask < (1u << n); ++mask) {
    std::vector<int32_t> face;
    for (int i = 0; i < n; ++i)
      if (mask & (1u << i)) face.push_back(top[i]);
    if (face.size() >= 2) visit(face);
  }
}

// Whether a facet of `simplex` (its seeds but one) is in `faces`.
bool has_facet_in(const std::vector<int32_t>& simplex,
                  const std::set<std::vector<int32_t>>& faces) {
  if (simplex.size() < 3) return false;  // an edge's facets are seeds, never dropped
  for (std::size_t skip = 0; skip < simplex.size(); ++skip) {
    std::vector<int32_t> facet;
    for (std::size_t v = 0; v < simplex.size(); ++v)
      if (v != skip) facet.push_back(simplex[v]);
    if (faces.count(facet)) return true;
  }
  return false;
}

std::vector<int32_t> seeds_of(const NerveSimplex& s) {
  return std::vector<int32_t>(s.seeds.begin(), s.seeds.begin() + s.vertex_count);
}

NerveSimplex unwitnessed(const std::vector<int32_t>& face, const Canvas& canvas,
                         const std::vector<Vec3>& seeds) {
  NerveSimplex s;
  s.vertex_count = static_cast<int>(face.size());
  Vec3 centroid = Vec3::Zero();
  for (std::size_t i = 0; i < face.size(); ++i) {
    s.seeds[i] = face[i];
    centroid += seeds[static_cast<std::size_t>(face[i])] / static_cast<double>(face.size());
  }
  s.nearest.position = s.farthest.position = centroid;
  s.nearest.slot = s.farthest.slot = canvas.slot_of(canvas.voxel_containing(centroid));
  // The distance a witness there would carry (local fields size their solves by it).
  const Mat3 G = s.nearest.slot >= 0
                     ? canvas.metric_at(static_cast<std::size_t>(s.nearest.slot))
                     : seed_metric(canvas, seeds, static_cast<std::size_t>(face[0]));
  double distance = 0.0;
  for (int32_t seed : face)
    distance =
        std::max(distance, metric_length(G, centroid - seeds[static_cast<std::size_t>(seed)]));
  s.nearest.distance = s.farthest.distance = static_cast<float>(distance);
  return s;
}

}  // namespace

LocalDelaunay witnessed_as_is(const Nerve& nerve) {
  LocalDelaunay out;
  for (const NerveSimplex& s : nerve.top_simplices()) out.top.push_back(s.seeds);
  out.near_degenerate.assign(out.top.size(), 0);
  return out;
}

}  // namespace rvor::dual

namespace rvor {

Nerve decided_nerve(const Canvas& canvas, const Nerve& nerve,
                    const std::vector<Vec3>& given_seeds) {
  const std::vector<Vec3> seeds =
      dual::checked_dual_seeds(canvas, nerve, given_seeds, "decided nerve");
  const dual::LocalDelaunay decided = dual::resolve_near_degenerate(canvas, nerve, seeds);
  const int d = canvas.dimension;
  std::set<std::vector<int32_t>> kept_faces, removed_faces;
  for (const dual::Top& top : decided.top)
    dual::for_each_face(top, d, [&](const std::vector<int32_t>& f) { kept_faces.insert(f); });
  for (const NerveSimplex& s : nerve.top_simplices())
    if (!std::binary_search(decided.top.begin(), decided.top.end(), s.seeds))
      dual::for_each_face(s.seeds, d,
                          [&](const std::vector<int32_t>& f) { removed_faces.insert(f); });
  Nerve out = nerve;
  std::set<std::vector<int32_t>> witnessed, dropped;
  // Edges first, so that a simplex the decision leaves alone (a face of no witnessed top: a
  // triangle whose tetrahedra the canvas never witnessed) goes with a dropped facet, and the
  // nerve stays closed under faces (the curved dual builds a face from its opposite edge).
  for (std::vector<NerveSimplex>* list : {&out.edges, &out.triangles, &out.tetrahedra}) {
    list->erase(std::remove_if(list->begin(), list->end(),
                               [&](const NerveSimplex& s) {
                                 const std::vector<int32_t> f = dual::seeds_of(s);
                                 witnessed.insert(f);
                                 const bool drop =
                                     (removed_faces.count(f) > 0 && kept_faces.count(f) == 0) ||
                                     dual::has_facet_in(f, dropped);
                                 if (drop) dropped.insert(f);
                                 return drop;
                               }),
                list->end());
  }
  for (const std::vector<int32_t>& f : kept_faces) {
    if (witnessed.count(f)) continue;
    std::vector<NerveSimplex>& list = f.size() == 2   ? out.edges
                                      : f.size() == 3 ? out.triangles
                                                      : out.tetrahedra;
    list.push_back(dual::unwitnessed(f, canvas, seeds));
  }
  for (std::vector<NerveSimplex>* list : {&out.edges, &out.triangles, &out.tetrahedra})
    std::sort(list->begin(), list->end(),
              [](const NerveSimplex& a, const NerveSimplex& b) { return a.seeds < b.seeds; });
  return out;
}

}  // namespace rvor
