// VoronoiSession (rvor/voronoi_session.h): a field and its propagator, kept together.
#include "rvor/voronoi_session.h"

#include <utility>

#include "one_call_at_a_time.h"
#include "rvor/error.h"

namespace rvor {

namespace {

// The session's seeds and field change before its propagator runs (the propagator refuses a call
// that overlaps another, but two insertions had appended to one seed list by then: seeds() no
// longer matched field()), so overlapping calls are refused first, here.
OneCallAtATime one_call_on(std::atomic<bool>& busy) {
  return OneCallAtATime(busy, "the VoronoiSession", "session");
}

}  // namespace

VoronoiSession::VoronoiSession(std::unique_ptr<Propagator> propagator)
    : propagator_(std::move(propagator)), busy_(std::make_unique<std::atomic<bool>>(false)) {
  if (!propagator_) throw Error("VoronoiSession: no propagator");
}

PropagationStats VoronoiSession::solve(const Canvas& canvas, std::vector<Vec3> seeds) {
  const OneCallAtATime exclusive = one_call_on(*busy_);
  return solve_alone(canvas, std::move(seeds));
}

PropagationStats VoronoiSession::solve_alone(const Canvas& canvas, std::vector<Vec3> seeds) {
  solved_ = returned_last_ = false;
  try {
    const PropagationStats stats = propagator_->solve(canvas, seeds, field_);
    seeds_ = std::move(seeds);
    solved_ = returned_last_ = true;
    solved_canvas_ = canvas.content_hash();
    return stats;
  } catch (...) {
    // What field_ holds now is neither the last solve's nor this one's: nothing is shown.
    seeds_.clear();
    field_ = VoronoiField{};
    throw;
  }
}

PropagationStats VoronoiSession::insert(const Canvas& canvas, const std::vector<Vec3>& new_seeds) {
  const OneCallAtATime exclusive = one_call_on(*busy_);
  return insert_alone(canvas, new_seeds);
}

PropagationStats VoronoiSession::insert_alone(const Canvas& canvas,
                                              const std::vector<Vec3>& new_seeds) {
  if (!solved_) throw Error("VoronoiSession::insert(): no solved field yet (call solve() first)");
  if (&new_seeds == &seeds_)
    return insert_alone(canvas, std::vector<Vec3>(new_seeds));  // seeds() again
  if (!solved_canvas_ || canvas.content_hash() != solved_canvas_) {
    // Continued on a changed canvas, the field kept values no solve there gives (256 of 4096
    // labels differed, the canvas's metric changed in place between the calls).
    std::vector<Vec3> all = seeds_;
    all.insert(all.end(), new_seeds.begin(), new_seeds.end());
    return solve_alone(canvas, std::move(all));
  }
  const std::size_t first_new = seeds_.size();
  // Appended in place (no copy of 100 000 seeds per insertion), taken back if the call fails.
  seeds_.insert(seeds_.end(), new_seeds.begin(), new_seeds.end());
  const bool returned_last = std::exchange(returned_last_, false);
  try {
    const PropagationStats stats =
        returned_last ? propagator_->insert_returned(canvas, seeds_, first_new, field_)
                      : propagator_->insert(canvas, seeds_, first_new, field_);
    returned_last_ = true;
    return stats;
  } catch (...) {
    seeds_.resize(first_new);
    throw;
  }
}

}  // namespace rvor
