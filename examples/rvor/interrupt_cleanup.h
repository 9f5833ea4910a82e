#pragma once
// A run interrupted by SIGINT, SIGTERM or SIGHUP (Ctrl-C, `timeout`, a closed terminal) removes
// its staging directory, and the output directory when the run created it and it is empty, before
// it dies of the signal; otherwise they stayed until a later run into the same --out.
#include <string>

namespace rvor::cli {

class InterruptCleanup {
 public:
  // Installs the handlers for `staging` (a directory of plain files) and `created_dir` ("" when
  // the output directory was there before). One at a time per process.
  InterruptCleanup(const std::string& staging, const std::string& created_dir);
  InterruptCleanup(const InterruptCleanup&) = delete;
  InterruptCleanup& operator=(const InterruptCleanup&) = delete;
  ~InterruptCleanup();  // restores the handlers, then raises a signal that hold() kept

  // From now on a signal waits until destruction: the outputs are being published, which must
  // finish rather than leave half a set.
  void hold();
};

}  // namespace rvor::cli
