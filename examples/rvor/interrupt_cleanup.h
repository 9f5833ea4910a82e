#pragma once
// A run interrupted by SIGINT, SIGTERM or SIGHUP (Ctrl-C, `timeout`, a closed terminal) removes
// its staging directory, and the folders the run created for its output directory when they are
// empty, before it dies of the signal; otherwise they stayed until a later run into the same --out.
#include <string>
#include <vector>

namespace rvor::cli {

// Records which of the signals the caller ignores (nohup; a shell's background job), before
// anything else installs handlers: PoCL's LLVM replaces SIG_IGN with its own handlers when OpenCL
// starts, and a run under nohup then died of the terminal's SIGHUP. Call first in main().
void record_ignored_signals();

// An abort (SIGABRT: PoCL's assertions and its failed dlopen of a damaged kernel cache's .so, which
// left exit 134, PoCL's lines and the staging directory behind) removes what an interrupt does,
// ends the open progress line with " failed", prints `on_abort` as rvor's error line and exits with
// code 1. An exit() in the middle of a run (LLVM's fatal errors: a full disk under PoCL's cache)
// does the same with `on_exit`. Call once in main(), before OpenCL starts.
void report_aborts(const std::string& on_abort, const std::string& on_exit);
// Puts report_aborts()'s handler back: PoCL's LLVM installs its own for SIGABRT (which prints and
// dies) when OpenCL lists its devices. Call after that; InterruptCleanup calls it.
void keep_reporting_aborts();

// Whether a progress line is open on stderr (Progress sets it): a run stopped by a signal ends it
// with " interrupted", so that the shell's prompt does not land on it.
void set_progress_line_open(bool open);

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
