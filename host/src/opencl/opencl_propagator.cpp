// The OpenCL propagation engine: uploads the canvas once, then runs block Fast Iterative Method
// rounds on the device until no brick is active (see kernels/propagation.cl).
#include "rvor/opencl_propagator.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <future>
#include <limits>
#include <memory>
#include <new>
#include <optional>
#include <utility>

#include "../canvas_identity.h"
#include "../one_call_at_a_time.h"
#include "device_canvas.h"
#include "field_transfer.h"
#include "front_step.h"
#include "opencl_runtime.h"
#include "rvor/embedded_kernels.h"
#include "rvor/error.h"
#include "rvor/nearest_seeds.h"
#include "rvor/seed_blocks.h"
#include "rvor/seeds.h"

namespace rvor {

namespace {

constexpr std::size_t kSeedRecord = 16;  // floats, see kernels/eikonal_scheme.clh
constexpr std::size_t kBookkeepingGroup = 64;
constexpr int kLanes = 8;  // bricks per work-item of relax_brick_lanes (kernels/brick_lanes.cl)
// A scheme that does not settle is a bug; stop with an error rather than loop forever.
constexpr std::uint64_t kMaxRounds = 100000;

std::size_t round_up(std::size_t n, std::size_t multiple) {
  return (n + multiple - 1) / multiple * multiple;
}

std::string kernel_source(const std::vector<std::string>& files) {
  std::string source;
  for (const std::string& file : files) source += embedded_kernel_source(file) + "\n";
  return source;
}

std::string propagation_source() {
  return kernel_source({"state_word.clh", "brick_layout.clh", "eikonal_scheme.clh",
                        "propagation.cl", "brick_lanes.cl"});
}

std::string nerve_source() {
  return kernel_source({"state_word.clh", "brick_layout.clh", "nerve.cl"});
}

// Seed records: index coordinates, containing voxel, (h / length_unit)^2 G_s. The seeds must lie in
// the canvas (validate_seeds).
// Sizes `records` for every seed and fills the records of seeds[first..].
void seed_records(const Canvas& canvas, const std::vector<Vec3>& seeds, std::size_t first,
                  double length_unit, std::vector<float>& records) {
  records.resize(kSeedRecord * seeds.size(), 0.0f);
  const double h2 = canvas.voxel_size * canvas.voxel_size / (length_unit * length_unit);
  for (std::size_t s = first; s < seeds.size(); ++s) {
    const Vec3& p = seeds[s];
    const VoxelIndex v = canvas.voxel_containing(p);
    const int64_t slot = canvas.slot_of(v);
    const Vec3 c = canvas.index_coordinates(p);
    float* r = &records[kSeedRecord * s];
    r[0] = static_cast<float>(c.x());
    r[1] = static_cast<float>(c.y());
    r[2] = canvas.dimension == 3 ? static_cast<float>(c.z()) : 0.0f;
    r[4] = static_cast<float>(v.i);
    r[5] = static_cast<float>(v.j);
    r[6] = static_cast<float>(v.k);
    const float* metric = canvas.metric_of(static_cast<std::size_t>(slot));
    for (int n = 0; n < 6; ++n) r[8 + n] = static_cast<float>(h2 * metric[n]);
  }
}

// The field the device state holds bit for bit: its field_hash, and how many seeds the propagation
// that left it there solved (their blocks are frozen in the state); none after an upload, which
// carries no frozen marks.
struct HeldField {
  std::uint64_t hash = 0;
  std::optional<std::size_t> solved_seeds;
};

class OpenCLPropagator final : public Propagator {
 public:
  OpenCLPropagator(opencl::Device device, const OpenCLOptions& options)
      : device_(std::move(device)), options_(options) {
    context_ = opencl::context_for(device_);
    queue_ = cl::CommandQueue(context_, device_.device);
    variant_ = choose_variant();
  }

  std::string device_description() const override {
    return "OpenCL: " + device_.info.name + " (" + device_.info.platform + ", " + variant_name() +
           ")";
  }

  PropagationStats solve(const Canvas& canvas, const std::vector<Vec3>& seeds,
                         VoronoiField& field) override {
    return guarded("solving", [&] {
      const auto start = std::chrono::steady_clock::now();
      const std::vector<cl_int4> claims = prepare(canvas, seeds, 0);
      device_field_.reset();
      // The exact start writes every slot; its values are no front to step.
      const bool exact_start = exact_start_reach_ != ExactStartReach::none && !seeds.empty();
      if (!exact_start)
        queue_.enqueueFillBuffer(canvas_->state, opencl::kInfiniteState, 0,
                                 canvas_->slots * sizeof(cl_ulong));
      reset_stamps();
      step_ = exact_start ? 0.0f : front_step(canvas, seeds);
      if (step_ > 0.0f) build_stepping_kernel();
      const std::optional<BrickSeedLists> nearest =
          exact_start ? std::optional(exact_start_lists(canvas, seeds, exact_start_reach_))
                      : std::nullopt;
      PropagationStats stats =
          propagate(canvas, 0, seeds.size(), claims, false, nearest ? &*nearest : nullptr);
      read_back(std::nullopt, seeds.size(), field, start, stats);
      return stats;
    });
  }

  PropagationStats insert(const Canvas& canvas, const std::vector<Vec3>& seeds,
                          std::size_t first_new, VoronoiField& field) override {
    return insert_into(canvas, seeds, first_new, field, false);
  }

  std::vector<std::uint8_t> multi_label_bricks(const Canvas& canvas,
                                               const VoronoiField& field) override {
    return guarded("finding multi-label bricks", [&] {
      require_field_for(canvas, field, "multi_label_bricks()");
      hold_canvas(canvas);
      hold_field(field);
      return flag_multi_label_bricks(canvas.dimension);
    });
  }

  std::uint64_t device_bytes() const { return canvas_ ? canvas_->bytes : 0; }

 private:
  template <typename F>
  auto guarded(const std::string& doing, F&& body) -> decltype(body()) {
    const OneCallAtATime exclusive(busy_, "the OpenCL propagator on " + device_.info.name);
    try {
      return body();
    } catch (const cl::Error& e) {
      opencl::throw_opencl_error(e, doing + " on " + device_.info.name);
    } catch (const std::bad_alloc&) {
      throw out_of_memory_error(doing + " on " + device_.info.name);
    }
  }

  std::string variant_name() const {
    switch (variant_) {
      case RelaxationVariant::brick_lanes:
        return "brick lanes";
      case RelaxationVariant::voxel_phases:
        return "voxel phases";
      default:
        return "brick sweep";
    }
  }

  // brick_sweep and brick_lanes: a work-item sweeps whole bricks, with evaluation stamps.
  bool sweeps_bricks() const { return variant_ != RelaxationVariant::voxel_phases; }

  RelaxationVariant choose_variant() const {
    if (options_.variant != RelaxationVariant::automatic) return options_.variant;
    return device_.info.is_gpu ? RelaxationVariant::voxel_phases : RelaxationVariant::brick_lanes;
  }

  PropagationStats insert_returned(const Canvas& canvas, const std::vector<Vec3>& seeds,
                                   std::size_t first_new, VoronoiField& field) override {
    return insert_into(canvas, seeds, first_new, field, true);
  }

  // returned: `field` is the one returned last, bit for bit (insert_returned).
  PropagationStats insert_into(const Canvas& canvas, const std::vector<Vec3>& seeds,
                               std::size_t first_new, VoronoiField& field, bool returned) {
    return guarded("inserting seeds", [&] {
      const auto start = std::chrono::steady_clock::now();
      require_field_for(canvas, field, "insert()");
      require_first_new(first_new, seeds.size());
      // The check of the caller's field reads every slot: it starts first, beside all the rest.
      std::future<opencl::FieldDigest> digest;
      if (!returned)
        digest = std::async(std::launch::async,
                            [&field, first_new] { return opencl::digest_field(field, first_new); });
      std::size_t known_seeds = 0;
      const std::vector<cl_int4> claims = prepare(canvas, seeds, first_new, &field, &known_seeds);
      step_ = 0.0f;  // an insertion changes a region around its seeds: no stepping
      std::optional<HeldField> held = std::exchange(device_field_, std::nullopt);
      const std::optional<BrickSeedLists> nearest =
          insertion_start_lists(canvas, seeds, first_new, field);
      PropagationStats stats =
          propagate_insertion(canvas, seeds.size(), first_new, known_seeds, claims, field, digest,
                              held, nearest ? &*nearest : nullptr);
      read_back(held, seeds.size(), field, start, stats);
      return stats;
    });
  }

  // Propagates seeds[first_new, seed_count) from the caller's `field`, once checked
  // (require_insertable_field) by its `digest`. `held`: the field the device state held, reset
  // unless `field` is that field bit for bit. The caller almost always passes back the field
  // returned last, but making sure reads every slot (16.8M at 256^3, 3-5 ms on 16 host cores of
  // the GPU machine): so when the held field was solved for the same old seeds (`known_seeds` of
  // them are the last call's), the insertion runs on it while the host checks, and runs again from
  // `field` if that differs. No digest: `field` is the one returned last (insert_returned), so
  // only a device that no longer holds it makes it checked.
  PropagationStats propagate_insertion(const Canvas& canvas, std::size_t seed_count,
                                       std::size_t first_new, std::size_t known_seeds,
                                       const std::vector<cl_int4>& claims,
                                       const VoronoiField& field,
                                       std::future<opencl::FieldDigest>& digest,
                                       std::optional<HeldField>& held,
                                       const BrickSeedLists* nearest) {
    const bool speculate = held && held->solved_seeds == first_new && known_seeds >= first_new;
    PropagationStats stats;
    if (speculate) stats = propagate(canvas, first_new, seed_count, claims, true, nearest);
    if (speculate && !digest.valid()) return stats;
    const opencl::FieldDigest caller =
        digest.valid() ? digest.get() : opencl::digest_field(field, first_new);
    if (caller.faulty) require_insertable_field(canvas, field, first_new, "insert()");
    require_own_field_for_these_seeds(caller, held, first_new, known_seeds);
    if (held && caller.hash != held->hash) held.reset();
    if (speculate && held) return stats;
    if (!held) upload_field(field);
    return propagate(canvas, first_new, seed_count, claims, held && held->solved_seeds.has_value(),
                     nearest);
  }

  // The caller's field is the one this engine's last propagation left (the same digest), so the
  // seeds it was solved for are known: old seeds other than those would give a field that is no
  // solve of any seeds, silently (0.98 relative error measured), so they are refused. A field from
  // elsewhere (the reference, a file) cannot be checked so: the caller's promise.
  static void require_own_field_for_these_seeds(const opencl::FieldDigest& caller,
                                                const std::optional<HeldField>& held,
                                                std::size_t first_new, std::size_t known_seeds) {
    if (held && held->solved_seeds && caller.hash == held->hash)
      require_solved_for_these_seeds(*held->solved_seeds, known_seeds, first_new);
  }

  // The lists of an insertion's exact start (lower_to_nearest_seeds) over the new seeds, labelled
  // as they are among `seeds`; none where solves take no exact start.
  std::optional<BrickSeedLists> insertion_start_lists(const Canvas& canvas,
                                                      const std::vector<Vec3>& seeds,
                                                      std::size_t first_new,
                                                      const VoronoiField& field) const {
    // With no solved seed, propagate() would take the lists for a solve's.
    if (exact_start_reach_ == ExactStartReach::none || first_new == 0 || first_new == seeds.size())
      return std::nullopt;
    return rvor::insertion_start_lists(canvas, seeds, first_new, field.distance,
                                       exact_start_reach_);
  }

  // Uploads the seeds; returns the claims that seeds[first_new..] can change (all of a solve's;
  // rvor/seed_blocks.h).
  // `solved`: an insertion's field (the claims read its seed blocks' values). `known_seeds`: set to
  // how many leading seeds are those of the last call.
  std::vector<cl_int4> prepare(const Canvas& canvas, const std::vector<Vec3>& seeds,
                               std::size_t first_new, const VoronoiField* solved = nullptr,
                               std::size_t* known_seeds = nullptr) {
    // Labels leave TENTATIVE_LABEL (kernels/state_word.clh) free for front stepping.
    if (seeds.size() > kMostOpenCLSeeds)
      throw Error("too many seeds: " + std::to_string(seeds.size()) + " (the OpenCL engine takes " +
                  std::to_string(kMostOpenCLSeeds) + " at most)");
    hold_canvas(canvas);
    // Seeds of the last call (an insertion's solved seeds, as the caller passes them again) are
    // neither checked, derived nor uploaded again: with 100 000 seeds that was ~0.15 s of every
    // insertion. The claim cache knows them; held_records_ are their records.
    const std::size_t known = claim_cache_.known_prefix(seeds);
    if (known_seeds) *known_seeds = known;
    validate_seeds(canvas, seeds, known);  // the reference's checks and messages
    try {
      upload_seed_records(canvas, seeds, known);
      std::vector<cl_int4> claims;
      for (const SeedClaim& claim : foreign_seed_claims(canvas, seeds, first_new, claim_cache_,
                                                        solved ? &solved->distance : nullptr))
        claims.push_back({{claim.voxel.i, claim.voxel.j, claim.voxel.k, claim.label}});
      return claims;
    } catch (...) {  // the records and the cache may no longer describe the same seeds
      held_records_.clear();
      claim_cache_.clear();
      throw;
    }
  }

  // The device records of `seeds`, those before `known` as held_records_ holds them already.
  void upload_seed_records(const Canvas& canvas, const std::vector<Vec3>& seeds,
                           std::size_t known) {
    seed_records(canvas, seeds, known, canvas_->length_unit, held_records_);
    std::size_t first_upload = known;
    if (canvas_->seed_capacity < seeds.size()) {
      canvas_->seed_capacity = std::max<std::size_t>(seeds.size(), 2 * canvas_->seed_capacity);
      canvas_->seeds = cl::Buffer(context_, CL_MEM_READ_ONLY,
                                  canvas_->seed_capacity * kSeedRecord * sizeof(float));
      first_upload = 0;  // a new buffer
    }
    const std::size_t offset = first_upload * kSeedRecord;
    queue_.enqueueWriteBuffer(canvas_->seeds, CL_TRUE, offset * sizeof(float),
                              (held_records_.size() - offset) * sizeof(float),
                              held_records_.data() + offset);
  }

  // Uploads the canvas unless the device holds it already.
  void hold_canvas(const Canvas& canvas) {
    const std::optional<std::uint64_t> identity = canvas_identity(canvas);
    if (!canvas_ || held_address_ != &canvas || !identity || held_identity_ != identity) {
      canvas.require_consistent();  // before its bricks are read (solves check it again, cheaply)
      canvas_.reset();
      canvas_ = std::make_unique<opencl::DeviceCanvas>(
          opencl::upload_canvas(context_, canvas, colours(canvas)));
      held_address_ = &canvas;
      held_identity_ = identity;
      // The metric half of the exact start's rule, which the upload has just decided.
      exact_start_reach_ =
          options_.exact_start
              ? exact_start_reach(canvas, canvas_->uniform_stencil && canvas_->uniform_diagonal)
              : ExactStartReach::none;
      device_field_.reset();
      held_records_.clear();  // what prepare() derived from the seeds was for the other canvas
      claim_cache_.clear();
      build_kernels(canvas);
    }
  }

  // Makes the device state hold `field`: unless it is the field returned last (the device still
  // holds it, with stamps that describe it), upload it and forget the evaluations.
  void hold_field(const VoronoiField& field) {
    const std::uint64_t hash = opencl::field_hash(field);
    if (device_field_ && device_field_->hash == hash) return;
    upload_field(field);
    device_field_ = HeldField{hash, std::nullopt};
  }

  // The device state becomes `field` (no frozen marks), its evaluations forgotten.
  void upload_field(const VoronoiField& field) {
    device_field_.reset();
    opencl::upload_field(queue_, canvas_->state, field, canvas_->length_unit);
    reset_stamps();
  }

  std::vector<std::uint8_t> flag_multi_label_bricks(int dimension) {
    const DeviceCanvasRef d = *canvas_;
    if (d.bricks == 0) return {};
    if (!flag_multi_label_()) {
      const cl::Program nerve = opencl::build_program(context_, device_.device, nerve_source(),
                                                      "-DDIM=" + std::to_string(dimension));
      flag_multi_label_ = cl::Kernel(nerve, "flag_multi_label_bricks");
    }
    const cl::Buffer flags(context_, CL_MEM_WRITE_ONLY, d.bricks);
    set_args(flag_multi_label_, static_cast<cl_int>(d.bricks), d.origins, d.table, d.dims, d.grid,
             d.state, flags);
    queue_.enqueueNDRangeKernel(flag_multi_label_, cl::NullRange,
                                cl::NDRange(round_up(d.bricks, kBookkeepingGroup)),
                                cl::NDRange(kBookkeepingGroup));
    std::vector<std::uint8_t> result(d.bricks);
    queue_.enqueueReadBuffer(flags, CL_TRUE, 0, result.size(), result.data());
    return result;
  }

  // voxel_phases: a work-item per voxel of one parity class (kernels/propagation.cl, PHASES).
  std::size_t phase_group_size() const { return brick_volume_ == 512 ? 64 : 16; }

  // Brick colours relaxed in turn (kernels/propagation.cl, compact_active); 1: all every round.
  int colours(const Canvas& canvas) const {
    return opencl::brick_colours(canvas, options_.brick_colouring);
  }

  // Whether the metric is uniform and its stencil has axis offsets only (a diagonal metric, the
  // isotropic one among them). brick_lanes then shares the stencil across the lanes, as
  // constants (a flipped axis offset is its opposite, the same term in every lane's frame), and
  // max_sweeps() picks 4.
  bool uniform_axis_stencil() const {
    const std::vector<int>& offsets = canvas_->uniform_offsets;
    // Axis offsets come from a diagonal metric only; the kernels use its diagonal alone.
    if (offsets.empty() || !canvas_->uniform_diagonal) return false;
    for (std::size_t i = 0; i < offsets.size(); i += 3) {
      const int length = std::abs(offsets[i]) + std::abs(offsets[i + 1]) + std::abs(offsets[i + 2]);
      if (length != 1) return false;
    }
    return true;
  }

  // Sweeps per relaxation (OpenCLOptions::max_sweeps): with axis offsets only, fronts cross a
  // brick along axes, and the sweeps reversing one axis each settle most bricks in one
  // relaxation; any other stencil computes more that later news overturns.
  int max_sweeps() const {
    if (options_.max_sweeps > 0) return options_.max_sweeps;
    return uniform_axis_stencil() ? 4 : 2;
  }

  // The most times one relaxation of a brick evaluates a voxel: a sweep visits each voxel once,
  // a voxel_phases iteration updates each once. An insertion's voxel_phases rounds take their own
  // bound (OpenCLOptions::insertion_phase_iterations).
  int visits_per_relaxation(bool insertion) const {
    if (sweeps_bricks()) return max_sweeps();
    return insertion ? options_.insertion_phase_iterations : options_.phase_iterations;
  }

  // The most of solves and insertions: the evaluation stamps of a round must cover either.
  int most_visits_per_relaxation() const {
    return std::max(visits_per_relaxation(false), visits_per_relaxation(true));
  }

  // The uniform stencil's shape as constants for relax_brick_lanes (kernels/brick_lanes.cl).
  std::string uniform_stencil_options() const {
    const std::vector<int>& offsets = canvas_->uniform_offsets;
    if (!uniform_axis_stencil()) return "";
    std::string options = " -DUNIFORM_TERMS=" + std::to_string(offsets.size() / 3);
    for (std::size_t n = 0; n < 3 * std::size_t{opencl::kStencilTerms}; ++n)
      options += " -DUNIFORM_OFFSET_" + std::to_string(n / 3) + "XYZ"[n % 3] + "=" +
                 std::to_string(n < offsets.size() ? offsets[n] : 0);
    return options;
  }

  // After upload_canvas: the kernels read the stencils the way they were packed.
  void build_kernels(const Canvas& canvas) {
    const int dimension = canvas.dimension;
    std::string options =
        "-DDIM=" + std::to_string(dimension) + " -DINIT_RADIUS=" + std::to_string(kSeedBlockRadius);
    if (canvas_->uniform_stencil) options += " -DUNIFORM_METRIC" + uniform_stencil_options();
    if (!options_.x86_gathers) options += " -DNO_X86_GATHERS";
    const cl::Program program =
        opencl::build_program(context_, device_.device, propagation_source(), options);
    build_options_ = options;
    relax_stepping_ = cl::Kernel();  // built when a solve first steps its front
    brick_volume_ = dimension == 3 ? 512 : 64;
    variant_ = choose_variant();  // per canvas: the fallback below depends on it
    if (variant_ == RelaxationVariant::voxel_phases &&
        device_.device.getInfo<CL_DEVICE_MAX_WORK_GROUP_SIZE>() < phase_group_size())
      variant_ = RelaxationVariant::brick_sweep;  // the device cannot hold a phase per work-group
    freeze_ = cl::Kernel(program, "freeze_seed_blocks");
    init_ = cl::Kernel(program, "initialise_seeds");
    start_ = cl::Kernel(program, "start_at_nearest_seeds");
    lower_ = cl::Kernel(program, "lower_to_nearest_seeds");
    claim_ = cl::Kernel(program, "claim_seed_voxels");
    relax_ =
        cl::Kernel(program, variant_ == RelaxationVariant::brick_lanes   ? "relax_brick_lanes"
                            : variant_ == RelaxationVariant::brick_sweep ? "relax_brick_sweep"
                                                                         : "relax_voxel_phases");
    commit_ = cl::Kernel(program, "commit_bricks");
    gather_ = cl::Kernel(program, "gather_bricks");
    activate_ = cl::Kernel(program, "activate_bricks");
    compact_ = cl::Kernel(program, "compact_active");
    pend_listed_ = cl::Kernel(program, "pend_listed");
    spread_ = cl::Kernel(program, "spread_activation");
    least_of_ = cl::Kernel(program, "least_tentative_of");
    pend_below_ = cl::Kernel(program, "pend_below_threshold");
    flag_multi_label_ = cl::Kernel();  // built when first used (only the nerve needs it)
  }

  // Propagates seeds[first_seed, seed_count) from the device state. frozen_marks_held: the state
  // is that of a completed propagation, whose seeds' blocks are frozen already.
  PropagationStats propagate(const Canvas& canvas, std::size_t first_seed, std::size_t seed_count,
                             const std::vector<cl_int4>& claims, bool frozen_marks_held,
                             const BrickSeedLists* exact_start = nullptr) {
    const bool insertion = first_seed > 0;
    const int visits = visits_per_relaxation(insertion);
    queue_.enqueueFillBuffer(canvas_->update_counter, cl_ulong{0}, 0, sizeof(cl_ulong));
    queue_.enqueueFillBuffer(canvas_->touched, cl_uchar{0}, 0, canvas_->bricks);
    queue_.enqueueFillBuffer(canvas_->flags, cl_uchar{0}, 0, canvas_->bricks);
    queue_.enqueueFillBuffer(canvas_->pending, cl_uchar{0}, 0, canvas_->bricks);
    threshold_ = std::numeric_limits<float>::infinity();
    if (step_ > 0.0f) {  // only a stepping relax_brick_lanes writes least_tentative
      threshold_ = step_;
      queue_.enqueueFillBuffer(canvas_->least_tentative, std::numeric_limits<cl_float>::infinity(),
                               0, canvas_->bricks * sizeof(cl_float));
    }
    const cl_uint seed_stamp = next_round_base();
    if (exact_start && !insertion) start_at_nearest_seeds(*exact_start, seed_stamp);
    // The solved seeds' blocks are frozen already where the device's own solve or insertion left
    // the field it holds; an uploaded field carries no frozen marks. (Re-freezing 20000 seeds'
    // blocks was ~45% of an insertion's samples at 128^3.)
    if (insertion && !frozen_marks_held) prepare_seed_blocks(0, first_seed, true, seed_stamp);
    // After the frozen marks: the claims, not the start, decide the solved seeds' blocks.
    if (exact_start && insertion) lower_to_nearest_seeds(*exact_start, seed_stamp);
    prepare_seed_blocks(first_seed, seed_count, false, seed_stamp);
    initialise_seeds(first_seed, seed_count, seed_stamp);
    claim_seed_voxels(claims, seed_stamp);
    activate_initial_bricks();
    queue_.finish();  // so that round_seconds holds the rounds alone
    const auto rounds_start = std::chrono::steady_clock::now();
    PropagationStats stats;
    stats.exact_start = exact_start != nullptr;
    // An insertion relaxes every pending brick each round while they fit the scratch: its front
    // crosses few bricks, and taking them a colour at a time made 5x the rounds, each a wait for
    // the device (docs/scheme.md, "Insertion on the device"). When they do not fit, it takes a
    // cycle of colours, then tries every colour at once again.
    int colour_count = insertion ? 1 : colours(canvas);
    int colour = 0;
    do {
      for (int count = 0; next_active_list(colour_count, colour, count);) {
        if (colour == 0 && step_ > 0.0f) raise_threshold();
        if (static_cast<std::size_t>(count) > canvas_->scratch_bricks) {
          // More than the scratch holds (every colour at once): none this round, a cycle of
          // colours from the next (a subset taken by the list would depend on the work-items'
          // timing).
          pend_listed(count);
          colour_count = colours(canvas);
          continue;
        }
        if (count > 0) {
          relax(count, visits);
          stats.brick_relaxations += static_cast<std::uint64_t>(count);
          if (++stats.iterations > kMaxRounds)
            throw Error("the OpenCL propagation did not converge in " + std::to_string(kMaxRounds) +
                        " rounds (float rounding can keep voxels changing under very strong "
                        "anisotropy along a grid axis, docs/scheme.md 'Convergence'; --device cpu "
                        "solves in double)");
        }
        colour = (colour + 1) % colour_count;
        if (insertion && colour == 0) colour_count = 1;
      }
    } while (step_ > 0.0f && raise_threshold());
    queue_.enqueueReadBuffer(canvas_->update_counter, CL_TRUE, 0, sizeof(cl_ulong),
                             &stats.voxel_updates);
    stats.round_seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - rounds_start).count();
    stats.device_bytes = canvas_->bytes;
    stats.visits_per_relaxation = static_cast<std::uint64_t>(visits);
    return stats;
  }

  // The propagated state into `field`. held_field: the state was `field` bit for bit before the
  // propagation (an insertion into the field the device held; an upload turns unlabelled slots
  // into +inf, so only then may the read-back skip the bricks nothing wrote).
  void read_back(const std::optional<HeldField>& held_field, std::size_t seed_count,
                 VoronoiField& field, std::chrono::steady_clock::time_point start,
                 PropagationStats& stats) {
    const std::uint64_t hash = held_field
                                   ? opencl::download_touched_bricks(
                                         queue_, canvas_->state, canvas_->touched, canvas_->bricks,
                                         brick_volume_, held_field->hash, canvas_->length_unit,
                                         [&](const std::vector<cl_int>& bricks, cl_ulong* words) {
                                           read_bricks(bricks, words);
                                         },
                                         field)
                                   : opencl::download_field(queue_, canvas_->state, canvas_->slots,
                                                            canvas_->length_unit, field);
    device_field_ = HeldField{hash, seed_count};
    stats.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  }

  std::size_t seed_block_items(std::size_t first_seed, std::size_t seed_count) const {
    const std::size_t side = 2 * kSeedBlockRadius + 1;
    return (seed_count - first_seed) * side * side * (brick_volume_ == 512 ? side : 1);
  }

  // Seeds [first_seed, seed_count): `existing` re-marks solved seeds' blocks frozen; otherwise
  // new seeds' block voxels are reset so they take their exact values.
  void prepare_seed_blocks(std::size_t first_seed, std::size_t seed_count, bool existing,
                           cl_uint stamp) {
    const std::size_t items = seed_block_items(first_seed, seed_count);
    if (items == 0) return;
    const DeviceCanvasRef d = *canvas_;
    set_args(freeze_, static_cast<cl_int>(first_seed), static_cast<cl_int>(seed_count - first_seed),
             static_cast<cl_int>(existing ? 1 : 0), d.seeds, d.state, d.activity, d.table, d.dims,
             d.grid, d.changed, stamp, d.touched);
    queue_.enqueueNDRangeKernel(freeze_, cl::NullRange,
                                cl::NDRange(round_up(items, kBookkeepingGroup)),
                                cl::NDRange(kBookkeepingGroup));
  }

  void initialise_seeds(std::size_t first_seed, std::size_t seed_count, cl_uint stamp) {
    const std::size_t items = seed_block_items(first_seed, seed_count);
    if (items == 0) return;
    const DeviceCanvasRef d = *canvas_;
    set_args(init_, static_cast<cl_int>(first_seed), static_cast<cl_int>(seed_count - first_seed),
             d.seeds, d.state, d.activity, d.table, d.dims, d.grid, d.flags, d.changed, stamp,
             d.touched);
    queue_.enqueueNDRangeKernel(init_, cl::NullRange,
                                cl::NDRange(round_up(items, kBookkeepingGroup)),
                                cl::NDRange(kBookkeepingGroup));
  }

  // Every slot at its least u0 over its brick's candidate seeds where its quarter brick sees that
  // seed, else at +inf; every brick pending (docs/scheme.md, "Initialisation": the exact start of
  // a uniform metric).
  void start_at_nearest_seeds(const BrickSeedLists& nearest, cl_uint stamp) {
    const DeviceCanvasRef d = *canvas_;
    if (d.bricks == 0) return;
    // Not empty: every brick lists at least its nearest seed. (Buffers live until the launch.)
    const cl::Buffer begin = read_only(nearest.begin), listed = read_only(nearest.seeds),
                     seen = read_only(nearest.seen);
    set_args(start_, static_cast<cl_int>(d.bricks), begin, listed, seen, d.seeds, d.origins,
             d.activity, d.state, d.flags, d.changed, stamp);
    const std::size_t rows = d.slots / Canvas::kBrickEdge;  // a work-item per brick row
    queue_.enqueueNDRangeKernel(start_, cl::NullRange,
                                cl::NDRange(round_up(rows, kBookkeepingGroup)),
                                cl::NDRange(kBookkeepingGroup));
  }

  // An insertion's exact start: the voxels a new seed's u0 lowers take it (kernels/propagation.cl),
  // on the bricks that list a seed.
  void lower_to_nearest_seeds(const BrickSeedLists& nearest, cl_uint stamp) {
    std::vector<cl_int> listed;
    std::vector<cl_uint> begin;  // the listed bricks' ranges follow each other in `seeds`
    for (std::size_t brick = 0; brick + 1 < nearest.begin.size(); ++brick)
      if (nearest.begin[brick] != nearest.begin[brick + 1]) {
        listed.push_back(static_cast<cl_int>(brick));
        begin.push_back(nearest.begin[brick]);
      }
    if (listed.empty()) return;
    begin.push_back(nearest.begin.back());
    const DeviceCanvasRef d = *canvas_;
    const cl::Buffer bricks = read_only(listed), ranges = read_only(begin),
                     entries = read_only(nearest.seeds), seen = read_only(nearest.seen);
    set_args(lower_, static_cast<cl_int>(listed.size()), bricks, ranges, entries, seen, d.seeds,
             d.origins, d.activity, d.state, d.flags, d.changed, d.evaluated, stamp, d.touched);
    const std::size_t rows = listed.size() * (brick_volume_ / Canvas::kBrickEdge);  // per row
    queue_.enqueueNDRangeKernel(lower_, cl::NullRange,
                                cl::NDRange(round_up(rows, kBookkeepingGroup)),
                                cl::NDRange(kBookkeepingGroup));
  }

  void claim_seed_voxels(const std::vector<cl_int4>& claims, cl_uint stamp) {
    if (claims.empty()) return;
    const DeviceCanvasRef d = *canvas_;
    const cl::Buffer buffer = read_only(claims);
    set_args(claim_, static_cast<cl_int>(claims.size()), buffer, d.seeds, d.state, d.activity,
             d.table, d.dims, d.grid, d.flags, d.changed, stamp, d.touched);
    queue_.enqueueNDRangeKernel(claim_, cl::NullRange,
                                cl::NDRange(round_up(claims.size(), kBookkeepingGroup)),
                                cl::NDRange(kBookkeepingGroup));
  }

  // A device copy of `values` (not empty) for a launch; it must outlive the enqueue (a kernel
  // argument does not hold its buffer).
  template <typename T>
  cl::Buffer read_only(const std::vector<T>& values) const {
    return cl::Buffer(context_, CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR, values.size() * sizeof(T),
                      const_cast<T*>(values.data()));
  }

  // Forgets every evaluation (work avoidance, every variant): the next one recomputes all voxels.
  void reset_stamps() {
    // A power of two above the evaluations of one relaxation, so rounds are stamp bit masks.
    const cl_uint ticks =
        static_cast<cl_uint>(most_visits_per_relaxation()) * static_cast<cl_uint>(brick_volume_);
    stamp_stride_ = 1;
    while (stamp_stride_ <= ticks) stamp_stride_ *= 2;
    round_base_ = 0;
    queue_.enqueueFillBuffer(canvas_->evaluated, cl_uint{0}, 0, canvas_->slots * sizeof(cl_uint));
    queue_.enqueueFillBuffer(canvas_->changed, cl_uint{0}, 0, canvas_->slots * sizeof(cl_uint));
  }

  // The first stamp of a new round. 32-bit stamps wrap after ~4 million rounds of 2 sweeps: before
  // they would, forget the evaluations (only costs re-evaluating voxels once).
  cl_uint next_round_base() {
    if (static_cast<std::uint64_t>(round_base_) + 2 * stamp_stride_ > kMaxStamp) reset_stamps();
    round_base_ += stamp_stride_;
    return round_base_;
  }

  // The bricks the seed initialisation touched, and those within stencil reach, become pending.
  void activate_initial_bricks() {
    const DeviceCanvasRef d = *canvas_;
    set_args(activate_, static_cast<cl_int>(d.bricks), d.origins, d.table, d.grid, d.brick_reach,
             d.flags, d.pending);
    queue_.enqueueNDRangeKernel(activate_, cl::NullRange,
                                cl::NDRange(round_up(d.bricks, kBookkeepingGroup)),
                                cl::NDRange(kBookkeepingGroup));
    queue_.enqueueFillBuffer(d.flags, cl_uchar{0}, 0, d.bricks);
  }

  // Lists the pending bricks of the given colour (`count`); returns whether any brick is pending.
  bool next_active_list(int colours, int colour, int& count) {
    const DeviceCanvasRef d = *canvas_;
    queue_.enqueueFillBuffer(d.round_counts, cl_int{0}, 0, 2 * sizeof(cl_int));
    set_args(compact_, static_cast<cl_int>(d.bricks), d.pending, d.origins,
             static_cast<cl_int>(colours), static_cast<cl_int>(colour), d.list, d.round_counts);
    queue_.enqueueNDRangeKernel(compact_, cl::NullRange,
                                cl::NDRange(round_up(d.bricks, kBookkeepingGroup)),
                                cl::NDRange(kBookkeepingGroup));
    cl_int counts[2] = {0, 0};  // listed, any pending
    queue_.enqueueReadBuffer(d.round_counts, CL_TRUE, 0, sizeof counts, counts);
    count = counts[0];
    return counts[1] != 0;
  }

  // Makes the `count` bricks of the last list pending again.
  void pend_listed(int count) {
    const DeviceCanvasRef d = *canvas_;
    set_args(pend_listed_, d.list, static_cast<cl_int>(count), d.pending);
    queue_.enqueueNDRangeKernel(
        pend_listed_, cl::NullRange,
        cl::NDRange(round_up(static_cast<std::size_t>(count), kBookkeepingGroup)),
        cl::NDRange(kBookkeepingGroup));
  }

  // Front stepping, once per colour cycle and when nothing is pending: the threshold moves to the
  // least tentative distance plus the step (it never falls), and the bricks holding tentative
  // distances below it become pending. Returns whether any tentative distance is left.
  bool raise_threshold() {
    const DeviceCanvasRef d = *canvas_;
    const cl_uint none = 0xFFFFFFFFu;
    queue_.enqueueFillBuffer(d.least_bits, none, 0, sizeof(cl_uint));
    set_args(least_of_, static_cast<cl_int>(d.bricks), d.least_tentative, d.least_bits);
    queue_.enqueueNDRangeKernel(least_of_, cl::NullRange,
                                cl::NDRange(round_up(d.bricks, kBookkeepingGroup)),
                                cl::NDRange(kBookkeepingGroup));
    cl_uint least_bits = none;
    queue_.enqueueReadBuffer(d.least_bits, CL_TRUE, 0, sizeof(cl_uint), &least_bits);
    if (least_bits == none) return false;
    float least = 0.0f;
    std::memcpy(&least, &least_bits, sizeof(float));
    threshold_ = std::max(threshold_, least + step_);
    set_args(pend_below_, static_cast<cl_int>(d.bricks), threshold_, d.least_tentative, d.pending);
    queue_.enqueueNDRangeKernel(pend_below_, cl::NullRange,
                                cl::NDRange(round_up(d.bricks, kBookkeepingGroup)),
                                cl::NDRange(kBookkeepingGroup));
    return true;
  }

  // The front step of a solve in distance units (0: none; front_step.h).
  float front_step(const Canvas& canvas, const std::vector<Vec3>& seeds) const {
    if (variant_ != RelaxationVariant::brick_lanes) return 0.0f;
    const double voxels =
        opencl::front_step_voxels(options_.front_step, canvas.dimension, canvas.active_voxel_count,
                                  seeds.size(), canvas_->axis_readers);
    return voxels > 0.0 ? static_cast<float>(voxels * opencl::voxel_length(canvas, seeds) /
                                             canvas_->length_unit)
                        : 0.0f;
  }

  // relax_brick_lanes with the stepping built in (FRONT_STEPPING), once per canvas.
  void build_stepping_kernel() {
    if (relax_stepping_()) return;
    const cl::Program program = opencl::build_program(
        context_, device_.device, propagation_source(), build_options_ + " -DFRONT_STEPPING=1");
    relax_stepping_ = cl::Kernel(program, "relax_brick_lanes");
  }

  // The states of `bricks` into `words`, packed on the device as many at a time as the scratch
  // holds, each load in one transfer: one read per brick paid a transfer's latency per brick.
  void read_bricks(const std::vector<cl_int>& bricks, cl_ulong* words) {
    const DeviceCanvasRef d = *canvas_;
    for (std::size_t first = 0; first < bricks.size(); first += d.scratch_bricks) {
      const std::size_t count = std::min(d.scratch_bricks, bricks.size() - first);
      queue_.enqueueWriteBuffer(d.list, CL_FALSE, 0, count * sizeof(cl_int), &bricks[first]);
      set_args(gather_, d.list, static_cast<cl_int>(count), d.state, d.scratch);
      queue_.enqueueNDRangeKernel(gather_, cl::NullRange,
                                  cl::NDRange(round_up(count * brick_volume_, kBookkeepingGroup)),
                                  cl::NDRange(kBookkeepingGroup));
      queue_.enqueueReadBuffer(d.scratch, CL_FALSE, 0, count * brick_volume_ * sizeof(cl_ulong),
                               words + first * brick_volume_);
    }
    queue_.finish();
  }

  // Relaxes the `count` listed bricks, each voxel at most `visits` times (visits_per_relaxation).
  void relax(int count, int visits) {
    const DeviceCanvasRef d = *canvas_;
    const bool sweep = sweeps_bricks();
    cl::Kernel& kernel = step_ > 0.0f ? relax_stepping_ : relax_;
    // Every variant takes BRICK_SWEEP_ARGUMENTS (kernels/propagation.cl).
    set_args(kernel, d.list, static_cast<cl_int>(count), d.state, d.scratch, d.scratch_stamps,
             d.stencils, d.shapes, d.table, d.origins, d.dims, d.grid, d.seeds, d.flags,
             d.update_counter, static_cast<cl_int>(visits), d.evaluated, d.changed,
             next_round_base(), stamp_stride_, d.activity, d.reader_reach, d.news, threshold_,
             d.least_tentative);
    const std::size_t voxels = static_cast<std::size_t>(count) * brick_volume_;
    if (variant_ == RelaxationVariant::brick_lanes)
      queue_.enqueueNDRangeKernel(kernel, cl::NullRange, cl::NDRange((count + kLanes - 1) / kLanes),
                                  cl::NDRange(1));
    else if (sweep)
      queue_.enqueueNDRangeKernel(kernel, cl::NullRange, cl::NDRange(count), cl::NDRange(1));
    else
      queue_.enqueueNDRangeKernel(kernel, cl::NullRange,
                                  cl::NDRange(static_cast<std::size_t>(count) * phase_group_size()),
                                  cl::NDRange(phase_group_size()));
    set_args(commit_, d.list, static_cast<cl_int>(count), d.scratch, d.scratch_stamps, d.state,
             d.changed, d.flags, d.touched);
    queue_.enqueueNDRangeKernel(commit_, cl::NullRange, cl::NDRange(voxels),
                                cl::NDRange(kBookkeepingGroup));
    set_args(spread_, d.list, static_cast<cl_int>(count), d.origins, d.table, d.grid, d.brick_reach,
             d.flags, d.pending, d.news);
    queue_.enqueueNDRangeKernel(spread_, cl::NullRange,
                                cl::NDRange(round_up(count, kBookkeepingGroup)),
                                cl::NDRange(kBookkeepingGroup));
  }

  using DeviceCanvasRef = const opencl::DeviceCanvas&;

  template <typename... Args>
  static void set_args(cl::Kernel& kernel, const Args&... args) {
    cl_uint index = 0;
    (kernel.setArg(index++, args), ...);
  }

  opencl::Device device_;
  OpenCLOptions options_;
  std::atomic<bool> busy_{false};  // OneCallAtATime
  RelaxationVariant variant_ = RelaxationVariant::brick_sweep;
  cl::Context context_;
  cl::CommandQueue queue_;
  std::unique_ptr<opencl::DeviceCanvas> canvas_;
  // The canvas canvas_ was uploaded from: its address and canvas_identity.
  const Canvas* held_address_ = nullptr;
  std::optional<std::uint64_t> held_identity_;
  ExactStartReach exact_start_reach_ = ExactStartReach::none;  // on the canvas held
  std::size_t brick_volume_ = 512;
  static constexpr std::uint64_t kMaxStamp = 0xFFFFFFFFu;  // stamps are cl_uint on the device
  cl_uint stamp_stride_ = 1, round_base_ = 0;              // evaluation stamps
  // The field the device state holds, while it holds one bit for bit.
  std::optional<HeldField> device_field_;
  // What the claims derived from the seeds of the last solve or insertion on this canvas (which
  // were checked, and are in the device's seed buffer), and their device records.
  SeedClaimCache claim_cache_;
  std::vector<float> held_records_;
  cl::Kernel freeze_, init_, start_, lower_, claim_, relax_, commit_, gather_, activate_, compact_,
      spread_, flag_multi_label_;
  cl::Kernel least_of_, pend_below_, relax_stepping_, pend_listed_;
  std::string build_options_;  // of the program the kernels above come from
  // Front stepping: evaluations above the threshold stay tentative (kernels/state_word.clh);
  // +inf: off. step_: how far the threshold moves past the least tentative distance.
  float threshold_ = std::numeric_limits<float>::infinity(), step_ = 0.0f;
};

}  // namespace

std::unique_ptr<Propagator> make_opencl_propagator(const std::string& device,
                                                   const OpenCLOptions& options) {
  if (options.max_sweeps < 0 || options.max_sweeps > kMostVisitsPerRelaxation)
    throw Error("OpenCLOptions::max_sweeps must be in [0, " +
                std::to_string(kMostVisitsPerRelaxation) + "] (0: automatic), got " +
                std::to_string(options.max_sweeps));
  for (const auto& [name, iterations] :
       {std::pair{"phase_iterations", options.phase_iterations},
        std::pair{"insertion_phase_iterations", options.insertion_phase_iterations}})
    if (iterations < 1 || iterations > kMostVisitsPerRelaxation)
      throw Error(std::string("OpenCLOptions::") + name + " must be in [1, " +
                  std::to_string(kMostVisitsPerRelaxation) + "], got " +
                  std::to_string(iterations));
  if (!std::isfinite(options.front_step) ||
      (options.front_step > 0.0 && options.front_step < kSmallestFrontStep))
    throw Error(
        "OpenCLOptions::front_step must be negative (automatic), 0 (off) or at least 0.25 "
        "voxel lengths, got " +
        std::to_string(options.front_step));
  switch (options.variant) {
    case RelaxationVariant::automatic:
    case RelaxationVariant::brick_sweep:
    case RelaxationVariant::brick_lanes:
    case RelaxationVariant::voxel_phases:
      break;
    default:
      throw Error("OpenCLOptions::variant " + std::to_string(static_cast<int>(options.variant)) +
                  " is not a variant");
  }
  opencl::Device selected = opencl::select_device(device);
  try {
    return std::make_unique<OpenCLPropagator>(std::move(selected), options);
  } catch (const cl::Error& e) {
    opencl::throw_opencl_error(e, "setting up " + device);
  }
}

void build_opencl_program(const std::string& device, const std::string& source,
                          const std::string& build_options) {
  const opencl::Device selected = opencl::select_device(device);
  opencl::build_program(opencl::context_for(selected), selected.device, source, build_options);
}

}  // namespace rvor
