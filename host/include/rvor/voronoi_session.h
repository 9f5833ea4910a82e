#pragma once
// A Voronoi field kept with its propagator for chains of insertions (farthest-point seeding,
// refinement): the session owns both, and callers read the field through field(), so no
// insertion has to make sure it continues the field the propagator returned last.
// (Propagator::insert reads every slot of a caller's field to make sure: 16.8M slots at 256^3,
// 3-5 ms on the 16 host cores of an NVIDIA H200 machine, as long as the insertion's rounds there.)
#include <atomic>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "rvor/propagation.h"

namespace rvor {

class VoronoiSession {
 public:
  // Throws rvor::Error for a null propagator.
  explicit VoronoiSession(std::unique_ptr<Propagator> propagator);

  // One call at a time, as its propagator: a solve() or insert() that overlaps another on the same
  // session (from another thread) throws rvor::Error and changes nothing; field() and seeds() are
  // not to be read while a call runs. Use one session per thread.

  // Solves `seeds` on `canvas` from scratch (Propagator::solve); seed i gets label i. After a
  // failed solve, seeds() and field() are empty and insert() refuses until a solve succeeds.
  PropagationStats solve(const Canvas& canvas, std::vector<Vec3> seeds);
  // Appends `new_seeds` to seeds() and propagates them into field() (Propagator::insert: the
  // result equals a solve with all seeds). On a canvas whose content differs from the last
  // solve()'s (Canvas::content_hash; changed in place, or another one), the field is no start for
  // an insertion, so all seeds are solved again (a failure then leaves the session as a failed
  // solve() does). Throws rvor::Error before any solve(); after a failed insertion the next one
  // checks the field as Propagator::insert does, or refuses it when the failure left it
  // unfinished.
  PropagationStats insert(const Canvas& canvas, const std::vector<Vec3>& new_seeds);

  const VoronoiField& field() const { return field_; }
  const std::vector<Vec3>& seeds() const { return seeds_; }
  std::string device_description() const { return propagator_->device_description(); }

 private:
  // solve() and insert() once the call is the session's only one.
  PropagationStats solve_alone(const Canvas& canvas, std::vector<Vec3> seeds);
  PropagationStats insert_alone(const Canvas& canvas, const std::vector<Vec3>& new_seeds);

  std::unique_ptr<Propagator> propagator_;
  std::vector<Vec3> seeds_;
  VoronoiField field_;
  bool solved_ = false;
  std::optional<std::uint64_t> solved_canvas_;  // the content hash of the last solve's canvas
  // field_ is, bit for bit, what the propagator returned last (false after a failed call).
  bool returned_last_ = false;
  // Set while a call runs; held apart so that a session can still be moved.
  std::unique_ptr<std::atomic<bool>> busy_;
};

}  // namespace rvor
