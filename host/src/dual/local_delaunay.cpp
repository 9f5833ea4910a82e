// Near-degenerate top simplices of the nerve, decided with the metric at their witness.
//
// The canvas orders two seeds only when their distances differ by more than about a voxel: where
// d+2 seeds are that close to cospherical (a Voronoi edge shorter than a voxel or two), the Kuhn
// simplices witness both triangulations of the configuration, or the wrong one. There the labels
// carry no more information, but the metric does: with G frozen at the witness, the empty-sphere
// test in G decides which simplices of the configuration are Delaunay. For a uniform metric this
// is the exact anisotropic Delaunay triangulation; for a varying one it is the locally uniform
// approximation, accurate to the metric's variation over a voxel or two, which is what the canvas
// resolves anyway. Simplices whose Voronoi vertex the canvas places without ambiguity are kept as
// witnessed.
#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <iterator>
#include <limits>
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

// Solves 2 (p_i - p_0)^T G c = |p_i|_G^2 - |p_0|_G^2 for i = 1..d (2D: c_z = p_0z); none when
// the points are (nearly) flat.
std::optional<Sphere> circumsphere(const std::vector<Vec3>& seeds, const Top& t, int d,
                                   const Mat3& G) {
  const Vec3& p0 = seeds[t[0]];
  Eigen::Matrix3d A = Eigen::Matrix3d::Identity();
  Vec3 b(0, 0, p0.z());
  for (int r = 0; r < d; ++r) {
    const Vec3& p = seeds[t[r + 1]];
    A.row(r) = 2.0 * (G * (p - p0)).transpose();
    b[r] = p.dot(G * p) - p0.dot(G * p0);
  }
  if (d == 2) A.row(2) = Vec3(0, 0, 1).transpose();
  // Closed-form 3x3 inverse (this runs for every top simplex); flat: det small against the rows.
  const double scale = A.row(0).norm() * A.row(1).norm() * A.row(2).norm();
  const double det = A.determinant();
  if (!(std::abs(det) > 1e-12 * scale)) return std::nullopt;
  Sphere s;
  s.centre = A.inverse() * b;
  s.radius = metric_length(G, s.centre - p0);
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

unsigned next_subset(unsigned mask) {
  const unsigned low = mask & (~mask + 1u), ripple = mask + low;
  return (((ripple ^ mask) >> 2) / low) | ripple;
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
  // the sphere, metric and voxel diameter its Delaunay simplices are decided with.
  std::vector<int32_t> configuration;
  Sphere sphere;
  Mat3 G = Mat3::Identity();
  double voxel = 0.0;
};

// The Delaunay simplices of one configuration, each with its near-degenerate mark.
using Found = std::vector<std::pair<Top, bool>>;

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
  LocalDelaunay run(const std::vector<NerveSimplex>& tops) {
    std::vector<Decision> decisions(tops.size());
    detail::parallel_for(tops.size(), 64, [&](std::size_t i) { decisions[i] = decide(tops[i]); });
    LocalDelaunay out;
    std::vector<Top> kept, near_degenerate;
    std::vector<const Decision*> jobs;
    std::set<std::vector<int32_t>> configurations;
    for (std::size_t i = 0; i < tops.size(); ++i) {
      const Decision& d = decisions[i];
      if (d.kept)
        kept.push_back(tops[i].seeds);
      else
        ++out.removed;
      if (d.near_degenerate) near_degenerate.push_back(tops[i].seeds);
      // Done from another of its simplices, or too large to enumerate.
      if (d.configuration.empty() || !configurations.insert(d.configuration).second ||
          static_cast<int>(d.configuration.size()) > kMaxConfiguration)
        continue;
      jobs.push_back(&d);
    }
    std::vector<Found> found(jobs.size());
    detail::parallel_for(jobs.size(), 16, [&](std::size_t j) { found[j] = configure(*jobs[j]); });
    std::vector<Top> added;
    for (const Found& f : found)
      for (const auto& [c, near] : f) {
        added.push_back(c);
        if (near) near_degenerate.push_back(c);
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
      d.configuration = configuration(t, *sphere, d.G, d.voxel, ring);
    }
    return d;
  }

  // The seeds of t and those of its ring within kSearchVoxels of its circumsphere, sorted (so
  // that the subsets below come out sorted).
  std::vector<int32_t> configuration(const Top& t, const Sphere& sphere, const Mat3& G,
                                     double voxel, const std::vector<int32_t>& ring) const {
    std::vector<int32_t> near(t.begin(), t.begin() + d_ + 1);
    for (int32_t e : ring)
      if (std::find(near.begin(), near.end(), e) == near.end() &&
          metric_length(G, seeds_[e] - sphere.centre) - sphere.radius < kSearchVoxels * voxel)
        near.push_back(e);
    std::sort(near.begin(), near.end());
    return near;
  }

  // The Delaunay simplices (in G) on the seeds nearly cospherical with the decided simplex,
  // whose Voronoi vertex lies in the domain near its own.
  Found configure(const Decision& d) const {
    const std::vector<int32_t>& near = d.configuration;
    const std::vector<int32_t> wide = ring_of(near.begin(), near.end());
    const int n = static_cast<int>(near.size());
    Found found;
    // The (d+1)-subsets of the configuration, as bit masks in increasing order (Gosper's hack).
    for (unsigned mask = (1u << (d_ + 1)) - 1; mask < (1u << n); mask = next_subset(mask)) {
      Top c{-1, -1, -1, -1};
      int m = 0;
      for (int i = 0; i < n; ++i)
        if (mask & (1u << i)) c[m++] = near[i];
      const std::optional<Sphere> s = circumsphere(seeds_, c, d_, d.G);
      if (!s || metric_length(d.G, s->centre - d.sphere.centre) > 0.5 * d.sphere.radius) continue;
      // Most subsets have a seed of the configuration inside: test those first.
      if (empty_margin(seeds_, c, d_, *s, d.G, near) < 0.0 || !in_domain(s->centre)) continue;
      const double margin = empty_margin(seeds_, c, d_, *s, d.G, wide);
      if (margin < 0.0) continue;
      found.emplace_back(c, margin < kFlagVoxels * d.voxel);
    }
    return found;
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
  static constexpr int kMaxConfiguration = 12;

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

LocalDelaunay witnessed_as_is(const Nerve& nerve) {
  LocalDelaunay out;
  for (const NerveSimplex& s : nerve.top_simplices()) out.top.push_back(s.seeds);
  out.near_degenerate.assign(out.top.size(), 0);
  return out;
}

}  // namespace rvor::dual
