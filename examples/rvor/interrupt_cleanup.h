#pragma once
// A run interrupted by SIGINT, SIGTERM or SIGHUP (Ctrl-C, `timeout`, a closed terminal) removes
// its staging directory, and the folders the run created for its output directory when they are
// empty, before it dies of the signal; otherwise they stayed until a later run into the same --out.
#include <string>
#include <vector>

namespace rvor::cli {

class InterruptCleanup {
 public:
  static constexpr int kMostCreatedFolders = 8;
  // Installs the handlers for `staging` (a directory of plain files) and `created_folders` (the
  // folders created for the output directory, outermost first; none when it was there before; the
  // innermost kMostCreatedFolders at most). One at a time per process.
  InterruptCleanup(const std::string& staging, const std::vector<std::string>& created_folders);
  InterruptCleanup(const InterruptCleanup&) = delete;
  InterruptCleanup& operator=(const InterruptCleanup&) = delete;
  ~InterruptCleanup();  // restores the handlers, then raises a signal that hold() kept

  // From now on a signal waits until destruction: the outputs are being published, which must
  // finish rather than leave half a set.
  void hold();
};

}  // namespace rvor::cli
