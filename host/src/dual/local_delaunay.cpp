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
#include <limits>
#include <optional>
#include <set>

#include "dual/dual_internal.h"
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

class Resolver {
 public:
  Resolver(const Canvas& canvas, const Nerve& nerve, const std::vector<Vec3>& seeds)
      : canvas_(canvas), seeds_(seeds), d_(canvas.dimension), neighbours_(seeds.size()) {
    for (const NerveSimplex& e : nerve.edges) {
      neighbours_[e.seeds[0]].push_back(e.seeds[1]);
      neighbours_[e.seeds[1]].push_back(e.seeds[0]);
    }
  }

  LocalDelaunay run(const std::vector<NerveSimplex>& tops) {
    LocalDelaunay out;
    std::set<Top> kept, added;
    for (const NerveSimplex& s : tops) decide(s, kept, added, out);
    std::set<Top> all = kept;
    all.insert(added.begin(), added.end());
    out.added = 0;
    for (const Top& t : added) out.added += kept.count(t) == 0;
    for (const Top& t : all) {
      out.top.push_back(t);
      out.near_degenerate.push_back(near_degenerate_.count(t) > 0);
    }
    return out;
  }

 private:
  // Keeps s unless some seed near it lies inside its circumsphere in the witness's metric; near-
  // degenerate configurations also contribute their other Delaunay simplices.
  void decide(const NerveSimplex& s, std::set<Top>& kept, std::set<Top>& added,
              LocalDelaunay& out) {
    const Top t = s.seeds;
    if (s.farthest.slot < 0) {  // no witness voxel, no metric to decide with: taken as given
      kept.insert(t);
      return;
    }
    const Mat3 G = canvas_.metric_at(static_cast<std::size_t>(s.farthest.slot));
    const double voxel = voxel_diameter(G);
    const std::vector<int32_t> ring = ring_of(t.begin(), t.begin() + d_ + 1);
    const std::optional<Sphere> sphere = circumsphere(seeds_, t, d_, G);
    const double margin = sphere ? empty_margin(seeds_, t, d_, *sphere, G, ring)
                                 : -std::numeric_limits<double>::infinity();
    if (margin < kFlagVoxels * voxel) near_degenerate_.insert(t);
    if (margin >= 0.0)
      kept.insert(t);
    else
      ++out.removed;
    if (sphere && margin < kSearchVoxels * voxel)
      add_configuration(t, *sphere, G, voxel, ring, added);
  }

  // The Delaunay simplices (in G) on the seeds nearly cospherical with t, whose Voronoi vertex
  // lies in the domain near t's.
  void add_configuration(const Top& t, const Sphere& sphere, const Mat3& G, double voxel,
                         const std::vector<int32_t>& ring, std::set<Top>& added) {
    std::vector<int32_t> near(t.begin(), t.begin() + d_ + 1);
    for (int32_t e : ring)
      if (std::find(near.begin(), near.end(), e) == near.end() &&
          metric_length(G, seeds_[e] - sphere.centre) - sphere.radius < kSearchVoxels * voxel)
        near.push_back(e);
    std::sort(near.begin(), near.end());               // so that the subsets below come out sorted
    if (!configurations_.insert(near).second) return;  // done from another of its simplices
    const std::vector<int32_t> wide = ring_of(near.begin(), near.end());
    const int n = static_cast<int>(near.size());
    if (n > kMaxConfiguration) return;
    // The (d+1)-subsets of the configuration, as bit masks in increasing order (Gosper's hack).
    for (unsigned mask = (1u << (d_ + 1)) - 1; mask < (1u << n); mask = next_subset(mask)) {
      Top c{-1, -1, -1, -1};
      int m = 0;
      for (int i = 0; i < n; ++i)
        if (mask & (1u << i)) c[m++] = near[i];
      const std::optional<Sphere> s = circumsphere(seeds_, c, d_, G);
      if (!s || metric_length(G, s->centre - sphere.centre) > 0.5 * sphere.radius) continue;
      // Most subsets have a seed of the configuration inside: test those first.
      if (empty_margin(seeds_, c, d_, *s, G, near) < 0.0 || !in_domain(s->centre)) continue;
      const double margin = empty_margin(seeds_, c, d_, *s, G, wide);
      if (margin < 0.0) continue;
      added.insert(c);
      if (margin < kFlagVoxels * voxel) near_degenerate_.insert(c);
    }
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
  std::set<Top> near_degenerate_;
  std::set<std::vector<int32_t>> configurations_;
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
