// The curved dual: nerve edges traced as geodesics by descending the distance field of each side's
// label from the edge's bisector point of smallest distance (curved_dual.h), and its VTK file.
#include "rvor/curved_dual.h"

#include <Eigen/Dense>
#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <limits>
#include <thread>

#include "rvor/error.h"
#include "vtu_appended_writer.h"

namespace rvor {

namespace {

constexpr double kStep = 0.5;          // voxels per tracing step
constexpr double kArrival = 1.0;       // voxels: a trace this close to its seed has reached it
constexpr double kMinWeight = 1e-9;    // below: corner weights are renormalised uniformly
constexpr int kMaxMisses = 16;         // steps through cells without a voxel of the label
constexpr int kRefineIterations = 64;  // moves of at most a voxel each
constexpr uint8_t kVtkPolyLine = 4;

class Tracer {
 public:
  Tracer(const Canvas& canvas, const VoronoiField& field)
      : canvas_(canvas), field_(field), dimension_(canvas.dimension) {}

  // Traces from `start` (index coordinates) towards the seed at `target` (index coordinates)
  // through voxels of `label`. Appends the visited points (index coordinates, not `start`) to
  // `path`, ending with `target` when reached.
  bool trace(const Vec3& start, const Vec3& target, int32_t label, std::vector<Vec3>& path) const {
    Vec3 x = start;
    const double straight = (target - x).norm();
    const std::size_t max_steps = static_cast<std::size_t>(8.0 * straight / kStep) + 64;
    Vec3 direction = Vec3::Zero();  // kept across cells without a voxel of the label
    int misses = 0;
    for (std::size_t step = 0; step < max_steps; ++step) {
      if ((target - x).norm() <= kArrival) {
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
        direction = -G.ldlt().solve(gradient);  // index units; only the direction matters
        if (dimension_ == 2) direction.z() = 0.0;
      } else if (++misses > kMaxMisses || direction.isZero()) {
        return false;  // off the voxels of the label for too long
      }
      const double norm = direction.norm();
      if (!(norm > 1e-12)) return false;
      x += (kStep / norm) * direction;
      path.push_back(x);
    }
    return false;
  }

  // Moves a bisector point of edge (a, b) (index coordinates) to where the geodesic from a to b
  // crosses the bisector: the fixed point of x -> midpoint of the seeds as seen from x, each seed
  // estimated from the voxels of its label around x as v - G^{-1} grad(u^2) / (2 h^2) (exact for
  // a uniform metric; in general the fixed point is where the descent directions towards a and b
  // are opposite and u_a = u_b). The point stays in grid cells that carry both labels: the
  // discrete common Voronoi face. Returns the start unchanged when no such move exists.
  Vec3 refine_bisector_point(const Vec3& start, int32_t a, int32_t b) const {
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
        const Vec3 next = x + delta;
        if (cell_carries(next, a) && cell_carries(next, b)) {
          x = next;
          moved = true;
        }
      }
      if (!moved) break;
    }
    return x;
  }

  // The metric at a point (index coordinates): interpolated over the active corners of its cell.
  Mat3 metric_near(const Vec3& x) const {
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

 private:
  VoxelIndex nearest_voxel(const Vec3& x) const {
    return {static_cast<int>(std::lround(x.x())), static_cast<int>(std::lround(x.y())),
            dimension_ == 3 ? static_cast<int>(std::lround(x.z())) : 0};
  }

  // Calls f(slot, weight) for each active corner of the grid cell containing x, with its
  // bi/trilinear weight.
  template <typename F>
  void for_each_corner(const Vec3& x, F&& f) const {
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

  bool carries(int64_t slot, int32_t label) const {
    return slot >= 0 && field_.label[static_cast<std::size_t>(slot)] == label &&
           std::isfinite(field_.distance[static_cast<std::size_t>(slot)]);
  }

  // Squared distance at a slot carrying `label`, or NaN.
  double squared_distance(int64_t slot, int32_t label) const {
    if (!carries(slot, label)) return std::numeric_limits<double>::quiet_NaN();
    const double u = field_.distance[static_cast<std::size_t>(slot)];
    return u * u;
  }

  // Finite-difference gradient of the squared distance u^2 at a voxel of `label`, from its
  // neighbours of the same label (index units): central where both neighbours carry the label,
  // else one-sided of second order where two voxels on one side do, else of first order. u^2
  // descends along the same direction as u, but is smooth at the seed and quadratic in a uniform
  // metric, where these differences are exact.
  // `complete` is false when some axis has no neighbour of the label (the component is then 0).
  Vec3 voxel_gradient(int64_t slot, int32_t label, bool& complete) const {
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

  bool cell_carries(const Vec3& x, int32_t label) const {
    bool found = false;
    for_each_corner(x, [&](int64_t slot, double) { found = found || carries(slot, label); });
    return found;
  }

  // The seed of `label` as extrapolated from the corners of x's cell that carry the label
  // (index coordinates): per corner v, v - G_v^{-1} grad(u^2)_v / (2 h^2), weighted as in sample.
  bool seed_estimate(const Vec3& x, int32_t label, Vec3& seed) const {
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
  bool sample_wide(const Vec3& x, int32_t label, Vec3& gradient, Mat3& G, int reach) const {
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
  bool sample(const Vec3& x, int32_t label, Vec3& gradient, Mat3& G) const {
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

  const Canvas& canvas_;
  const VoronoiField& field_;
  int dimension_;
};

Vec3 world_of_index(const Canvas& canvas, const Vec3& x) {
  Vec3 w = canvas.origin + canvas.voxel_size * x;
  if (canvas.dimension == 2) w.z() = canvas.origin.z();
  return w;
}

CurvedEdge trace_edge(const Canvas& canvas, const Tracer& tracer, const NerveSimplex& edge,
                      const std::vector<Vec3>& seeds) {
  CurvedEdge out;
  out.seeds = {edge.seeds[0], edge.seeds[1]};
  Vec3 start = canvas.index_coordinates(edge.nearest.position);
  if (canvas.dimension == 2) start.z() = 0.0;
  start = tracer.refine_bisector_point(start, out.seeds[0], out.seeds[1]);
  std::array<std::vector<Vec3>, 2> sides;  // index coordinates, from the bisector outwards
  for (int s = 0; s < 2; ++s) {
    Vec3 target = canvas.index_coordinates(seeds[static_cast<std::size_t>(out.seeds[s])]);
    if (canvas.dimension == 2) target.z() = 0.0;
    out.side_reached[s] = tracer.trace(start, target, out.seeds[s], sides[s]);
  }
  std::vector<Vec3> index_points(sides[0].rbegin(), sides[0].rend());
  out.bisector_index = index_points.size();
  index_points.push_back(start);
  index_points.insert(index_points.end(), sides[1].begin(), sides[1].end());

  out.points.reserve(index_points.size());
  for (std::size_t p = 0; p < index_points.size(); ++p) {
    const bool seed_end =
        (p == 0 && out.side_reached[0]) || (p + 1 == index_points.size() && out.side_reached[1]);
    out.points.push_back(seed_end ? seeds[static_cast<std::size_t>(out.seeds[p == 0 ? 0 : 1])]
                                  : world_of_index(canvas, index_points[p]));
  }
  for (std::size_t p = 1; p < out.points.size(); ++p) {
    const Mat3 G = tracer.metric_near(0.5 * (index_points[p - 1] + index_points[p]));
    out.length += metric_length(G, out.points[p] - out.points[p - 1]);
  }
  return out;
}

}  // namespace

CurvedDual build_curved_dual(const Canvas& canvas, const VoronoiField& field, const Nerve& nerve,
                             const std::vector<Vec3>& seeds) {
  const auto t0 = std::chrono::steady_clock::now();
  if (field.distance.size() != canvas.slot_count() || field.label.size() != canvas.slot_count())
    throw Error("curved dual: the field has " + std::to_string(field.distance.size()) +
                " distances and " + std::to_string(field.label.size()) + " labels, the canvas " +
                std::to_string(canvas.slot_count()) + " slots");
  if (nerve.seed_count != seeds.size())
    throw Error("curved dual: the nerve has " + std::to_string(nerve.seed_count) + " seeds, " +
                std::to_string(seeds.size()) + " given");
  for (const NerveSimplex& e : nerve.edges)
    if (e.vertex_count != 2 || e.seeds[0] < 0 || e.seeds[1] < 0 ||
        static_cast<std::size_t>(std::max(e.seeds[0], e.seeds[1])) >= seeds.size())
      throw Error("curved dual: nerve edge (" + std::to_string(e.seeds[0]) + ", " +
                  std::to_string(e.seeds[1]) + ") does not name two of the " +
                  std::to_string(seeds.size()) + " seeds");

  CurvedDual dual;
  dual.dimension = canvas.dimension;
  dual.vertices = seeds;
  dual.edges.resize(nerve.edges.size());
  const Tracer tracer(canvas, field);
  std::atomic<std::size_t> next{0};
  auto work = [&] {
    for (std::size_t e; (e = next.fetch_add(1)) < nerve.edges.size();)
      dual.edges[e] = trace_edge(canvas, tracer, nerve.edges[e], seeds);
  };
  const std::size_t threads =
      std::min<std::size_t>(std::max(1u, std::thread::hardware_concurrency()),
                            std::max<std::size_t>(1, nerve.edges.size() / 64));
  std::vector<std::thread> pool;
  for (std::size_t t = 1; t < threads; ++t) pool.emplace_back(work);
  work();
  for (std::thread& t : pool) t.join();

  for (const CurvedEdge& e : dual.edges) dual.unreached_edges += e.reached() ? 0 : 1;
  dual.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return dual;
}

void write_curved_dual_vtu(const std::string& path, const CurvedDual& dual) {
  std::vector<float> points;
  std::vector<int64_t> connectivity, offsets;
  std::vector<uint8_t> types, reached;
  std::vector<double> length;
  std::vector<int32_t> seed_a, seed_b;
  for (const CurvedEdge& e : dual.edges) {
    for (const Vec3& p : e.points) {
      connectivity.push_back(static_cast<int64_t>(points.size() / 3));
      for (int a = 0; a < 3; ++a) points.push_back(static_cast<float>(p[a]));
    }
    offsets.push_back(static_cast<int64_t>(connectivity.size()));
    types.push_back(kVtkPolyLine);
    reached.push_back(e.reached() ? 1 : 0);
    length.push_back(e.length);
    seed_a.push_back(e.seeds[0]);
    seed_b.push_back(e.seeds[1]);
  }
  vtu::AppendedWriter appended;
  std::string xml = vtu::grid_header(points.size() / 3, types.size());
  xml += appended.declare("Float32", "", 3, points);
  xml += "</Points>\n<Cells>\n";
  xml += appended.declare("Int64", "connectivity", 1, connectivity);
  xml += appended.declare("Int64", "offsets", 1, offsets);
  xml += appended.declare("UInt8", "types", 1, types);
  xml += "</Cells>\n<CellData Scalars=\"length\">\n";
  xml += appended.declare("Float64", "length", 1, length);
  xml += appended.declare("UInt8", "reached", 1, reached);
  xml += appended.declare("Int32", "seed_a", 1, seed_a);
  xml += appended.declare("Int32", "seed_b", 1, seed_b);
  xml += "</CellData>\n";
  vtu::publish(path, std::move(xml), appended);
}

}  // namespace rvor
