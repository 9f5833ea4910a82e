#pragma once
// Work that can kill its process, done first in a forked child (private to the canvas library):
// OpenVDB's reader trusts sizes inside a file's voxel data, and damaged data corrupted its heap.
#include <chrono>
#include <functional>
#include <string>

namespace rvor {

// How the child's work ended.
struct ChildEnd {
  enum class How {
    reported,  // the work called its report: `text` holds what it said ("" for success)
    died,      // the child died before reporting: `text` says of what ("SIGSEGV", ...)
    unknown,   // no child could tell: none could be made, or it was not done by the deadline
  };
  How how = How::unknown;
  std::string text;
};

// Hands the work its report: the child sends `text` to the parent and exits at once, with no
// destructor, atexit handler or stdio flush run in it.
using ChildReport = std::function<void(const std::string& text)>;

// Runs `work` in a forked child process and waits for its report, at most until `deadline`
// (then the child is killed: How::unknown). The child's stderr goes to /dev/null and it leaves no
// core file; it dies with the caller. Work that returns without reporting counts as unknown.
// Beware: a fork copies only the calling thread, so the work must not wait on locks another
// thread of the caller may hold (the report lets it exit without destroying what it built).
ChildEnd end_of_child(const std::function<void(const ChildReport&)>& work,
                      std::chrono::steady_clock::time_point deadline);

}  // namespace rvor
