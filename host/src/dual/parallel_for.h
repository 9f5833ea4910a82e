#pragma once
// Runs f(i) for i in [0, count) on up to hardware_concurrency threads, and at most `max_threads`
// (work shared through an atomic counter; at least `per_thread` items per extra thread, so small
// jobs stay on the caller). The first exception is rethrown on the calling thread once all
// threads have stopped.
#include <algorithm>
#include <atomic>
#include <cstddef>
#include <exception>
#include <limits>
#include <mutex>
#include <thread>
#include <vector>

#include "joining_threads.h"

namespace rvor::detail {

template <typename F>
void parallel_for(std::size_t count, std::size_t per_thread, F&& f,
                  std::size_t max_threads = std::numeric_limits<std::size_t>::max()) {
  std::atomic<std::size_t> next{0};
  std::mutex error_mutex;
  std::exception_ptr error;
  auto work = [&] {
    try {
      for (std::size_t i; (i = next.fetch_add(1)) < count;) f(i);
    } catch (...) {
      const std::lock_guard<std::mutex> lock(error_mutex);
      if (!error) error = std::current_exception();
      next = count;
    }
  };
  const std::size_t threads = std::max<std::size_t>(
      1, std::min({std::size_t{std::max(1u, std::thread::hardware_concurrency())},
                   count / std::max<std::size_t>(1, per_thread), max_threads}));
  {
    JoiningThreads pool;  // a thread that cannot start leaves its share to the others
    for (std::size_t t = 1; t < threads && pool.start(work); ++t) {
    }
    work();
  }
  if (error) std::rethrow_exception(error);
}

}  // namespace rvor::detail
