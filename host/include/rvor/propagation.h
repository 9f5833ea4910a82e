#pragma once
// Multi-source Riemannian eikonal propagation: for every active canvas voxel, the geodesic
// distance to its nearest seed and that seed's label. The discrete scheme (Selling stencils,
// per-label updates, exact initialisation, additive source factorization) is specified in
// docs/scheme.md; every Propagator iterates the same update operator to its fixed point, so
// implementations agree up to floating-point rounding, whatever their schedule.
#include <algorithm>
#include <cstdint>
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include "rvor/canvas.h"
#include "rvor/error.h"

namespace rvor {

// Per canvas slot: distance (+inf where unreached or inactive) and label (seed index, -1 where
// none).
struct VoronoiField {
  std::vector<float> distance;
  std::vector<int32_t> label;
};

// Throws rvor::Error "WHAT: the field does not match the canvas (...)" unless the field has one
// distance and one label per canvas slot (a field solved on another canvas, or none yet).
inline void require_field_for(const Canvas& canvas, const VoronoiField& field,
                              const std::string& what) {
  if (field.distance.size() == canvas.slot_count() && field.label.size() == canvas.slot_count())
    return;
  throw Error(what + ": the field does not match the canvas (" +
              std::to_string(field.distance.size()) + " distances and " +
              std::to_string(field.label.size()) + " labels for " +
              std::to_string(canvas.slot_count()) + " slots; solve on this canvas first)");
}

// Whether a slot holding (distance, label) can belong to a field solved for `solved_seeds` seeds:
// a label in -1..solved_seeds-1, and a distance that is +inf without a label, finite and at least
// 0 with one (NaN never). Branch-free, so that loops over all slots vectorise.
inline bool insertable_slot(float distance, std::int32_t label, std::size_t solved_seeds) {
  const auto seeds = static_cast<std::uint32_t>(
      std::min<std::size_t>(solved_seeds, std::numeric_limits<std::int32_t>::max()));
  const bool labelled = label >= 0;
  const bool finite = distance < std::numeric_limits<float>::infinity();  // false for NaN
  return (static_cast<std::uint32_t>(label) + 1u <= seeds) & (distance >= 0.0f) &
         (labelled == finite);
}

// Throws rvor::Error "WHAT: the field is not one solved for the first N seeds: slot S (voxel i, j,
// k) has ..." at the first slot that fails insertable_slot, after require_field_for: insert()
// starts from the field, and a label of an unknown seed would index past the seeds.
void require_insertable_field(const Canvas& canvas, const VoronoiField& field,
                              std::size_t solved_seeds, const std::string& what);

// Throws rvor::Error "insert(): first_new F is past the last of the N seeds" unless the new seeds
// start within `seed_count` (every engine's insert() checks it).
void require_first_new(std::size_t first_new, std::size_t seed_count);

// For an insertion into the field the engine returned last, solved for `solved_seeds` seeds of
// which the first `unchanged` are the caller's seeds[0..unchanged): throws rvor::Error unless those
// are the insertion's old seeds, first_new of them (other old seeds would give a field that solves
// no seeds, silently; every engine checks its own last field so).
void require_solved_for_these_seeds(std::size_t solved_seeds, std::size_t unchanged,
                                    std::size_t first_new);

struct PropagationStats {
  // Outer iterations (reference: queue pops; OpenCL: active-list rounds).
  std::uint64_t iterations = 0;
  // Local solves performed, all labels counted once per voxel visit.
  std::uint64_t voxel_updates = 0;
  // OpenCL: bricks relaxed, summed over the rounds (a brick relaxed in 10 rounds counts 10);
  // the reference has no bricks: 0.
  std::uint64_t brick_relaxations = 0;
  // OpenCL: device memory allocated for the canvas (its buffers, held between solves); the
  // reference: 0.
  std::uint64_t device_bytes = 0;
  // OpenCL: the most evaluations of one voxel in one brick relaxation (sweeps per relaxation, or
  // voxel_phases iterations per round), so voxel_updates <= visits_per_relaxation * 512 *
  // brick_relaxations; the reference: 0.
  std::uint64_t visits_per_relaxation = 0;
  // Whether the solve started voxels at their nearest seed's exact distance rather than +inf (the
  // exact start of rvor/nearest_seeds.h, under a uniform diagonal metric: every voxel of a convex
  // domain, elsewhere those whose quarter brick sees the seed, which may be none).
  bool exact_start = false;
  double seconds = 0.0;
  // OpenCL: the part of `seconds` in the rounds of relaxations (from the first round's start to
  // the last's end); the rest prepares the seeds and the field and reads it back. Reference: 0.
  double round_seconds = 0.0;
};

// A propagator keeps what it derived from the last canvas it was given (stencils; the OpenCL
// engine, the canvas uploaded to the device and the field it returned) and reuses it while the
// canvas is the same: same content hash (Canvas::content_hash, which finalize() records once per
// build rather than every call: reading all 16.8M slots at 256^3 would cost an insertion more than
// its propagation), geometry and tensors of ~4096 evenly spread slots as they are at the call,
// and for the OpenCL engine the same address. Call finalize() after changing a canvas in place: a
// direct write to `active` or Canvas::mutable_metric() without it is seen only where it touches one
// of those slots.
class Propagator {
 public:
  virtual ~Propagator() = default;
  // One call at a time: a propagator keeps its canvas and last field between calls, so a call
  // that overlaps another on the same propagator (from another thread) throws rvor::Error. Use
  // one propagator per thread; separate propagators run in parallel.
  // What runs the propagation, e.g. "cpu reference" or "OpenCL: pthread-haswell (PoCL 3.1)".
  virtual std::string device_description() const = 0;
  // Bytes the propagator's own arrays may take (0, the default: the memory available when a
  // canvas is first solved). The CPU reference checks its arrays against it before allocating
  // them; the OpenCL engine checks its buffers against the device's memory instead.
  virtual void set_memory_budget(std::uint64_t bytes) { (void)bytes; }
  // Solves from scratch: seed i gets label i. Validates the seeds first (validate_seeds).
  virtual PropagationStats solve(const Canvas& canvas, const std::vector<Vec3>& seeds,
                                 VoronoiField& field) = 0;
  // Adds seeds[first_new..] to a field solved for seeds[0..first_new): only what the new seeds
  // change is recomputed, and the result equals solve() with all seeds (docs/scheme.md). Any
  // field of the canvas is taken, once checked (require_insertable_field), which reads every
  // slot; chains of insertions into the field returned last skip that in a VoronoiSession. That
  // the field was solved for seeds[0..first_new) is the caller's promise, which no check of the
  // field alone can keep; both engines refuse their own last field with other old seeds.
  virtual PropagationStats insert(const Canvas& canvas, const std::vector<Vec3>& seeds,
                                  std::size_t first_new, VoronoiField& field) = 0;
  // Per canvas brick, 1 where the brick holds a multi-label grid cell (find_multi_label_bricks),
  // else 0: the bricks extract_nerve has to visit. `field` is one this propagator returned. The
  // OpenCL engine finds them with a kernel on the state it still holds (it uploads `field` when
  // the device holds another one); the default scans on the host.
  virtual std::vector<std::uint8_t> multi_label_bricks(const Canvas& canvas,
                                                       const VoronoiField& field);

 protected:
  // insert() into a `field` that is, bit for bit, the one this propagator's last solve() or
  // insert() returned: VoronoiSession, which alone calls it, owns both the propagator and the
  // field. The OpenCL engine then skips reading all of it to make sure. Default: insert().
  virtual PropagationStats insert_returned(const Canvas& canvas, const std::vector<Vec3>& seeds,
                                           std::size_t first_new, VoronoiField& field) {
    return insert(canvas, seeds, first_new, field);
  }
  friend class VoronoiSession;
};

// Per canvas brick, 1 where some grid cell based at one of its voxels (the cube, in 2D the square,
// whose corners are that voxel and its +x/+y/+z neighbours) has active corners carrying two or
// more labels: only such cells witness Delaunay simplices (nerve.h). Sequential, on the host.
// Throws rvor::Error when the field does not match the canvas.
std::vector<std::uint8_t> find_multi_label_bricks(const Canvas& canvas, const VoronoiField& field);

// The sequential CPU reference solver: clear on purpose, the ground truth for every kernel.
// exact_start: solves under a uniform diagonal metric start voxels at their nearest seed's exact
// distance (docs/scheme.md, "Initialisation"; which voxels: rvor/nearest_seeds.h), as the OpenCL
// engine does by default; false: from +inf.
std::unique_ptr<Propagator> make_reference_propagator(bool exact_start = true);

// "cpu" -> the reference; "auto", "opencl", "opencl:N", "pocl" -> the OpenCL engine (added by
// the OpenCL runtime). Throws rvor::Error for unknown names or missing devices.
std::unique_ptr<Propagator> make_propagator(const std::string& device);
// make_propagator(default_device_name()): $RVOR_DEVICE, else "auto" (rvor/devices.h). An error
// for a name taken from RVOR_DEVICE begins "RVOR_DEVICE=<name>: ", so that the caller's user
// knows where the name came from.
std::unique_ptr<Propagator> make_default_propagator();

}  // namespace rvor
