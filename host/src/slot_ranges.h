#pragma once
// Work over a canvas's slots (or seeds) split into contiguous ranges, one thread each (internal):
// packing stencils, converting fields and the seed blocks' claims, which are independent per item.
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <exception>
#include <thread>
#include <vector>

#include "joining_threads.h"

namespace rvor {

// Threads for per-slot host work: the machine's, at most 16. (An insertion's check of the
// caller's field at 512^3 outlasted the rounds on the H200 machine's 16 cores by 23-31 ms on 8
// threads, 17-20 ms on 16: a temporary switch and timers, session 28, docs/scheme.md "Insertions
// on the GPU"; `rvor bench --checked-insert --resolution 512` shows the whole insertion.)
inline unsigned slot_threads() {
  return std::max(1u, std::min(16u, std::thread::hardware_concurrency()));
}

// Runs work(t, begin, end) on `threads` threads over [0, slots); rethrows the first error.
template <typename Work>
void for_slot_ranges(std::size_t slots, unsigned threads, Work&& work) {
  if (threads <= 1) return work(0u, std::size_t{0}, slots);  // no thread to start
  std::vector<std::exception_ptr> errors(threads);
  const auto range = [&](unsigned t) {
    try {
      work(t, slots * t / threads, slots * (t + 1) / threads);
    } catch (...) {
      errors[t] = std::current_exception();
    }
  };
  {
    JoiningThreads workers;
    for (unsigned t = 0; t < threads; ++t)
      if (!workers.start(range, t)) range(t);  // no thread: its range here
  }
  for (const std::exception_ptr& e : errors)
    if (e) std::rethrow_exception(e);
}

// Below this many slots per thread a range runs on the calling thread: starting threads costs
// more than the work (a canvas cropped around each seed of a curved dual is finalized inside
// a parallel loop already).
constexpr std::size_t kSlotsPerThread = std::size_t{1} << 16;

// range_result(begin, end) over contiguous ranges covering [0, slots), one per thread (at most
// slot_threads(), and one per kSlotsPerThread slots), in range order.
template <typename RangeResult>
auto over_slot_ranges(std::size_t slots, RangeResult&& range_result) {
  const unsigned threads = static_cast<unsigned>(
      std::min<std::size_t>(slot_threads(), std::max<std::size_t>(1, slots / kSlotsPerThread)));
  std::vector<decltype(range_result(std::size_t{0}, std::size_t{0}))> partial(threads);
  for_slot_ranges(slots, threads, [&](unsigned t, std::size_t begin, std::size_t end) {
    partial[t] = range_result(begin, end);
  });
  return partial;
}

// The sum, wrapping, of range_sum(begin, end) over contiguous ranges covering [0, slots), as
// over_slot_ranges splits them.
template <typename RangeSum>
std::uint64_t sum_over_slot_ranges(std::size_t slots, RangeSum&& range_sum) {
  std::uint64_t total = 0;
  for (std::uint64_t p : over_slot_ranges(slots, range_sum)) total += p;
  return total;
}

// The sum, wrapping, of term(slot) over [0, slots), as over_slot_ranges splits them.
template <typename Term>
std::uint64_t sum_over_slots(std::size_t slots, Term&& term) {
  return sum_over_slot_ranges(slots, [&](std::size_t begin, std::size_t end) {
    std::uint64_t sum = 0;
    for (std::size_t slot = begin; slot < end; ++slot) sum += term(slot);
    return sum;
  });
}

}  // namespace rvor
