// The sequential CPU reference solver of docs/scheme.md: double precision, label-correcting
// Dijkstra on the reverse stencil graph. It is the ground truth the OpenCL kernels are checked
// against, so it favours clarity; the inner loop (local_solve) is allocation-free.
#include "reference_solver.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>
#include <functional>
#include <limits>
#include <memory>

#include <Eigen/LU>

#include "rvor/error.h"
#include "rvor/seeds.h"
#include "rvor/selling.h"

namespace rvor::detail {

namespace {

constexpr double kInfinity = std::numeric_limits<double>::infinity();
// Half-width r of the (2r+1)^d block initialised exactly around each seed's voxel.
constexpr int kInitRadius = 2;
// A candidate replaces a value only when smaller by this relative amount (or equal-ish with a
// smaller label): strict decrease with a margin guarantees termination despite rounding.
constexpr double kRelativeDecrease = 1e-12;

// D = G^-1 in double from the float metric; in 2D only the 2x2 block is meaningful.
Mat3 dual_metric(const Canvas& canvas, std::size_t slot) {
  const Mat3 G = canvas.metric_at(slot);
  if (canvas.dimension == 3) return G.inverse();
  Mat3 D = Mat3::Identity();
  D.topLeftCorner<2, 2>() = G.topLeftCorner<2, 2>().inverse();
  return D;
}

VoxelStencil to_voxel_stencil(const SellingStencil& selling) {
  VoxelStencil stencil;
  stencil.size = static_cast<int8_t>(selling.size);
  for (int t = 0; t < selling.size; ++t) {
    stencil.weight[t] = selling.weight[t];
    for (int a = 0; a < 3; ++a) {
      const int c = selling.offset[t][a];
      if (c < -127 || c > 127)
        throw Error("reference solver: stencil offset component " + std::to_string(c) +
                    " does not fit in int8 (metric anisotropy too large)");
      stencil.offset[t][a] = static_cast<int8_t>(c);
    }
  }
  return stencil;
}

// Solves sum_k rho_k max(0, t - w_k)^2 = h^2 for its largest root, w sorted ascending (n >= 1).
// Solved for tau = t - w_0 so that large distances do not cancel catastrophically.
double solve_sorted_quadratic(const double* w, const double* rho, int n, double h) {
  double a = 0, b = 0, c = -h * h;
  double tau = 0;
  for (int k = 0; k < n; ++k) {
    const double delta = w[k] - w[0];
    a += rho[k];
    b += rho[k] * delta;
    c += rho[k] * delta * delta;
    tau = (b + std::sqrt(std::max(0.0, b * b - a * c))) / a;
    if (k + 1 == n || w[0] + tau <= w[k + 1]) break;
  }
  return w[0] + tau;
}

}  // namespace

ReferenceSolver::ReferenceSolver(const Canvas& canvas)
    : dimension_(canvas.dimension),
      h_(canvas.voxel_size),
      origin_(canvas.origin),
      slot_count_(canvas.slot_count()) {
  if (slot_count_ >= static_cast<std::size_t>(std::numeric_limits<int32_t>::max()))
    throw Error("reference solver: canvas has too many slots for 32-bit voxel ids");
  voxel_of_slot_.assign(slot_count_, -1);
  for (std::size_t slot = 0; slot < slot_count_; ++slot) {
    if (!canvas.active[slot]) continue;
    voxel_of_slot_[slot] = static_cast<int32_t>(slot_of_voxel_.size());
    slot_of_voxel_.push_back(static_cast<int32_t>(slot));
    index_of_voxel_.push_back(canvas.voxel_of(slot));
  }
  compute_stencils(canvas);
  compute_neighbours(canvas);
  compute_reverse_graph();
}

void ReferenceSolver::compute_stencils(const Canvas& canvas) {
  stencil_of_voxel_.resize(slot_of_voxel_.size());
  stencils_.clear();
  const float* previous_metric = nullptr;
  for (std::size_t v = 0; v < slot_of_voxel_.size(); ++v) {
    const float* metric = &canvas.metric[6 * static_cast<std::size_t>(slot_of_voxel_[v])];
    // Uniform regions repeat the same tensor: share the previous stencil instead of recomputing.
    if (!previous_metric || std::memcmp(metric, previous_metric, 6 * sizeof(float)) != 0)
      stencils_.push_back(to_voxel_stencil(
          selling_decomposition(dual_metric(canvas, slot_of_voxel_[v]), dimension_)));
    stencil_of_voxel_[v] = static_cast<int32_t>(stencils_.size() - 1);
    previous_metric = metric;
  }
}

void ReferenceSolver::compute_neighbours(const Canvas& canvas) {
  neighbour_.assign(12 * slot_of_voxel_.size(), -1);
  for (std::size_t v = 0; v < slot_of_voxel_.size(); ++v) {
    const VoxelIndex& x = index_of_voxel_[v];
    const VoxelStencil& stencil = stencils_[stencil_of_voxel_[v]];
    for (int t = 0; t < stencil.size; ++t) {
      const int8_t* e = stencil.offset[t];
      for (int side = 0; side < 2; ++side) {
        const int sign = side == 0 ? 1 : -1;
        const int64_t slot =
            canvas.slot_of(x.i + sign * e[0], x.j + sign * e[1], x.k + sign * e[2]);
        if (slot >= 0) neighbour_[12 * v + 2 * t + side] = voxel_of_slot_[slot];
      }
    }
  }
}

void ReferenceSolver::compute_reverse_graph() {
  const std::size_t n = slot_of_voxel_.size();
  reverse_begin_.assign(n + 1, 0);
  for (int32_t y : neighbour_)
    if (y >= 0) ++reverse_begin_[y + 1];
  for (std::size_t v = 0; v < n; ++v) reverse_begin_[v + 1] += reverse_begin_[v];
  reverse_.resize(reverse_begin_[n]);
  std::vector<int64_t> fill(reverse_begin_.begin(), reverse_begin_.end() - 1);
  for (std::size_t entry = 0; entry < neighbour_.size(); ++entry) {
    const int32_t y = neighbour_[entry];
    if (y >= 0) reverse_[fill[y]++] = static_cast<int32_t>(entry / 12);
  }
}

PropagationStats ReferenceSolver::solve(const Canvas& canvas, const std::vector<Vec3>& seeds,
                                        ExactField& field) {
  ExactField empty;
  empty.distance.assign(slot_count_, kInfinity);
  empty.label.assign(slot_count_, -1);
  field = std::move(empty);
  return insert(canvas, seeds, 0, field);
}

PropagationStats ReferenceSolver::insert(const Canvas& canvas, const std::vector<Vec3>& seeds,
                                         std::size_t first_new, ExactField& field) {
  const auto start = std::chrono::steady_clock::now();
  if (canvas.slot_count() != slot_count_ || field.distance.size() != slot_count_ ||
      field.label.size() != slot_count_)
    throw Error("reference solver: the field does not match the canvas (slot counts differ)");
  if (first_new > seeds.size())
    throw Error("reference solver: first new seed index is past the end of the seed list");
  validate_seeds(canvas, seeds);
  load_seeds(canvas, seeds);
  load_field(field);
  PropagationStats stats;
  initialise_seed_blocks(canvas, first_new);
  run_queue(stats);
  store_field(field);
  stats.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return stats;
}

void ReferenceSolver::load_seeds(const Canvas& canvas, const std::vector<Vec3>& seeds) {
  if (seeds.size() > static_cast<std::size_t>(std::numeric_limits<int32_t>::max()))
    throw Error("reference solver: too many seeds");
  seeds_.clear();
  for (const Vec3& position : seeds) {
    Vec3 p = position;
    if (dimension_ == 2) p.z() = origin_.z();  // 2D: the z coordinate plays no role
    const int64_t slot = canvas.slot_of(canvas.voxel_containing(p));
    seeds_.push_back({p, canvas.metric_at(static_cast<std::size_t>(slot))});
  }
}

void ReferenceSolver::load_field(const ExactField& field) {
  const std::size_t n = slot_of_voxel_.size();
  state_.resize(n);
  for (std::size_t v = 0; v < n; ++v)
    state_[v] = {field.distance[slot_of_voxel_[v]], field.label[slot_of_voxel_[v]]};
}

void ReferenceSolver::store_field(ExactField& field) const {
  for (std::size_t v = 0; v < slot_of_voxel_.size(); ++v) {
    field.distance[slot_of_voxel_[v]] = state_[v].value;
    field.label[slot_of_voxel_[v]] = state_[v].label;
  }
}

// Exact values u0_s(x) = |F_s (x - s)| in the (2r+1)^d block around each new seed's voxel.
void ReferenceSolver::initialise_seed_blocks(const Canvas& canvas, std::size_t first_seed) {
  queue_.clear();
  const int rz = dimension_ == 3 ? kInitRadius : 0;
  for (std::size_t s = first_seed; s < seeds_.size(); ++s) {
    const VoxelIndex c = canvas.voxel_containing(seeds_[s].position);
    for (int dk = -rz; dk <= rz; ++dk)
      for (int dj = -kInitRadius; dj <= kInitRadius; ++dj)
        for (int di = -kInitRadius; di <= kInitRadius; ++di) {
          const int64_t slot = canvas.slot_of(c.i + di, c.j + dj, c.k + dk);
          if (slot < 0) continue;
          const int32_t voxel = voxel_of_slot_[slot];
          const Vec3 p = position_of(voxel) - seeds_[s].position;
          const double u0 = std::sqrt(std::max(0.0, p.dot(seeds_[s].G * p)));
          if (offer(voxel, u0, static_cast<int32_t>(s))) {
            queue_.push_back({u0, voxel});
            std::push_heap(queue_.begin(), queue_.end(), std::greater<QueueEntry>());
          }
        }
  }
}

// Label-correcting Dijkstra: pop the smallest value; every voxel that has the popped voxel y in
// its stencil is re-solved for y's label (only y changed, so only that label's candidate can have
// decreased: the candidates of other labels count y as +inf or did not involve it).
void ReferenceSolver::run_queue(PropagationStats& stats) {
  while (!queue_.empty()) {
    std::pop_heap(queue_.begin(), queue_.end(), std::greater<QueueEntry>());
    const QueueEntry entry = queue_.back();
    queue_.pop_back();
    if (entry.value != state_[entry.voxel].value) continue;  // stale: the voxel decreased since
    ++stats.iterations;
    const int32_t label = state_[entry.voxel].label;
    for (int64_t r = reverse_begin_[entry.voxel]; r < reverse_begin_[entry.voxel + 1]; ++r) {
      const int32_t x = reverse_[r];
      const double t = local_solve(x, label);
      ++stats.voxel_updates;
      if (offer(x, t, label)) {
        queue_.push_back({t, x});
        std::push_heap(queue_.begin(), queue_.end(), std::greater<QueueEntry>());
      }
    }
  }
}

// Values only decrease: a candidate wins when clearly smaller, or when not larger and carrying a
// smaller label (the tie rule of the scheme).
bool ReferenceSolver::offer(int32_t voxel, double value, int32_t label) {
  VoxelState& state = state_[voxel];
  const bool smaller = value < state.value * (1 - kRelativeDecrease);
  const bool tie_won = value <= state.value && label < state.label;
  if (!smaller && !tie_won) return false;
  state = {value, label};
  return true;
}

// The candidate value of `voxel` for `label` (docs/scheme.md, "Local update"), +inf if no
// stencil neighbour carries that label.
double ReferenceSolver::local_solve(int32_t voxel, int32_t label) const {
  const Seed& seed = seeds_[label];
  const Vec3 p = position_of(voxel) - seed.position;
  const Vec3 Gp = seed.G * p;
  const double u0_squared = std::max(0.0, p.dot(Gp));
  const double u0 = std::sqrt(u0_squared);
  const bool factorize = u0 > 0;

  const VoxelStencil& stencil = stencils_[stencil_of_voxel_[voxel]];
  const int32_t* neighbours = &neighbour_[12 * static_cast<std::size_t>(voxel)];
  double w[6], rho[6];
  int n = 0;
  for (int t = 0; t < stencil.size; ++t) {
    const Vec3 step = h_ * Vec3(stencil.offset[t][0], stencil.offset[t][1], stencil.offset[t][2]);
    const double step_dot_Gp = step.dot(Gp);            // h e^T G_s p
    const double step_norm2 = step.dot(seed.G * step);  // h^2 e^T G_s e
    double best = kInfinity;
    for (int side = 0; side < 2; ++side) {
      const int32_t y = neighbours[2 * t + side];
      if (y < 0 || state_[y].label != label) continue;
      double v = state_[y].value;
      if (factorize) {
        // v + u0(x) - u0(y) + <grad u0(x), y - x>, y = x + sign h e.
        const double sign = side == 0 ? 1.0 : -1.0;
        const double u0_y =
            std::sqrt(std::max(0.0, u0_squared + 2 * sign * step_dot_Gp + step_norm2));
        v += u0 - u0_y + sign * step_dot_Gp / u0;
      }
      best = std::min(best, v);
    }
    if (best == kInfinity) continue;
    // Insertion into the sorted (w, rho) arrays: at most 6 terms.
    int k = n++;
    for (; k > 0 && w[k - 1] > best; --k) {
      w[k] = w[k - 1];
      rho[k] = rho[k - 1];
    }
    w[k] = best;
    rho[k] = stencil.weight[t];
  }
  if (n == 0) return kInfinity;
  return solve_sorted_quadratic(w, rho, n, h_);
}

namespace {

// Identifies a canvas by content, so that insert() can reuse the stencils of the previous call.
uint64_t fingerprint(const Canvas& canvas) {
  uint64_t hash = 1469598103934665603ull;
  auto mix = [&hash](uint64_t word) {
    hash ^= word;
    hash *= 1099511628211ull;
    hash ^= hash >> 29;
  };
  auto mix_double = [&mix](double x) {
    uint64_t bits;
    std::memcpy(&bits, &x, sizeof bits);
    mix(bits);
  };
  mix(static_cast<uint64_t>(canvas.dimension));
  for (int a = 0; a < 3; ++a) {
    mix(static_cast<uint64_t>(canvas.dims[a]));
    mix_double(canvas.origin[a]);
  }
  mix_double(canvas.voxel_size);
  for (const VoxelIndex& o : canvas.brick_origins)
    mix((static_cast<uint64_t>(o.i) << 42) ^ (static_cast<uint64_t>(o.j) << 21) ^
        static_cast<uint64_t>(o.k));
  for (uint8_t a : canvas.active) mix(a);
  for (float m : canvas.metric) {
    uint32_t bits;
    std::memcpy(&bits, &m, sizeof bits);
    mix(bits);
  }
  return hash;
}

// The public Propagator: float fields outside, double inside. It remembers the double field of
// its last call, so that a chain of insert() calls keeps full precision.
class ReferencePropagator final : public Propagator {
 public:
  std::string device_description() const override { return "cpu reference"; }

  PropagationStats solve(const Canvas& canvas, const std::vector<Vec3>& seeds,
                         VoronoiField& field) override {
    validate_seeds(canvas, seeds);
    ReferenceSolver& solver = solver_for(canvas);
    const PropagationStats stats = solver.solve(canvas, seeds, last_);
    export_field(field);
    return stats;
  }

  PropagationStats insert(const Canvas& canvas, const std::vector<Vec3>& seeds,
                          std::size_t first_new, VoronoiField& field) override {
    validate_seeds(canvas, seeds);
    if (field.distance.size() != canvas.slot_count() || field.label.size() != canvas.slot_count())
      throw Error("insert: the field does not match the canvas (slot counts differ)");
    ReferenceSolver& solver = solver_for(canvas);
    if (!is_last_output(field)) import_field(field);
    const PropagationStats stats = solver.insert(canvas, seeds, first_new, last_);
    export_field(field);
    return stats;
  }

 private:
  ReferenceSolver& solver_for(const Canvas& canvas) {
    const uint64_t id = fingerprint(canvas);
    if (!solver_ || id != canvas_id_) {
      solver_.reset();  // free the old stencils before building new ones
      solver_ = std::make_unique<ReferenceSolver>(canvas);
      canvas_id_ = id;
      last_ = {};
    }
    return *solver_;
  }

  void export_field(VoronoiField& field) const {
    field.distance.resize(last_.distance.size());
    for (std::size_t s = 0; s < last_.distance.size(); ++s)
      field.distance[s] = static_cast<float>(last_.distance[s]);
    field.label = last_.label;
  }

  bool is_last_output(const VoronoiField& field) const {
    if (last_.distance.size() != field.distance.size() || last_.label != field.label) return false;
    for (std::size_t s = 0; s < field.distance.size(); ++s)
      if (static_cast<float>(last_.distance[s]) != field.distance[s]) return false;
    return true;
  }

  void import_field(const VoronoiField& field) {
    last_.distance.assign(field.distance.begin(), field.distance.end());
    last_.label = field.label;
  }

  std::unique_ptr<ReferenceSolver> solver_;
  uint64_t canvas_id_ = 0;
  ExactField last_;
};

}  // namespace

}  // namespace rvor::detail

namespace rvor {

std::unique_ptr<Propagator> make_reference_propagator() {
  return std::make_unique<detail::ReferencePropagator>();
}

}  // namespace rvor
