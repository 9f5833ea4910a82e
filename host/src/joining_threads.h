#pragma once
// Worker threads that are joined when their group goes, and whose failure to start is no error
// (internal). A std::vector<std::thread> called std::terminate where a start failed after others
// had started (too many threads, RLIMIT_AS: the process aborted); here the caller does that
// share of the work itself.
#include <new>
#include <system_error>
#include <thread>
#include <utility>
#include <vector>

namespace rvor {

class JoiningThreads {
 public:
  JoiningThreads() = default;
  JoiningThreads(const JoiningThreads&) = delete;
  JoiningThreads& operator=(const JoiningThreads&) = delete;
  ~JoiningThreads() { join(); }

  // Starts f(args...) on a thread; false where none could be started (then nothing ran).
  template <typename F, typename... Args>
  bool start(F&& f, Args&&... args) {
    try {
      threads_.emplace_back(std::forward<F>(f), std::forward<Args>(args)...);
      return true;
    } catch (const std::system_error&) {
      return false;
    } catch (const std::bad_alloc&) {
      return false;
    }
  }

  void join() {
    for (std::thread& thread : threads_)
      if (thread.joinable()) thread.join();
  }

 private:
  std::vector<std::thread> threads_;
};

}  // namespace rvor
