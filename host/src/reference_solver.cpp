// The sequential CPU reference solver of docs/scheme.md: double precision, label-correcting
// worklist in value order on the reverse stencil graph. It is the ground truth the OpenCL kernels
// are checked against, so it favours clarity; the inner loop (local_solve) is allocation-free.
#include "reference_solver.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>
#include <functional>
#include <limits>
#include <memory>
#include <optional>

#include <Eigen/LU>

#include "canvas_identity.h"
#include "one_call_at_a_time.h"
#include "rvor/error.h"
#include "rvor/memory_budget.h"
#include "rvor/nearest_seeds.h"
#include "rvor/seeds.h"
#include "rvor/selling.h"

namespace rvor::detail {

namespace {

constexpr double kInfinity = std::numeric_limits<double>::infinity();
// A recomputed value counts as a change only beyond this relative amount (or with another label):
// rounding noise cannot then keep two voxels re-evaluating each other forever.
constexpr double kRelativeChange = 1e-12;
// Guard against a scheme that does not settle: more recomputations than this per voxel is a bug.
constexpr uint64_t kMaxPopsPerVoxel = 1000;

// D = G^-1 in double from the float metric; in 2D only the 2x2 block is meaningful.
Mat3 dual_metric(const Canvas& canvas, std::size_t slot) {
  const Mat3 G = canvas.metric_at(slot);
  if (canvas.dimension == 3) return G.inverse();
  Mat3 D = Mat3::Identity();
  D.topLeftCorner<2, 2>() = G.topLeftCorner<2, 2>().inverse();
  return D;
}

VoxelStencil to_voxel_stencil(const SellingStencil& selling, const Mat3& D) {
  VoxelStencil stencil;
  stencil.D = D;
  stencil.size = static_cast<int8_t>(selling.size);
  for (int t = 0; t < selling.size; ++t) {
    stencil.weight[t] = selling.weight[t];
    for (int a = 0; a < 3; ++a) {
      // Within int8: canvas_selling_decomposition refuses longer offsets.
      stencil.offset[t][a] = static_cast<int8_t>(selling.offset[t][a]);
    }
  }
  return stencil;
}

// Solves sum_k rho_k max(0, t - w_k)^2 = h^2 for its largest root, w sorted ascending (n >= 1).
// Solved for tau = t - w_0 so that large distances do not cancel catastrophically, with the
// discriminant b^2 - a c written as a h^2 - sum_{i<j} rho_i rho_j (w_i - w_j)^2 (as the kernels'
// solve_sorted): b^2 and a c cancel when a term of tiny weight lies far below the others (strong
// anisotropy nearly along an axis), and their rounding, 1e-11 of t at anisotropy 1000, kept two
// voxels re-evaluating each other above the 1e-12 change threshold forever.
double solve_sorted_quadratic(const double* w, const double* rho, int n, double h) {
  double a = 0, b = 0, pair_sum = 0;
  double tau = 0;
  for (int k = 0; k < n; ++k) {
    const double delta = w[k] - w[0];
    for (int i = 0; i < k; ++i) {
      const double d = w[i] - w[k];
      pair_sum += rho[i] * rho[k] * d * d;
    }
    a += rho[k];
    b += rho[k] * delta;
    tau = (b + std::sqrt(std::max(0.0, a * h * h - pair_sum))) / a;
    if (k + 1 == n || w[0] + tau <= w[k + 1]) break;
  }
  return w[0] + tau;
}

// Source factorization corrects for the curvature of the front of u0 = |F_s (x - s)|. It is only
// consistent where the seed's metric still describes the local one: far from a seed in a strongly
// varying field (swirl) the correction is not small, the update stops being causal and iterations
// do not settle (measured: swirl, 128^2, 1 seed: 30 s and no convergence with the correction
// everywhere; 0.03 s without). So it is weighted by how well |F_s D(x) F_s - I|_F (D = G^-1, which
// the kernels rebuild from their stored stencil) stays small: fully up to 0.2, not at all from this
// bound on, linearly (in the squared norm) between, so that float and double evaluations of the
// test near the bound give nearly the same value. Uniform metrics are fully factored, so the scheme
// is exact for them. The bound trades accuracy for robustness: 0.5 still fails to settle for
// unidimensional_shock (256^2, 100 seeds); 0.3 settles there in 0.3 s.
constexpr double kFactorizationMismatchBound = 0.3, kFactorizationFullBelow = 0.2;

// The correction also extrapolates u0 linearly from x over the offset, which fails when the offset
// is about as long as x's distance to the seed (y may lie beyond the seed): strongly anisotropic
// stencils near a seed then make the update non-causal, and iterations crawl (measured: uniform
// anisotropy 25-100 nearly along an axis, 127^2: no convergence after 1000 recomputations per
// voxel; docs/scheme.md, "Local update", step 2). So the correction of a term is weighted by
// |p|^2 / |e|^2 (p = x - s, e the offset; any common unit): 0 up to 1, 1 from 2.25 on, linear
// between. Offsets of length 1 are always fully corrected: voxels outside the seed blocks are at
// least 2.5 voxels from every seed.
double offset_factorization_weight(double p_norm2, double e_norm2) {
  return std::clamp((p_norm2 - e_norm2) / (1.25 * e_norm2), 0.0, 1.0);
}

}  // namespace

double ReferenceSolver::factorization_weight(const Seed& seed, const Mat3& D) const {
  const double mismatch2 = (seed.F * D * seed.F - Mat3::Identity()).squaredNorm();
  const double none = kFactorizationMismatchBound * kFactorizationMismatchBound;
  const double full = kFactorizationFullBelow * kFactorizationFullBelow;
  return std::clamp((none - mismatch2) / (none - full), 0.0, 1.0);
}

ReferenceSolver::ReferenceSolver(const Canvas& canvas)
    : dimension_(canvas.dimension),
      h_(canvas.voxel_size),
      origin_(canvas.origin),
      slot_count_(canvas.slot_count()),
      brick_shift_(canvas.dimension == 3 ? 9 : 6),
      brick_origins_(canvas.brick_origins),
      dims_(canvas.dims),
      brick_grid_dims_(canvas.brick_grid_dims),
      brick_table_(canvas.brick_table) {
  // Slots are int32 and reverse-graph entries (12 per slot) uint32.
  if (slot_count_ >= std::numeric_limits<uint32_t>::max() / 12)
    throw Error("reference solver: canvas has too many slots for 32-bit voxel ids");
  if (canvas.brick_volume() != (1 << brick_shift_))
    throw Error("reference solver: unexpected canvas brick size");
  compute_stencils(canvas);
  compute_reverse_graph();
}

double ReferenceSolver::estimated_bytes(const Canvas& canvas) {
  const double slots = static_cast<double>(canvas.slot_count());
  const double active = static_cast<double>(canvas.active_voxel_count);
  const double per_slot = sizeof(VoxelState) + 1 + sizeof(uint32_t) + 2 * sizeof(uint32_t) +
                          sizeof(double) + sizeof(int32_t) + sizeof(float) + sizeof(int32_t);
  const double reverse_entries = canvas.dimension == 3 ? 12 : 6;
  // The queue keeps stale entries and its capacity (three per voxel), and evaluate_all_once's
  // order one more.
  const double per_active = reverse_entries * sizeof(uint32_t) + 4 * sizeof(QueueEntry);
  const double stencils = canvas.uniform_metric() ? 1 : active;
  return slots * per_slot + active * per_active + stencils * sizeof(VoxelStencil);
}

void ReferenceSolver::compute_stencils(const Canvas& canvas) {
  state_.assign(slot_count_, {kInfinity, -1, -1});
  stencils_.clear();
  // At most one per active voxel, reserved so that growing never holds two copies (pages not
  // written are not taken).
  stencils_.reserve(canvas.uniform_metric() ? 1 : canvas.active_voxel_count);
  const float* previous_metric = nullptr;
  for (std::size_t slot = 0; slot < slot_count_; ++slot) {
    if (!canvas.active[slot]) continue;
    const float* metric = canvas.metric_of(slot);
    // Uniform regions repeat the same tensor: share the previous stencil instead of recomputing.
    if (!previous_metric || std::memcmp(metric, previous_metric, 6 * sizeof(float)) != 0) {
      const Mat3 D = dual_metric(canvas, slot);
      stencils_.push_back(to_voxel_stencil(canvas_selling_decomposition(canvas, slot, D), D));
    }
    state_[slot].stencil = static_cast<int32_t>(stencils_.size() - 1);
    previous_metric = metric;
  }
}

void ReferenceSolver::compute_reverse_graph() {
  // Calls `visit(y, entry)` for every stencil neighbour y of every active voxel.
  auto for_each_stencil_entry = [this](auto&& visit) {
    for (std::size_t slot = 0; slot < slot_count_; ++slot) {
      if (state_[slot].stencil < 0) continue;
      const VoxelIndex x = index_of(static_cast<int32_t>(slot));
      const VoxelStencil& stencil = stencil_of(static_cast<int32_t>(slot));
      for (int t = 0; t < stencil.size; ++t)
        for (int side = 0; side < 2; ++side) {
          const int32_t y = neighbour_slot(x, stencil.offset[t], side == 0 ? 1 : -1);
          if (y >= 0) visit(y, static_cast<uint32_t>(12 * slot + 2 * t + side));
        }
    }
  };
  reverse_begin_.assign(slot_count_ + 1, 0);
  for_each_stencil_entry([this](int32_t y, uint32_t) { ++reverse_begin_[y + 1]; });
  for (std::size_t v = 0; v < slot_count_; ++v) reverse_begin_[v + 1] += reverse_begin_[v];
  reverse_.resize(reverse_begin_[slot_count_]);
  std::vector<uint32_t> fill(reverse_begin_.begin(), reverse_begin_.end() - 1);
  for_each_stencil_entry([this, &fill](int32_t y, uint32_t entry) { reverse_[fill[y]++] = entry; });
}

PropagationStats ReferenceSolver::solve(const Canvas& canvas, const std::vector<Vec3>& seeds,
                                        ExactField& field) {
  // In place: a field of the last solve is reused, not held beside a new one.
  field.distance.assign(slot_count_, kInfinity);
  field.label.assign(slot_count_, -1);
  const bool wanted = exact_start_ && !seeds.empty() && distance_limit_ == kInfinity;
  if (wanted && !exact_start_reach_) exact_start_reach_ = exact_start_reach(canvas);
  const bool exact_start = wanted && *exact_start_reach_ != ExactStartReach::none;
  return propagate(canvas, seeds, 0, field, exact_start, /*from_infinity=*/true);
}

PropagationStats ReferenceSolver::insert(const Canvas& canvas, const std::vector<Vec3>& seeds,
                                         std::size_t first_new, ExactField& field) {
  return propagate(canvas, seeds, first_new, field, false, /*from_infinity=*/false);
}

PropagationStats ReferenceSolver::propagate(const Canvas& canvas, const std::vector<Vec3>& seeds,
                                            std::size_t first_new, ExactField& field,
                                            bool exact_start, bool from_infinity) {
  const auto start = std::chrono::steady_clock::now();
  if (canvas.slot_count() != slot_count_ || field.distance.size() != slot_count_ ||
      field.label.size() != slot_count_)
    throw Error("reference solver: the field does not match the canvas (slot counts differ)");
  if (first_new > seeds.size())
    throw Error("reference solver: first new seed index is past the end of the seed list");
  validate_seeds(canvas, seeds);
  load_seeds(canvas, seeds);
  load_field(field);
  const bool single_source =
      keep_single_source_terms_ && seeds.size() == 1 && slot_count_ <= kMostSingleSourceSlots;
  single_source_terms_.resize(single_source ? slot_count_ : 0);
  single_source_ready_.assign(single_source ? slot_count_ : 0, 0);
  // From +inf everywhere but the seed block, every evaluation's neighbours hold at most what they
  // held at the one before, so values only decrease (the update is monotone): settled_below needs
  // that. A field loaded for insert(), or the exact start's values, may still rise.
  skip_settled_ = single_source && !exact_start && from_infinity;
  evaluated_at_.assign(slot_count_, 0);
  changed_at_.assign(slot_count_, 0);
  clock_ = 0;
  if (exact_start) start_at_nearest_seeds(canvas, seeds);
  PropagationStats stats;
  stats.exact_start = exact_start;
  initialise_seed_blocks(canvas, first_new, foreign_seed_claims(canvas, seeds, first_new));
  if (exact_start) evaluate_all_once(stats);
  run_queue(stats);
  // A solver kept for later solves keeps no per-slot terms (144 B per slot) between them.
  std::vector<SingleSourceTerms>().swap(single_source_terms_);
  std::vector<uint8_t>().swap(single_source_ready_);
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
    const Mat3 G = canvas.metric_at(static_cast<std::size_t>(slot));
    seeds_.push_back({p, G, metric_sqrt(G)});
  }
}

// Inactive slots keep (+inf, -1) whatever the field says: they take no part in the solve.
void ReferenceSolver::load_field(const ExactField& field) {
  for (std::size_t slot = 0; slot < slot_count_; ++slot) {
    VoxelState& state = state_[slot];
    const bool active = state.stencil >= 0;
    state.value = active ? field.distance[slot] : kInfinity;
    state.label = active ? field.label[slot] : -1;
  }
}

void ReferenceSolver::store_field(ExactField& field) const {
  for (std::size_t slot = 0; slot < slot_count_; ++slot) {
    field.distance[slot] = state_[slot].value;
    field.label[slot] = state_[slot].label;
  }
}

// Exact values u0_s(x) = |F_s (x - s)| in the (2r+1)^d block around each seed's voxel. Block voxels
// are frozen (boundary data, never recomputed) and hold the smallest exact value of all seeds
// (rvor/seed_blocks.h: the seeds whose block contains them, then the claims of the others, which
// replace what the blocks wrote).
// Seeds before `first_seed` only re-mark their blocks as frozen (their values are in the field
// already); new seeds and claims assign values and queue the voxels they changed.
void ReferenceSolver::initialise_seed_blocks(const Canvas& canvas, std::size_t first_seed,
                                             const std::vector<SeedClaim>& claims) {
  queue_.clear();
  frozen_.assign(slot_count_, 0);
  for (std::size_t s = 0; s < first_seed; ++s) mark_seed_block(canvas, s, false);
  for (std::size_t s = first_seed; s < seeds_.size(); ++s) mark_seed_block(canvas, s, true);
  for (const SeedClaim& claim : claims)  // the seed chosen once for every engine: it replaces
    offer_exact_value(static_cast<int32_t>(canvas.slot_of(claim.voxel)), claim.label, false);
}

void ReferenceSolver::mark_seed_block(const Canvas& canvas, std::size_t s, bool assign_values) {
  const VoxelIndex centre = canvas.voxel_containing(seeds_[s].position);
  for_each_seed_block_voxel(centre, dimension_, [&](const VoxelIndex& x) {
    const int64_t slot = canvas.slot_of(x);
    if (slot < 0) return;
    const int32_t voxel = static_cast<int32_t>(slot);
    const bool was_frozen = frozen_[voxel];
    frozen_[voxel] = 1;
    if (assign_values) offer_exact_value(voxel, static_cast<int32_t>(s), was_frozen);
  });
}

// A voxel that was not boundary data (or is claimed) takes the exact value even if its old value
// was smaller: solving with all seeds at once would have frozen it to that value too. Boundary data
// keeps the smallest value (ties: smaller label).
void ReferenceSolver::offer_exact_value(int32_t voxel, int32_t s, bool was_frozen) {
  const double u0 = seed_distance(position_of(voxel), s);
  VoxelState& state = state_[voxel];
  const bool wins = !was_frozen || u0 < state.value || (u0 == state.value && s < state.label);
  if (!wins || (u0 == state.value && s == state.label)) return;
  state.value = u0;
  state.label = s;
  queue_.push_back({u0, voxel});
  std::push_heap(queue_.begin(), queue_.end(), std::greater<QueueEntry>());
}

// The exact start (docs/scheme.md, "Initialisation"): every active voxel at the least u0 over the
// seeds (ties: the smaller label), from its brick's candidates, where its quarter brick sees that
// seed; elsewhere it stays at +inf. Not boundary data: the seed blocks overwrite their voxels next,
// and evaluate_all_once checks every other one.
void ReferenceSolver::start_at_nearest_seeds(const Canvas& canvas, const std::vector<Vec3>& seeds) {
  const BrickSeedLists nearest = exact_start_lists(canvas, seeds, *exact_start_reach_);
  const std::size_t brick_volume = std::size_t{1} << brick_shift_;
  for (std::size_t slot = 0; slot < slot_count_; ++slot) {
    VoxelState& state = state_[slot];
    if (state.stencil < 0) continue;
    const std::size_t brick = slot / brick_volume;
    const Vec3 x = position_of(static_cast<int32_t>(slot));
    double least = kInfinity;
    std::uint32_t entry = nearest.begin[brick + 1];  // of the nearest seed; none yet
    for (std::uint32_t c = nearest.begin[brick]; c < nearest.begin[brick + 1]; ++c) {
      const double u0 = seed_distance(x, nearest.seeds[c]);
      if (u0 < least) least = u0, entry = c;  // ascending labels: a tie keeps the smaller
    }
    if (entry == nearest.begin[brick + 1]) continue;
    const VoxelIndex v = index_of(static_cast<int32_t>(slot));
    const VoxelIndex& o = canvas.brick_origins[brick];
    const int quarter = quarter_of(v.i - o.i, v.j - o.j, v.k - o.k);
    if ((nearest.seen[entry] >> quarter & 1) && least < state.value)
      state.value = least, state.label = nearest.seeds[entry];
  }
}

// After the exact start: each voxel that is not boundary data is evaluated once, in increasing
// order of its starting value, and those that change are queued like any change. Most are fixed
// points already; the voxels next to bisectors, where a neighbour upwind carries another label,
// are not.
void ReferenceSolver::evaluate_all_once(PropagationStats& stats) {
  std::vector<QueueEntry> order;
  for (std::size_t slot = 0; slot < slot_count_; ++slot)
    if (state_[slot].stencil >= 0 && !frozen_[slot])
      order.push_back({state_[slot].value, static_cast<int32_t>(slot)});
  std::sort(order.begin(), order.end(),
            [](const QueueEntry& a, const QueueEntry& b) { return b > a; });
  for (const QueueEntry& entry : order) {
    ++stats.voxel_updates;
    if (evaluate(entry.voxel)) {
      queue_.push_back({state_[entry.voxel].value, entry.voxel});
      std::push_heap(queue_.begin(), queue_.end(), std::greater<QueueEntry>());
    }
  }
}

// Small helpers of the inner loop, defined first so that they are inlined.
inline ReferenceSolver::SourceFrame ReferenceSolver::source_frame(int32_t voxel,
                                                                  int32_t label) const {
  const Seed& seed = seeds_[label];
  const Vec3 p = position_of(voxel) - seed.position;
  SourceFrame frame{&seed.G, seed.G * p, 0, 0, 0, 0, p.squaredNorm()};
  frame.u0_squared = std::max(0.0, p.dot(frame.Gp));
  frame.u0 = std::sqrt(frame.u0_squared);
  frame.weight = frame.u0 > 0 ? factorization_weight(seed, stencil_of(voxel).D) : 0;
  frame.inverse_u0 = frame.weight > 0 ? 1 / frame.u0 : 0;
  return frame;
}

inline Vec3 ReferenceSolver::stencil_step(int32_t voxel, int term) const {
  const int8_t* e = stencil_of(voxel).offset[term];
  return h_ * Vec3(e[0], e[1], e[2]);
}

// Source factorization of a neighbour value v at y = x + sign * step adds
// u0(x) - u0(y) + <grad u0(x), y - x> (nothing at the seed itself, where u0(x) = 0), with
// `weight`, the frame's times the offset's (term_factorization_weight).
inline double ReferenceSolver::correction(const SourceFrame& frame, const Vec3& step, double sign,
                                          double weight) const {
  if (!(weight > 0)) return 0;
  const double step_dot_Gp = step.dot(frame.Gp);        // h e^T G_s p
  const double step_norm2 = step.dot(*frame.G * step);  // h^2 e^T G_s e
  const double u0_y =
      std::sqrt(std::max(0.0, frame.u0_squared + 2 * sign * step_dot_Gp + step_norm2));
  return weight * (frame.u0 - u0_y + sign * step_dot_Gp * frame.inverse_u0);
}

// The weight of the correction for a term with this step: the frame's times the offset's
// (offset_factorization_weight); 0 at the seed itself.
inline double ReferenceSolver::term_factorization_weight(const SourceFrame& frame,
                                                         const Vec3& step) const {
  if (!(frame.inverse_u0 > 0)) return 0;
  return frame.weight * offset_factorization_weight(frame.p_norm2, step.squaredNorm());
}

// Worklist in value order (Dijkstra-like): pop the smallest changed voxel y and recompute every
// voxel that has y in its stencil. Recomputing (rather than only accepting decreases) makes the
// result the fixed point u = T(u) of the scheme whatever the order of updates: when y changes
// label, the voxels that used y's old label lose that support, as they would never have had it in
// a solve from scratch. The kernels iterate the same operator in parallel and reach the same field.
// A voxel evaluated after y's last change has read y's value: evaluating it again for y would
// find what it found then, and a neighbour that changed since is queued and evaluates it when
// popped. That skips about a third of the evaluations (half for a single seed), and the field is
// still a fixed point (the tests check that one more evaluation changes no voxel). A
// single-source solve also skips the voxels that cannot change (settled_below), about half of the
// rest.
void ReferenceSolver::run_queue(PropagationStats& stats) {
  const uint64_t max_pops = kMaxPopsPerVoxel * static_cast<uint64_t>(slot_count_ + 1);
  while (!queue_.empty()) {
    std::pop_heap(queue_.begin(), queue_.end(), std::greater<QueueEntry>());
    const QueueEntry entry = queue_.back();
    queue_.pop_back();
    if (entry.value != state_[entry.voxel].value) continue;  // stale: the voxel changed since
    if (entry.value > distance_limit_) {  // later pops are larger, as are the values they give
      queue_.clear();
      break;
    }
    if (++stats.iterations > max_pops)
      throw Error("reference solver did not converge (a voxel was recomputed over " +
                  std::to_string(kMaxPopsPerVoxel) + " times on average)");
    // Every queued value is at least y's, but for those this loop queues.
    double lowest = entry.value;
    const uint32_t y_changed = changed_at_[entry.voxel];
    for (uint32_t r = reverse_begin_[entry.voxel]; r < reverse_begin_[entry.voxel + 1]; ++r) {
      const int32_t x = static_cast<int32_t>(reverse_[r] / 12);
      if (frozen_[x] || evaluated_at_[x] > y_changed || settled_below(x, lowest)) continue;
      ++stats.voxel_updates;
      if (evaluate(x)) {
        lowest = std::min(lowest, state_[x].value);
        queue_.push_back({state_[x].value, x});
        std::push_heap(queue_.begin(), queue_.end(), std::greater<QueueEntry>());
      }
    }
  }
}

// In a solve whose values only decrease (skip_settled_), a neighbour of x changed since x's last
// evaluation is either still queued, so it holds at least `lowest` now and held more before, or it
// was popped when this test held for it. Either way x's term of it is at least the value tested
// here (lowest + least_correction, at most the corrected neighbour), and when that is not below
// x's value, every changed term lies above the root x's last evaluation found, before and after:
// the root's terms and arithmetic, and its floor (the least raw neighbour value), are those of that
// evaluation, so it would find the same value again, not a change. The margin covers a last
// evaluation that found a value within kRelativeChange of x's and kept x's. Checked in the solver
// tests: the same fields bit for bit as the same solve without this test.
bool ReferenceSolver::settled_below(int32_t x, double lowest) const {
  if (!skip_settled_ || !single_source_ready_[static_cast<std::size_t>(x)]) return false;
  const double least = lowest + single_source_terms_[static_cast<std::size_t>(x)].least_correction;
  return least >= state_[x].value * (1 + 4 * kRelativeChange);
}

void ReferenceSolver::neighbour_slots(int32_t voxel, int32_t* neighbours) const {
  const VoxelStencil& stencil = stencil_of(voxel);
  const VoxelIndex x = index_of(voxel);
  for (int t = 0; t < stencil.size; ++t)
    for (int side = 0; side < 2; ++side)
      neighbours[2 * t + side] = neighbour_slot(x, stencil.offset[t], side == 0 ? 1 : -1);
}

std::size_t ReferenceSolver::unsettled_voxels() {
  if (frozen_.size() != slot_count_)
    throw Error("reference solver: unsettled_voxels() needs a solve first");
  std::size_t unsettled = 0;
  for (std::size_t slot = 0; slot < slot_count_; ++slot) {
    if (state_[slot].stencil < 0 || frozen_[slot]) continue;
    const VoxelState solved = state_[slot];
    if (recompute(static_cast<int32_t>(slot))) ++unsettled;
    state_[slot] = solved;
  }
  return unsettled;
}

bool ReferenceSolver::evaluate(int32_t voxel) {
  if (clock_ == std::numeric_limits<uint32_t>::max()) {
    // Every stamp back to 0 then says nothing: no voxel is skipped until evaluated again. Those
    // extra evaluations can move the result's last bits (only past 4.29e9 evaluations in a solve).
    std::fill(evaluated_at_.begin(), evaluated_at_.end(), 0);
    std::fill(changed_at_.begin(), changed_at_.end(), 0);
    clock_ = 0;
  }
  const uint32_t now = ++clock_;
  evaluated_at_[voxel] = now;
  if (!recompute(voxel)) return false;
  changed_at_[voxel] = now;
  return true;
}

bool ReferenceSolver::recompute(int32_t voxel) {
  if (!single_source_ready_.empty()) return recompute_single_source(voxel);
  // Candidate labels: the distinct labels of the stencil neighbours (at most 12).
  int32_t labels[12];
  int label_count = 0;
  // The neighbours' slots, found once for every label's solve (entry 2 t + side, -1: none).
  int32_t neighbours[12];
  neighbour_slots(voxel, neighbours);
  for (int n = 0; n < 2 * stencil_of(voxel).size; ++n) {
    const int32_t y = neighbours[n];
    if (y < 0 || state_[y].label < 0) continue;
    const int32_t label = state_[y].label;
    if (std::find(labels, labels + label_count, label) == labels + label_count)
      labels[label_count++] = label;
  }
  double best = kInfinity;
  int32_t best_label = -1;
  for (int n = 0; n < label_count; ++n) {
    const double t = local_solve(voxel, labels[n], neighbours);
    if (t < best || (t == best && labels[n] < best_label)) best = t, best_label = labels[n];
  }
  return store_recomputed(voxel, best, best_label);
}

bool ReferenceSolver::store_recomputed(int32_t voxel, double best, int32_t best_label) {
  VoxelState& state = state_[voxel];
  if (best_label < 0) best = kInfinity;
  const bool same_label = best_label == state.label;
  const bool same_value = best == state.value || std::abs(best - state.value) <=
                                                     kRelativeChange * std::min(best, state.value);
  if (same_label && same_value) return false;
  state.value = best;
  state.label = best_label;
  return true;
}

const ReferenceSolver::SingleSourceTerms& ReferenceSolver::single_source_terms(int32_t voxel) {
  SingleSourceTerms& terms = single_source_terms_[static_cast<std::size_t>(voxel)];
  if (single_source_ready_[static_cast<std::size_t>(voxel)]) return terms;
  single_source_ready_[static_cast<std::size_t>(voxel)] = 1;
  neighbour_slots(voxel, terms.neighbours);
  const SourceFrame frame = source_frame(voxel, 0);
  for (int t = 0; t < stencil_of(voxel).size; ++t) {
    const Vec3 step = stencil_step(voxel, t);
    const double weight = term_factorization_weight(frame, step);
    for (int side = 0; side < 2; ++side)
      terms.correction[2 * t + side] = correction(frame, step, side == 0 ? 1.0 : -1.0, weight);
  }
  terms.least_correction = 0;
  for (int n = 0; n < 2 * stencil_of(voxel).size; ++n)
    terms.least_correction = std::min(terms.least_correction, terms.correction[n]);
  return terms;
}

bool ReferenceSolver::recompute_single_source(int32_t voxel) {
  const SingleSourceTerms& terms = single_source_terms(voxel);
  const double best = solve_with(
      voxel, 0, terms.neighbours,
      [&terms](int t, int side, double value) { return value + terms.correction[2 * t + side]; });
  return store_recomputed(voxel, best, best < kInfinity ? 0 : -1);  // as recompute's ties do
}

// The candidate value of `voxel` for `label` (docs/scheme.md, "Local update"), +inf if no
// stencil neighbour carries that label.
double ReferenceSolver::local_solve(int32_t voxel, int32_t label, const int32_t* neighbours) const {
  const SourceFrame frame = source_frame(voxel, label);
  // The step and weight of the term last asked for: both sides of a term share them.
  int term = -1;
  Vec3 step = Vec3::Zero();
  double weight = 0;
  return solve_with(voxel, label, neighbours, [&](int t, int side, double value) {
    if (t != term) {
      term = t;
      step = stencil_step(voxel, t);
      weight = term_factorization_weight(frame, step);
    }
    return value + correction(frame, step, side == 0 ? 1.0 : -1.0, weight);
  });
}

template <typename Corrected>
double ReferenceSolver::solve_with(int32_t voxel, int32_t label, const int32_t* neighbours,
                                   Corrected&& corrected) const {
  const VoxelStencil& stencil = stencil_of(voxel);
  double w[6], rho[6];  // corrected neighbour value and weight, sorted by w
  int n = 0;
  double least_raw = kInfinity;  // the candidate's floor (docs/scheme.md, "Local update", 6)
  for (int t = 0; t < stencil.size; ++t) {
    double best = kInfinity;
    for (int side = 0; side < 2; ++side) {
      const int32_t y = neighbours[2 * t + side];
      if (y < 0 || state_[y].label != label) continue;
      least_raw = std::min(least_raw, state_[y].value);
      best = std::min(best, corrected(t, side, state_[y].value));
    }
    if (best == kInfinity) continue;
    // Insertion into the sorted arrays: at most 6 terms.
    int k = n++;
    for (; k > 0 && w[k - 1] > best; --k) {
      w[k] = w[k - 1];
      rho[k] = rho[k - 1];
    }
    w[k] = best;
    rho[k] = stencil.weight[t];
  }
  if (n == 0) return kInfinity;
  return std::max(solve_sorted_quadratic(w, rho, n, h_), least_raw);
}

namespace {

// The public Propagator: float fields outside, double inside. It remembers the double field of
// its last call, so that a chain of insert() calls keeps full precision.
class ReferencePropagator final : public Propagator {
 public:
  explicit ReferencePropagator(bool exact_start) : exact_start_(exact_start) {}
  std::string device_description() const override { return "cpu reference"; }
  void set_memory_budget(std::uint64_t bytes) override { memory_budget_ = bytes; }

  PropagationStats solve(const Canvas& canvas, const std::vector<Vec3>& seeds,
                         VoronoiField& field) override {
    const OneCallAtATime exclusive(busy_, "the CPU reference propagator");
    return naming_out_of_memory("solving on the CPU reference", [&] {
      validate_seeds(canvas, seeds);
      ReferenceSolver& solver = solver_for(canvas);
      const PropagationStats stats = solver.solve(canvas, seeds, last_);
      export_field(field);
      last_seeds_ = seeds;
      return stats;
    });
  }

  PropagationStats insert(const Canvas& canvas, const std::vector<Vec3>& seeds,
                          std::size_t first_new, VoronoiField& field) override {
    const OneCallAtATime exclusive(busy_, "the CPU reference propagator");
    return naming_out_of_memory("inserting seeds on the CPU reference", [&] {
      validate_seeds(canvas, seeds);
      require_first_new(first_new, seeds.size());
      require_insertable_field(canvas, field, first_new, "insert()");
      ReferenceSolver& solver = solver_for(canvas);
      // Its own last field: the seeds it was solved for are known (as the OpenCL engine checks).
      if (is_last_output(field))
        require_solved_for_these_seeds(last_seeds_.size(), unchanged_prefix(seeds), first_new);
      else
        import_field(field);
      const PropagationStats stats = solver.insert(canvas, seeds, first_new, last_);
      export_field(field);
      last_seeds_ = seeds;
      return stats;
    });
  }

 private:
  ReferenceSolver& solver_for(const Canvas& canvas) {
    const std::optional<uint64_t> id = canvas_identity(canvas);
    if (!solver_ || !id || id != canvas_id_) {
      solver_.reset();  // free the old stencils before building new ones
      last_ = {};
      last_seeds_.clear();
      require_memory_for(
          "the CPU reference's solve of " + std::to_string(canvas.active_voxel_count) +
              " active voxels",
          ReferenceSolver::estimated_bytes(canvas), memory_budget_,
          ": use an OpenCL device (--device pocl), which needs about a third of that, or a "
          "coarser --resolution");
      solver_ = std::make_unique<ReferenceSolver>(canvas);
      solver_->set_exact_start(exact_start_);
      canvas_id_ = id;
    }
    return *solver_;
  }

  // How many of `seeds` lead as last_seeds_ does.
  std::size_t unchanged_prefix(const std::vector<Vec3>& seeds) const {
    const std::size_t most = std::min(last_seeds_.size(), seeds.size());
    return static_cast<std::size_t>(
        std::mismatch(last_seeds_.begin(), last_seeds_.begin() + static_cast<std::ptrdiff_t>(most),
                      seeds.begin())
            .first -
        last_seeds_.begin());
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

  bool exact_start_;
  std::uint64_t memory_budget_ = 0;
  std::atomic<bool> busy_{false};  // OneCallAtATime
  std::unique_ptr<ReferenceSolver> solver_;
  std::optional<uint64_t> canvas_id_;
  ExactField last_;
  std::vector<Vec3> last_seeds_;  // what last_ was solved for
};

}  // namespace

}  // namespace rvor::detail

namespace rvor {

std::unique_ptr<Propagator> make_reference_propagator(bool exact_start) {
  return std::make_unique<detail::ReferencePropagator>(exact_start);
}

}  // namespace rvor
