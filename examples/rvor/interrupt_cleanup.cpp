#include "interrupt_cleanup.h"

#include <fcntl.h>
#include <signal.h>
#include <sys/syscall.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <climits>
#include <cstdlib>
#include <cstring>

#include "rvor/error.h"

namespace rvor::cli {

namespace {

constexpr int kSignals[] = {SIGINT, SIGTERM, SIGHUP};

// What the handler removes, in storage it can read without allocating.
char staging_path[PATH_MAX];
char created_paths[InterruptCleanup::kMostCreatedFolders][PATH_MAX];  // innermost first
volatile sig_atomic_t created_count = 0;
volatile sig_atomic_t armed = 0;  // an InterruptCleanup is live: the paths above are its
// report_aborts()'s lines, "rvor: error: ...\n", written by the SIGABRT handler and at exit().
char abort_message[2048], exit_message[2048];
std::size_t abort_message_size = 0, exit_message_size = 0;
struct sigaction previous[sizeof kSignals / sizeof *kSignals];
// hold(): a signal is kept in `pending` rather than acted on. (sigprocmask would block it for the
// calling thread only, and PoCL's and TBB's threads can take it.)
volatile sig_atomic_t holding = 0, pending = 0;
volatile sig_atomic_t progress_line_open = 0;  // set_progress_line_open
std::atomic_flag cleaning = ATOMIC_FLAG_INIT;  // lock-free, so a handler may use it

// A getdents64 record (the libc wrapper, readdir, allocates; a handler may not): inode and offset
// (8 bytes each), the record's length (2), the entry's type (1), then its name.
constexpr int kRecordLengthAt = 16, kNameAt = 19;

// Only async-signal-safe calls: open, getdents64, unlinkat, close, rmdir.
void remove_staging() {
  if (!armed) return;
  const int dir = open(staging_path, O_RDONLY | O_DIRECTORY);
  if (dir >= 0) {
    alignas(8) char buffer[4096];
    for (long read; (read = syscall(SYS_getdents64, dir, buffer, sizeof buffer)) > 0;)
      for (long at = 0; at < read;) {
        const char* name = buffer + at + kNameAt;
        if (std::strcmp(name, ".") != 0 && std::strcmp(name, "..") != 0) unlinkat(dir, name, 0);
        unsigned short length;
        std::memcpy(&length, buffer + at + kRecordLengthAt, sizeof length);
        at += length;
      }
    close(dir);
    rmdir(staging_path);
  }
  for (int n = 0; n < created_count; ++n) rmdir(created_paths[n]);  // only when empty
}

void write_to_stderr(const char* text, std::size_t size) {
  [[maybe_unused]] const ssize_t written =  // nothing more to do where stderr is gone
      write(STDERR_FILENO, text, size);
}

// Only async-signal-safe calls: those of remove_staging, write, sigaction, raise.
void remove_staging_and_die(int signal_number) {
  if (holding) {
    pending = signal_number;
    return;
  }
  // `timeout` signals the process and then its group: the second signal can reach another thread
  // while the first cleans, and must wait for it rather than kill the process midway.
  if (cleaning.test_and_set())
    for (;;) pause();
  remove_staging();
  if (progress_line_open) {
    constexpr char kInterrupted[] = " interrupted\n";
    write_to_stderr(kInterrupted, sizeof kInterrupted - 1);
  }
  // Death by this signal, as without the handler: the default action, pending until the handler
  // returns (the signal is blocked while it runs).
  struct sigaction default_action {};
  default_action.sa_handler = SIG_DFL;
  sigaction(signal_number, &default_action, nullptr);
  raise(signal_number);
}

// Only async-signal-safe calls: those of remove_staging, write, _exit. A second abort (another
// thread's) waits for the first, which ends the process.
void report_abort_and_exit(int) {
  if (cleaning.test_and_set())
    for (;;) pause();
  if (!holding) remove_staging();  // while publishing, the set may be half moved: left to the user
  if (progress_line_open) {
    constexpr char kFailed[] = " failed\n";
    write_to_stderr(kFailed, sizeof kFailed - 1);
  }
  write_to_stderr(abort_message, abort_message_size);
  _exit(1);
}

// record_ignored_signals(): which of kSignals were ignored when the process started.
bool ignored_at_start[sizeof kSignals / sizeof *kSignals] = {};

void copy_path(const std::string& path, char (&into)[PATH_MAX]) {
  if (path.size() >= PATH_MAX) throw Error("output path too long: " + path);
  std::memcpy(into, path.c_str(), path.size() + 1);
}

}  // namespace

namespace {

std::size_t copy_error_line(const std::string& message, char (&into)[2048]) {
  const std::string line = "rvor: error: " + message + "\n";
  const std::size_t size = std::min(line.size(), sizeof into - 1);
  std::memcpy(into, line.data(), size);
  into[size - 1] = '\n';  // also where the message was cut
  return size;
}

// At exit() (LLVM's fatal errors, "LLVM ERROR: IO failure on output stream: No space left on
// device" from PoCL's compiler, call it with code 1): a run still under way cleans up as for an
// abort; a run that ended normally has destroyed its InterruptCleanup, and this does nothing.
void report_exit_midrun() {
  if (!armed || holding || cleaning.test_and_set()) return;
  remove_staging();
  if (progress_line_open) {
    constexpr char kFailed[] = " failed\n";
    write_to_stderr(kFailed, sizeof kFailed - 1);
  }
  write_to_stderr(exit_message, exit_message_size);
}

}  // namespace

void report_aborts(const std::string& on_abort, const std::string& on_exit) {
  abort_message_size = copy_error_line(on_abort, abort_message);
  exit_message_size = copy_error_line(on_exit, exit_message);
  std::atexit(report_exit_midrun);
  keep_reporting_aborts();
}

void keep_reporting_aborts() {
  if (abort_message_size == 0) return;  // report_aborts() was not called
  struct sigaction action {};
  action.sa_handler = report_abort_and_exit;
  sigemptyset(&action.sa_mask);
  for (int s : kSignals) sigaddset(&action.sa_mask, s);  // not an interrupt's cleanup as well
  sigaction(SIGABRT, &action, nullptr);
}

void set_progress_line_open(bool open) {
  progress_line_open = open ? 1 : 0;
}

void record_ignored_signals() {
  for (std::size_t n = 0; n < sizeof kSignals / sizeof *kSignals; ++n) {
    struct sigaction now {};
    ignored_at_start[n] = sigaction(kSignals[n], nullptr, &now) == 0 && now.sa_handler == SIG_IGN;
  }
}

InterruptCleanup::InterruptCleanup(const std::string& staging,
                                   const std::vector<std::string>& created_folders) {
  copy_path(staging, staging_path);
  created_count = 0;
  for (auto folder = created_folders.rbegin();
       folder != created_folders.rend() && created_count < kMostCreatedFolders; ++folder)
    copy_path(*folder, created_paths[created_count++]);
  holding = pending = 0;
  cleaning.clear();
  armed = 1;
  keep_reporting_aborts();  // the OpenCL device has been looked up: LLVM's handler is in its place
  struct sigaction action {};
  action.sa_handler = remove_staging_and_die;
  sigemptyset(&action.sa_mask);
  for (int s : kSignals) sigaddset(&action.sa_mask, s);  // one cleanup at a time
  for (std::size_t n = 0; n < sizeof kSignals / sizeof *kSignals; ++n) {
    sigaction(kSignals[n], nullptr, &previous[n]);
    // A signal the caller ignores (nohup) stays ignored, also where PoCL's LLVM has put its own
    // handler in SIG_IGN's place since.
    if (previous[n].sa_handler != SIG_IGN && !ignored_at_start[n])
      sigaction(kSignals[n], &action, nullptr);
  }
}

void InterruptCleanup::hold() {
  holding = 1;
}

InterruptCleanup::~InterruptCleanup() {
  armed = 0;
  for (std::size_t n = 0; n < sizeof kSignals / sizeof *kSignals; ++n)
    sigaction(kSignals[n], &previous[n], nullptr);
  if (pending != 0) raise(pending);  // held during publication: acted on now, as its old handler
}

}  // namespace rvor::cli
