// Geodesic tracing by descent of a distance field (geodesic_tracer.h), moved out of
// curved_dual.cpp so that curved faces (curved_faces.cpp) trace with the same code.
#include "geodesic_tracer.h"

#include <Eigen/Dense>
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

#include "rvor/seed_blocks.h"
#include "rvor/selling.h"

namespace rvor::detail {

namespace {

constexpr double kStep = 0.5;            // voxels per tracing step
constexpr double kArrival = 1.0;         // voxels: a trace this close to its seed has reached it
constexpr double kMinWeight = 1e-9;      // below: corner weights are renormalised uniformly
constexpr int kMaxMisses = 16;           // steps through cells without a voxel of the label
constexpr int kRefineIterations = 64;    // moves of at most a voxel each
constexpr std::size_t kPullWindow = 32;  // how many points later a shortcut may end, at most
// Voxels, along the longest axis, between the checks that a segment passes through voxels of its
// label (segment_carries): a staircase's steps join voxel centres, a shortcut any two of them.
constexpr double kStaircaseSpacing = 0.5;
constexpr double kPullSpacing = 1.0 / 16;

// The points dividing the segment p-q into equal pieces of at most kStep, q excluded: the pieces
// of a segment already divided so measure as one piece each (the tolerance absorbs the rounding
// of p + (q - p) n / pieces), so a length summed over a divided polyline is the segment's.
std::vector<Vec3> division_points(const Vec3& p, const Vec3& q) {
  const int pieces = std::max(1, static_cast<int>(std::ceil((q - p).norm() / kStep - 1e-9)));
  std::vector<Vec3> points;
  for (int n = 0; n < pieces; ++n)
    points.push_back(p + (q - p) * (static_cast<double>(n) / pieces));
  return points;
}

}  // namespace

VoxelIndex GeodesicTracer::nearest_voxel(const Vec3& x) const {
  return {static_cast<int>(std::lround(x.x())), static_cast<int>(std::lround(x.y())),
          dimension_ == 3 ? static_cast<int>(std::lround(x.z())) : 0};
}

// Calls f(slot, weight) for each active corner of the grid cell containing x, with its
// bi/trilinear weight.
template <typename F>
void GeodesicTracer::for_each_corner(const Vec3& x, F&& f) const {
  const int bi = static_cast<int>(std::floor(x.x())), bj = static_cast<int>(std::floor(x.y()));
  const int bk = dimension_ == 3 ? static_cast<int>(std::floor(x.z())) : 0;
  const double fx = x.x() - bi, fy = x.y() - bj, fz = dimension_ == 3 ? x.z() - bk : 0.0;
  const int corners = dimension_ == 3 ? 8 : 4;
  for (int c = 0; c < corners; ++c) {
    const int di = c & 1, dj = (c >> 1) & 1, dk = (c >> 2) & 1;
    const int64_t slot = canvas_.slot_of(bi + di, bj + dj, bk + dk);
    if (slot < 0) continue;
    const double w = (di ? fx : 1.0 - fx) * (dj ? fy : 1.0 - fy) *
                     (dimension_ == 3 ? (dk ? fz : 1.0 - fz) : 1.0);
    f(slot, w);
  }
}

double GeodesicTracer::distance_of(int64_t slot, int32_t label) const {
  constexpr double kUnknown = std::numeric_limits<double>::quiet_NaN();
  if (slot < 0) return kUnknown;
  const auto s = static_cast<std::size_t>(slot);
  if (locals_) {
    const float u = locals_->fields[static_cast<std::size_t>(label)].at(canvas_.voxel_of(s));
    return std::isfinite(u) ? u : kUnknown;
  }
  return field_.label[s] == label && std::isfinite(field_.distance[s]) ? field_.distance[s]
                                                                       : kUnknown;
}

bool GeodesicTracer::carries(int64_t slot, int32_t label) const {
  return !std::isnan(distance_of(slot, label));
}

// Squared distance of `label` at a slot, or NaN where unknown.
double GeodesicTracer::squared_distance(int64_t slot, int32_t label) const {
  const double u = distance_of(slot, label);
  return u * u;
}

bool GeodesicTracer::bisector_minimum(int32_t a, int32_t b, Vec3& x) const {
  if (!locals_) return false;
  const LocalField& fa = locals_->fields[static_cast<std::size_t>(a)];
  const LocalField& fb = locals_->fields[static_cast<std::size_t>(b)];
  std::array<int, 3> lo{}, hi{};
  for (int c = 0; c < 3; ++c) {
    lo[c] = std::max(fa.lo[c], fb.lo[c]);
    hi[c] = std::min(fa.lo[c] + fa.dims[c], fb.lo[c] + fb.dims[c]);  // exclusive
  }
  // max(u_a, u_b) is smallest on the bisector, at its point of smallest distance.
  float best = std::numeric_limits<float>::infinity();
  for (int k = lo[2]; k < hi[2]; ++k)
    for (int j = lo[1]; j < hi[1]; ++j)
      for (int i = lo[0]; i < hi[0]; ++i) {
        const float value = std::max(fa.at(i, j, k), fb.at(i, j, k));
        if (value < best) {
          best = value;
          x = Vec3(i, j, k);
        }
      }
  return std::isfinite(best);
}

// Finite-difference gradient of the squared distance u^2 at a voxel of `label`, from its
// neighbours of the same label (index units): central where both neighbours carry the label,
// else one-sided of second order where two voxels on one side do, else of first order. u^2
// descends along the same direction as u, but is smooth at the seed and quadratic in a uniform
// metric, where these differences are exact.
// `complete` is false when some axis has no neighbour of the label (the component is then 0).
Vec3 GeodesicTracer::voxel_gradient(int64_t slot, int32_t label, bool& complete) const {
  const VoxelIndex v = canvas_.voxel_of(static_cast<std::size_t>(slot));
  const double q0 = squared_distance(slot, label);
  const double h2 = canvas_.voxel_size * canvas_.voxel_size;
  const Mat3 G = canvas_.metric_at(static_cast<std::size_t>(slot));
  Vec3 g = Vec3::Zero();
  complete = true;
  for (int a = 0; a < dimension_; ++a) {
    auto at = [&](int offset) {
      VoxelIndex w = v;
      (a == 0 ? w.i : a == 1 ? w.j : w.k) += offset;
      return squared_distance(canvas_.slot_of(w), label);
    };
    // First-order differences are corrected by the curvature of u^2 in the metric, h^2 G_aa
    // (exact in a uniform metric): uncorrected, their error is amplified by G's anisotropy.
    const double qm = at(-1), qp = at(1);
    if (!std::isnan(qm) && !std::isnan(qp)) {
      g[a] = 0.5 * (qp - qm);
    } else if (!std::isnan(qp)) {
      const double qpp = at(2);
      g[a] = std::isnan(qpp) ? qp - q0 - h2 * G(a, a) : 0.5 * (-3.0 * q0 + 4.0 * qp - qpp);
    } else if (!std::isnan(qm)) {
      const double qmm = at(-2);
      g[a] = std::isnan(qmm) ? q0 - qm + h2 * G(a, a) : 0.5 * (3.0 * q0 - 4.0 * qm + qmm);
    } else {
      complete = false;
    }
  }
  return g;
}

bool GeodesicTracer::cell_carries(const Vec3& x, int32_t label) const {
  bool found = false;
  for_each_corner(x, [&](int64_t slot, double) { found = found || carries(slot, label); });
  return found;
}

// The seed of `label` as extrapolated from the corners of x's cell that carry the label
// (index coordinates): per corner v, v - G_v^{-1} grad(u^2)_v / (2 h^2), weighted as in sample.
bool GeodesicTracer::seed_estimate(const Vec3& x, int32_t label, Vec3& seed) const {
  const double scale = 0.5 / (canvas_.voxel_size * canvas_.voxel_size);
  Vec3 weighted = Vec3::Zero(), uniform = Vec3::Zero();
  double total = 0.0;
  int count = 0;
  for_each_corner(x, [&](int64_t slot, double w) {
    if (!carries(slot, label)) return;
    bool complete = false;
    const Vec3 g = voxel_gradient(slot, label, complete);
    if (!complete) return;
    const VoxelIndex v = canvas_.voxel_of(static_cast<std::size_t>(slot));
    const Mat3 G = canvas_.metric_at(static_cast<std::size_t>(slot));
    const Vec3 estimate = Vec3(v.i, v.j, v.k) - scale * G.ldlt().solve(g);
    weighted += w * estimate;
    uniform += estimate;
    total += w;
    ++count;
  });
  if (count == 0) return false;
  seed = total > kMinWeight ? Vec3(weighted / total) : Vec3(uniform / count);
  return true;
}

// As sample, over the voxels of `label` within the (2 reach)^d block around x's cell (inverse
// squared distance weights): for points whose cell has no voxel of the label, e.g. a bisector
// point where the label's discrete cell is a thin sliver.
bool GeodesicTracer::sample_wide(const Vec3& x, int32_t label, Vec3& gradient, Mat3& G,
                                 int reach) const {
  const int bi = static_cast<int>(std::floor(x.x())), bj = static_cast<int>(std::floor(x.y()));
  const int bk = dimension_ == 3 ? static_cast<int>(std::floor(x.z())) : 0;
  const int k_lo = dimension_ == 3 ? 1 - reach : 0, k_hi = dimension_ == 3 ? reach : 0;
  gradient.setZero();
  G.setZero();
  double total = 0.0;
  for (int dk = k_lo; dk <= k_hi; ++dk)
    for (int dj = 1 - reach; dj <= reach; ++dj)
      for (int di = 1 - reach; di <= reach; ++di) {
        const int64_t slot = canvas_.slot_of(bi + di, bj + dj, bk + dk);
        if (!carries(slot, label)) continue;
        bool complete = false;
        const Vec3 g = voxel_gradient(slot, label, complete);
        if (!complete) continue;
        const Vec3 v(bi + di, bj + dj, bk + dk);
        const double w = 1.0 / (1e-6 + (v - x).squaredNorm());
        gradient += w * g;
        G += w * canvas_.metric_at(static_cast<std::size_t>(slot));
        total += w;
      }
  if (total <= 0.0) return false;
  gradient /= total;
  G /= total;
  return true;
}

// Gradient of the distance of `label` and the metric at x (index coordinates), interpolated
// over the corners of x's cell that carry the label. False when none does.
bool GeodesicTracer::sample(const Vec3& x, int32_t label, Vec3& gradient, Mat3& G) const {
  gradient.setZero();
  G.setZero();
  double total = 0.0;
  int count = 0;
  Vec3 uniform_gradient = Vec3::Zero();
  Mat3 uniform_G = Mat3::Zero();
  for_each_corner(x, [&](int64_t slot, double w) {
    if (!carries(slot, label)) return;
    bool complete = false;
    const Vec3 g = voxel_gradient(slot, label, complete);
    if (!complete) return;  // a voxel without neighbours of the label along some axis
    const Mat3 M = canvas_.metric_at(static_cast<std::size_t>(slot));
    gradient += w * g;
    G += w * M;
    total += w;
    uniform_gradient += g;
    uniform_G += M;
    ++count;
  });
  if (count == 0) return false;
  if (total > kMinWeight) {
    gradient /= total;
    G /= total;
  } else {
    gradient = uniform_gradient / count;
    G = uniform_G / count;
  }
  return true;
}

Vec3 GeodesicTracer::inside_canvas(const Vec3& x) const {
  Vec3 y = x;
  for (int a = 0; a < dimension_; ++a) y[a] = std::clamp(y[a], -0.5, canvas_.dims[a] - 0.5);
  return y;
}

bool GeodesicTracer::in_seed_block(const Vec3& x, const VoxelIndex& seed_voxel,
                                   int32_t label) const {
  const std::array<int, 3> centre{seed_voxel.i, seed_voxel.j, seed_voxel.k};
  for (int a = 0; a < dimension_; ++a)
    if (std::abs(x[a] - centre[static_cast<std::size_t>(a)]) > kSeedBlockRadius) return false;
  bool all = true, any = false;
  for_each_corner(x, [&](int64_t slot, double) {  // active corners only
    const bool c = carries(slot, label);
    all = all && c;
    any = any || c;
  });
  return all && any;
}

// Whether the segment p-q (index coordinates) passes through voxels of the label: at every sample
// (`spacing` apart along its longest axis), one of the voxels nearest the point (both, per axis,
// at a tie) other than the voxels nearest its two ends carries it, where there is such a voxel
// (none halfway along a step to a face neighbour). Otherwise a diagonal step, or one of several
// voxels (stencil steps are up to 0.71 times the anisotropy long), could cross a one-voxel wall of
// inactive voxels, or a strip of another label, into the label's voxels beyond. Between voxel
// centres sampled every half voxel the ties are exact (a quotient of integers that is a
// half-integer is representable); a shortcut sampled finer may graze a cell's corner by less than
// its spacing unseen.
bool GeodesicTracer::segment_on_canvas(const Vec3& p, const Vec3& q) const {
  const int samples =
      std::max(1, static_cast<int>(std::ceil(2.0 * (q - p).cwiseAbs().maxCoeff() - 1e-9)));
  for (int n = 0; n <= samples; ++n)
    if (canvas_.slot_of(nearest_voxel(p + (q - p) * (static_cast<double>(n) / samples))) < 0)
      return false;
  return true;
}

bool GeodesicTracer::segment_carries(const Vec3& p, const Vec3& q, int32_t label,
                                     double spacing) const {
  const VoxelIndex from = nearest_voxel(p), to = nearest_voxel(q);
  const int samples =
      std::max(1, static_cast<int>(std::ceil((q - p).cwiseAbs().maxCoeff() / spacing - 1e-9)));
  for (int n = 1; n < samples; ++n) {
    std::array<std::array<int, 2>, 3> nearest{};  // per axis, the voxels nearest the point
    for (int a = 0; a < 3; ++a) {
      const double x = a < dimension_ ? p[a] + (q[a] - p[a]) * n / samples : 0.0;
      nearest[static_cast<std::size_t>(a)] = {static_cast<int>(std::ceil(x - 0.5)),
                                              static_cast<int>(std::floor(x + 0.5))};
    }
    bool between = false, carried = false;
    for (int k = nearest[2][0]; k <= nearest[2][1] && !carried; ++k)
      for (int j = nearest[1][0]; j <= nearest[1][1] && !carried; ++j)
        for (int i = nearest[0][0]; i <= nearest[0][1] && !carried; ++i) {
          if ((i == from.i && j == from.j && k == from.k) || (i == to.i && j == to.j && k == to.k))
            continue;
          between = true;
          carried = carries(canvas_.slot_of(i, j, k), label);
        }
    if (between && !carried) return false;
  }
  return true;
}

// Steepest descent over voxels from the voxel of `label` nearest below x: each step moves to the
// voxel within a Chebyshev radius of 1 (2 where none of those is lower) that lowers the distance
// most per unit of metric length, until the seed's block (see in_seed_block). Where none within 2
// is lower, it steps along the voxel's Selling stencil: the neighbours the solver computed its
// value from (up to 0.71 times the anisotropy away in 3D), of which one is lower wherever the
// update is causal; the segment must pass through voxels of the label (segment_carries). Without
// that, radial_shock_3d (anisotropy 40 at the shock, several voxels thick at 128^3 and finer) left
// 26 of 14187 edges unreached at 192^3 with 2000 seeds, 15 of 6814 at 128^3 with 1000: each at a
// voxel 5 to 9 voxels from its seed whose 124 neighbours within 2 were all known and higher, with
// 2 to 4 lower stencil neighbours 3 to 5 voxels away.
bool GeodesicTracer::discrete_descent(const Vec3& x, const Vec3& target,
                                      const VoxelIndex& seed_voxel, int32_t label,
                                      std::vector<Vec3>& path) const {
  // The start: the least distance among the corners of x's cell, else within the 4^d block.
  int64_t current = -1;
  double u = std::numeric_limits<double>::infinity();
  for (int reach = 1; reach <= 2 && current < 0; ++reach) {
    const int bi = static_cast<int>(std::floor(x.x())), bj = static_cast<int>(std::floor(x.y()));
    const int bk = dimension_ == 3 ? static_cast<int>(std::floor(x.z())) : 0;
    const int k_lo = dimension_ == 3 ? 1 - reach : 0, k_hi = dimension_ == 3 ? reach : 0;
    for (int dk = k_lo; dk <= k_hi; ++dk)
      for (int dj = 1 - reach; dj <= reach; ++dj)
        for (int di = 1 - reach; di <= reach; ++di) {
          const int64_t slot = canvas_.slot_of(bi + di, bj + dj, bk + dk);
          const double d = distance_of(slot, label);
          if (d < u) u = d, current = slot;
        }
  }
  if (current < 0) return false;
  VoxelIndex v = canvas_.voxel_of(static_cast<std::size_t>(current));
  path.push_back(Vec3(v.i, v.j, v.k));
  const double h = canvas_.voxel_size;
  for (;;) {  // u decreases strictly: it ends
    const Vec3 here(v.i, v.j, v.k);
    if ((target - here).norm() <= kArrival || in_seed_block(here, seed_voxel, label)) {
      path.push_back(target);
      return true;
    }
    const Mat3 G = canvas_.metric_at(static_cast<std::size_t>(current));
    double best_slope = 0.0;
    int64_t next = -1;
    // The step to v + offset if it lowers u most per unit of metric length so far.
    auto consider = [&](const std::array<int, 3>& offset) {
      const int64_t slot = canvas_.slot_of(v.i + offset[0], v.j + offset[1], v.k + offset[2]);
      const double d = distance_of(slot, label);
      if (!(d < u) || !segment_carries(here, here + Vec3(offset[0], offset[1], offset[2]), label,
                                       kStaircaseSpacing))
        return;
      const Vec3 step(offset[0], offset[1], offset[2]);
      const Mat3 M = 0.5 * (G + canvas_.metric_at(static_cast<std::size_t>(slot)));
      const double slope = (u - d) / (h * std::sqrt(step.dot(M * step)));
      if (slope > best_slope) best_slope = slope, next = slot;
    };
    for (int reach = 1; reach <= 2 && next < 0; ++reach) {
      const int kr = dimension_ == 3 ? reach : 0;
      for (int dk = -kr; dk <= kr; ++dk)
        for (int dj = -reach; dj <= reach; ++dj)
          for (int di = -reach; di <= reach; ++di) consider({di, dj, dk});
    }
    if (next < 0) {  // the solver's stencil, as the engines build it (device_canvas.cpp)
      const SellingStencil stencil =
          canvas_selling_decomposition(canvas_, static_cast<std::size_t>(current), G.inverse());
      for (int t = 0; t < stencil.size; ++t)
        for (int sign = -1; sign <= 1; sign += 2) {
          const auto& e = stencil.offset[static_cast<std::size_t>(t)];
          consider({sign * e[0], sign * e[1], sign * e[2]});
        }
    }
    if (next < 0) return false;  // a discrete local minimum away from the seed
    current = next;
    u = distance_of(current, label);
    v = canvas_.voxel_of(static_cast<std::size_t>(current));
    path.push_back(Vec3(v.i, v.j, v.k));
  }
}

double GeodesicTracer::segment_length(const Vec3& p, const Vec3& q) const {
  const std::vector<Vec3> points = division_points(p, q);
  double length = 0.0;
  for (std::size_t n = 0; n < points.size(); ++n) {
    const Vec3& b = n + 1 < points.size() ? points[n + 1] : q;
    length += metric_length(metric_near(0.5 * (points[n] + b)), b - points[n]);
  }
  return length;
}

// A staircase of voxel centres is the discrete field's steepest descent, not a geodesic: it turns
// at every voxel. From each of its points, the farthest later point (within kPullWindow) that a
// straight segment reaches through voxels where the label's distance is known, no longer in the
// metric than the staircase between them, replaces the points in between; the segments are
// divided at kStep, as traced descents are. Each replacement shortens the path, so the polyline
// is the staircase's or shorter everywhere, and it stays where the field is known.
void GeodesicTracer::pull_taut(const Vec3& anchor, int32_t label, std::vector<Vec3>& path,
                               std::size_t from) const {
  std::vector<Vec3> stairs{anchor};
  stairs.insert(stairs.end(), path.begin() + static_cast<std::ptrdiff_t>(from), path.end());
  std::vector<double> along(stairs.size(), 0.0);  // metric length from the anchor
  for (std::size_t n = 1; n < stairs.size(); ++n)
    along[n] = along[n - 1] + segment_length(stairs[n - 1], stairs[n]);
  path.resize(from);
  for (std::size_t i = 0; i + 1 < stairs.size();) {
    std::size_t reach = i + 1;
    for (std::size_t j = i + 2; j < stairs.size() && j <= i + kPullWindow; ++j)
      if (segment_length(stairs[i], stairs[j]) <= along[j] - along[i] &&
          segment_carries(stairs[i], stairs[j], label, kPullSpacing))
        reach = j;
    const std::vector<Vec3> points = division_points(stairs[i], stairs[reach]);
    path.insert(path.end(), points.begin() + 1, points.end());
    path.push_back(stairs[reach]);
    i = reach;
  }
}

bool GeodesicTracer::trace(const Vec3& start, const Vec3& target, int32_t label,
                           std::vector<Vec3>& path, bool* staircase) const {
  if (staircase) *staircase = false;
  Vec3 x = start;
  const VoxelIndex seed_voxel = canvas_.voxel_containing(world_of_index(canvas_, target));
  const double straight = (target - x).norm();
  const std::size_t max_steps = static_cast<std::size_t>(8.0 * straight / kStep) + 64;
  Vec3 direction = Vec3::Zero();  // kept across cells without a voxel of the label
  int misses = 0;
  const std::size_t first = path.size();
  std::size_t known = first;  // path size at the last point where the label was sampled
  Vec3 known_x = start;
  // Where the descent stalls (it cycles, is pushed against the canvas's boundary, runs out of
  // steps) or leaves the label's voxels, it goes on over voxels from the last point it sampled.
  auto give_up = [&]() {
    path.resize(known);
    const bool reached = discrete_descent(known_x, target, seed_voxel, label, path);
    if (reached && pull_staircases_)
      pull_taut(known > first ? path[known - 1] : start, label, path, known);
    if (staircase) *staircase = reached;
    return reached;
  };
  for (std::size_t step = 0; step < max_steps; ++step) {
    if ((target - x).norm() <= kArrival || in_seed_block(x, seed_voxel, label)) {
      path.push_back(target);
      return true;
    }
    Vec3 gradient;
    Mat3 G;
    const bool sampled =
        (sample(x, label, gradient, G) && !gradient.isZero()) ||
        (sample_wide(x, label, gradient, G, 2) && !gradient.isZero()) ||  // e.g. a sliver
        (sample_wide(x, label, gradient, G, 4) && !gradient.isZero());
    if (sampled) {
      misses = 0;
      known = path.size();
      known_x = x;
      direction = -G.ldlt().solve(gradient);  // index units; only the direction matters
      if (dimension_ == 2) direction.z() = 0.0;
    } else if (++misses > kMaxMisses || direction.isZero()) {
      return give_up();  // off the voxels of the label for too long
    }
    const double norm = direction.norm();
    if (!(norm > 1e-12)) return give_up();
    const Vec3 before = x;
    x = inside_canvas(x + (kStep / norm) * direction);
    if ((x - before).norm() < 1e-3 * kStep) return give_up();  // pushed against the boundary
    // Back where it was two steps ago: the descent cycles (an interpolated minimum).
    if (path.size() >= first + 2 && (x - path[path.size() - 2]).norm() < 0.1 * kStep)
      return give_up();
    path.push_back(x);
  }
  return give_up();
}

Vec3 GeodesicTracer::refine_bisector_point(const Vec3& start, int32_t a, int32_t b) const {
  Vec3 x = start;
  for (int iteration = 0; iteration < kRefineIterations; ++iteration) {
    Vec3 seed_a, seed_b;
    if (!seed_estimate(x, a, seed_a) || !seed_estimate(x, b, seed_b)) break;
    Vec3 delta = 0.5 * (seed_a + seed_b) - x;
    if (dimension_ == 2) delta.z() = 0.0;
    const double norm = delta.norm();
    if (norm < 1e-3) break;
    if (norm > 1.0) delta /= norm;  // at most a voxel per iteration
    bool moved = false;             // halve the move until it stays on the face
    for (int halving = 0; halving < 6 && !moved; ++halving, delta *= 0.5) {
      const Vec3 next = inside_canvas(x + delta);
      if (cell_carries(next, a) && cell_carries(next, b)) {
        x = next;
        moved = true;
      }
    }
    if (!moved) break;
  }
  return x;
}

Mat3 GeodesicTracer::metric_near(const Vec3& x) const {
  Mat3 G = Mat3::Zero();
  double total = 0.0;
  for_each_corner(x, [&](int64_t slot, double w) {
    G += w * canvas_.metric_at(static_cast<std::size_t>(slot));
    total += w;
  });
  if (total > kMinWeight) return G / total;
  const VoxelIndex v = nearest_voxel(x);
  const int64_t slot = canvas_.slot_of(v);
  return slot >= 0 ? canvas_.metric_at(static_cast<std::size_t>(slot)) : Mat3::Identity();
}
Vec3 world_of_index(const Canvas& canvas, const Vec3& x) {
  Vec3 w = canvas.origin + canvas.voxel_size * x;
  if (canvas.dimension == 2) w.z() = canvas.origin.z();
  return w;
}

}  // namespace rvor::detail
