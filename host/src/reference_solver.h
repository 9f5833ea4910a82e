#pragma once
// The sequential CPU reference of docs/scheme.md in double precision (private to rvor_solver; the
// solver tests use it directly to compare fields at full precision). The public entry point is
// make_reference_propagator() in rvor/propagation.h, which wraps this class.
#include <array>
#include <cstdint>
#include <limits>
#include <optional>
#include <vector>

#include "rvor/canvas.h"
#include "rvor/nearest_seeds.h"
#include "rvor/propagation.h"
#include "rvor/seed_blocks.h"

namespace rvor::detail {

// Per canvas slot, like VoronoiField but in double: +inf / -1 where unreached or inactive.
struct ExactField {
  std::vector<double> distance;
  std::vector<int32_t> label;
};

// Stencil of one active voxel, with the offsets stored as the kernels store them (int8).
struct VoxelStencil {
  int8_t size = 0;
  int8_t offset[6][3] = {};
  double weight[6] = {};
  Mat3 D = Mat3::Identity();  // the voxel's dual metric G^-1, for the factorization test
};

class ReferenceSolver {
 public:
  // Precomputes, once per canvas, the Selling stencil of every active voxel, its stencil
  // neighbours and the reverse stencil graph (who has me in their stencil), as CSR.
  explicit ReferenceSolver(const Canvas& canvas);
  // Bytes a solver of this canvas and a solve with it allocate at their peak, estimated: per slot
  // its state, frozen flag, reverse-graph offset, time stamps and the fields (double inside, float
  // outside); per active voxel its reverse-graph entries and four queue entries (the queue keeps
  // stale ones); per distinct tensor a stencil, 144 B, one per active voxel where tensors are
  // stored per slot. 305 B per voxel in 3D then, against a peak of 245 B printed by
  // `build/bin/test_solver --gtest_filter='ReferenceMemory*'` (2000 seeds at 64^3); 161 B for a
  // uniform metric, against 74 B there. (The whole run's 261 B and 80 B per voxel of
  // docs/measurements/peak_bytes_per_voxel.sh with --device cpu count the canvas and the outputs
  // too.)
  static double estimated_bytes(const Canvas& canvas);

  // `canvas` must be the one given to the constructor. Seed i gets label i.
  PropagationStats solve(const Canvas& canvas, const std::vector<Vec3>& seeds, ExactField& field);
  // Adds seeds[first_new..] to `field`, solved for seeds[0..first_new).
  PropagationStats insert(const Canvas& canvas, const std::vector<Vec3>& seeds,
                          std::size_t first_new, ExactField& field);
  // Stops the solves at the first queue entry above `limit` (the queue runs in value order, so
  // values up to the limit are final wherever the update is causal): values above it are then
  // only upper bounds. For fields needed in a bounded ball only (rvor/local_fields.h). Default
  // +inf: solve everything.
  void set_distance_limit(double limit) { distance_limit_ = limit; }
  // Solves under a uniform diagonal metric start the voxels that exact_start_reach
  // (rvor/nearest_seeds.h) allows at their nearest seed's u0 and evaluate each voxel once, in
  // increasing order, before the queue runs (docs/scheme.md, "Initialisation"). Off by default;
  // ignored under a distance limit, whose unsolved values must stay upper bounds.
  void set_exact_start(bool on) { exact_start_ = on; }
  // After a solve without a distance limit: how many voxels one more evaluation of every voxel
  // would change (0 at the fixed point u = T(u) the solve must reach). For the tests of the
  // evaluations the solves skip; the field is left as it is. A single-seed solve's kept terms are
  // gone by then: its voxels are evaluated as any solve's, which gives the same values bit for bit.
  // Throws rvor::Error before the first solve.
  std::size_t unsettled_voxels();
  // Whether single-seed solves keep each voxel's neighbours and corrections (SingleSourceTerms);
  // on by default. The same values bit for bit either way: off is for the tests that check it.
  void keep_single_source_terms(bool on) { keep_single_source_terms_ = on; }

 private:
  struct Seed {
    Vec3 position;
    Mat3 G;  // metric of the voxel containing the seed
    Mat3 F;  // F_s = G_s^{1/2}, for the factorization test
  };
  struct QueueEntry {
    double value;
    int32_t voxel;
    bool operator>(const QueueEntry& other) const { return value > other.value; }
  };

  void compute_stencils(const Canvas& canvas);
  const VoxelStencil& stencil_of(int32_t slot) const { return stencils_[state_[slot].stencil]; }
  void compute_reverse_graph();

  void load_seeds(const Canvas& canvas, const std::vector<Vec3>& seeds);
  void load_field(const ExactField& field);
  void store_field(ExactField& field) const;
  void initialise_seed_blocks(const Canvas& canvas, std::size_t first_seed,
                              const std::vector<SeedClaim>& claims);
  // `from_infinity`: the field holds +inf everywhere (solve(), not insert()).
  PropagationStats propagate(const Canvas& canvas, const std::vector<Vec3>& seeds,
                             std::size_t first_new, ExactField& field, bool exact_start,
                             bool from_infinity);
  void start_at_nearest_seeds(const Canvas& canvas, const std::vector<Vec3>& seeds);
  void evaluate_all_once(PropagationStats& stats);
  void run_queue(PropagationStats& stats);

  // The factored source of one label seen from one voxel x: p = x - s, G_s p and u0(x).
  struct SourceFrame {
    const Mat3* G;
    Vec3 Gp;
    double u0_squared;
    double u0;
    double inverse_u0;  // 0 at the seed itself (no correction there)
    double weight;      // of the factorization correction, in [0, 1] (docs/scheme.md, step 2)
    double p_norm2;     // |x - s|^2 (world)
  };
  SourceFrame source_frame(int32_t voxel, int32_t label) const;
  double factorization_weight(const Seed& seed, const Mat3& D) const;
  // h e_t of the voxel's stencil term t, in world units.
  Vec3 stencil_step(int32_t voxel, int term) const;
  double term_factorization_weight(const SourceFrame& frame, const Vec3& step) const;
  // What source factorization adds to the value of a neighbour: it does not depend on the value.
  double correction(const SourceFrame& frame, const Vec3& step, double sign, double weight) const;
  // Recomputes x from its neighbours: the smallest candidate over the labels of its stencil
  // neighbours (ties: smaller label). Returns whether (value, label) changed.
  bool recompute(int32_t x);
  // recompute() with its time stamps (evaluated_at_, changed_at_).
  bool evaluate(int32_t x);
  // Stores a recomputed (value, label) unless it is the voxel's own; returns whether it changed.
  bool store_recomputed(int32_t voxel, double best, int32_t best_label);
  void mark_seed_block(const Canvas& canvas, std::size_t seed, bool assign_values);
  void offer_exact_value(int32_t voxel, int32_t seed, bool was_frozen);
  // `neighbours`: the slots of the voxel's stencil neighbours, entry 2 t + side (recompute).
  double local_solve(int32_t voxel, int32_t label, const int32_t* neighbours) const;
  // local_solve with `corrected(t, side, value)` giving a neighbour's factorized value.
  template <typename Corrected>
  double solve_with(int32_t voxel, int32_t label, const int32_t* neighbours,
                    Corrected&& corrected) const;
  void neighbour_slots(int32_t voxel, int32_t* neighbours) const;

  // Single-source solves (the dual's local fields) evaluate each voxel about 11 times, always for
  // the one seed: the stencil neighbours' slots and what the factorization adds to their values
  // are computed at a voxel's first evaluation and kept. Bit for bit the values of local_solve.
  struct SingleSourceTerms {
    // Left unset (read once computed): a crop's table is 144 bytes per slot, zeroed for nothing.
    SingleSourceTerms() {}  // NOLINT(modernize-use-equals-default): = default would zero it
    int32_t neighbours[12];
    double correction[12];
    double least_correction;  // the least of them, at most 0
  };
  bool recompute_single_source(int32_t voxel);
  // Whether recomputing x cannot change it, in a single-source solve, when every neighbour
  // changed since x's last evaluation now holds at least `lowest` (its definition says why).
  bool settled_below(int32_t x, double lowest) const;
  const SingleSourceTerms& single_source_terms(int32_t voxel);
  // Slots up to which a single-source solve keeps them (144 bytes per slot).
  static constexpr std::size_t kMostSingleSourceSlots = std::size_t{1} << 20;
  // Voxel index and world position of a slot, and the slot of a stencil neighbour, by arithmetic
  // on the brick layout: no per-voxel memory access (the run time is dominated by cache misses).
  VoxelIndex index_of(int32_t slot) const {
    const VoxelIndex& o = brick_origins_[static_cast<uint32_t>(slot) >> brick_shift_];
    const int local = static_cast<int>(static_cast<uint32_t>(slot) & ((1u << brick_shift_) - 1));
    return {o.i + (local & 7), o.j + ((local >> 3) & 7), o.k + (local >> 6)};
  }
  Vec3 position_of(int32_t slot) const {
    const VoxelIndex x = index_of(slot);
    return origin_ + h_ * Vec3(x.i, x.j, x.k);
  }
  // u0 of seed s at x: |x - s| in the seed's metric.
  double seed_distance(const Vec3& x, int32_t s) const {
    return metric_length(seeds_[s].G, x - seeds_[s].position);
  }
  // Slot of x + sign * e; -1 outside the canvas or inactive (like Canvas::slot_of).
  int32_t neighbour_slot(const VoxelIndex& x, const int8_t* e, int sign) const {
    const int i = x.i + sign * e[0], j = x.j + sign * e[1], k = x.k + sign * e[2];
    if (i < 0 || j < 0 || k < 0 || i >= dims_[0] || j >= dims_[1] || k >= dims_[2]) return -1;
    const int brick_k = dimension_ == 3 ? k >> 3 : 0;
    const int32_t brick =
        brick_table_[(i >> 3) + brick_grid_dims_[0] * ((j >> 3) + brick_grid_dims_[1] * brick_k)];
    if (brick < 0) return -1;
    const int local = (i & 7) + 8 * ((j & 7) + 8 * (dimension_ == 3 ? k & 7 : 0));
    const int32_t slot = (brick << brick_shift_) + local;
    return state_[slot].stencil >= 0 ? slot : -1;
  }

  // Canvas geometry. Voxels are identified by their canvas slot (int32).
  int dimension_ = 3;
  double h_ = 0;
  Vec3 origin_ = Vec3::Zero();
  std::size_t slot_count_ = 0;
  int brick_shift_ = 9;  // log2 of the brick volume (8^3 or 8^2 slots)
  std::vector<VoxelIndex> brick_origins_;
  std::array<int, 3> dims_{};
  std::array<int, 3> brick_grid_dims_{};
  std::vector<int32_t> brick_table_;

  std::vector<VoxelStencil> stencils_;  // distinct stencils (uniform regions share one)
  // Reverse stencil graph as CSR: for voxel y, the entries 12 x + 2 t + side (side 0: y = x + e_t,
  // side 1: y = x - e_t) of the voxels x that have y in their stencil.
  std::vector<uint32_t> reverse_begin_;
  std::vector<uint32_t> reverse_;

  // Per slot: the state of the current solve, and the slot's stencil (index into stencils_, -1
  // when inactive). Side by side because the run time is dominated by scattered memory reads of
  // neighbours: one cache line gives all that a visit of a voxel needs.
  struct VoxelState {
    double value;
    int32_t label;
    int32_t stencil;
  };
  std::vector<Seed> seeds_;
  std::vector<VoxelState> state_;
  // 1 for voxels of a seed's initialisation block: their exact values are boundary data.
  std::vector<uint8_t> frozen_;
  std::vector<QueueEntry> queue_;  // binary min-heap (std::push_heap with greater)
  // Per slot, when it was last evaluated and last changed, on a clock that ticks at every
  // evaluation (0: before the solve's first, where the seeds' values and a loaded field are set): a
  // voxel evaluated after a neighbour's last change has seen it.
  std::vector<uint32_t> evaluated_at_, changed_at_;
  uint32_t clock_ = 0;
  // SingleSourceTerms per slot, and whether computed, while a single-source solve runs.
  std::vector<SingleSourceTerms> single_source_terms_;
  std::vector<uint8_t> single_source_ready_;
  double distance_limit_ = std::numeric_limits<double>::infinity();
  bool exact_start_ = false;
  bool keep_single_source_terms_ = true;
  bool skip_settled_ = false;  // settled_below applies to the current solve
  // Where the exact start applies on the canvas (rvor/nearest_seeds.h), decided at the first
  // solve that wants it: the test can flood-fill the canvas.
  std::optional<ExactStartReach> exact_start_reach_;
};

}  // namespace rvor::detail
