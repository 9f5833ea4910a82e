#pragma once
// A propagator keeps its canvas, stencils and last field between calls, so two calls at once on
// one propagator would share them: from two threads the process crashed (SIGSEGV). The second of
// two overlapping calls is an rvor::Error instead; separate propagators run in parallel freely.
#include <atomic>
#include <string>

#include "rvor/error.h"

namespace rvor {

class OneCallAtATime {
 public:
  // `busy` is the object's flag; `what` names it in the error ("the CPU reference"), `kind` is
  // what it is ("propagator", "session").
  OneCallAtATime(std::atomic<bool>& busy, const std::string& what,
                 const std::string& kind = "propagator")
      : busy_(busy) {
    if (busy_.exchange(true, std::memory_order_acquire))
      throw Error(what + " was called while another call on it ran (from another thread): a " +
                  kind + " serves one call at a time; make one " + kind + " per thread");
  }
  OneCallAtATime(const OneCallAtATime&) = delete;
  OneCallAtATime& operator=(const OneCallAtATime&) = delete;
  ~OneCallAtATime() { busy_.store(false, std::memory_order_release); }

 private:
  std::atomic<bool>& busy_;
};

}  // namespace rvor
