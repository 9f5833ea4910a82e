#include "child_check.h"

#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <sys/prctl.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <optional>

namespace rvor {

namespace {

// The report's first byte: a report follows; an end of file before it means the child died.
constexpr char kReported = 'R';
constexpr char kReturned = '?';  // the work returned without reporting

void write_all(int fd, const std::string& bytes) {
  for (std::size_t done = 0; done < bytes.size();) {
    const ssize_t written = write(fd, bytes.data() + done, bytes.size() - done);
    if (written < 0 && errno == EINTR) continue;
    if (written <= 0) return;
    done += static_cast<std::size_t>(written);
  }
}

// The child's side: dies with the parent, quiet, no core file; reports through `fd`.
[[noreturn]] void run_child(const std::function<void(const ChildReport&)>& work, int fd,
                            pid_t parent) {
  prctl(PR_SET_PDEATHSIG, SIGKILL);
  if (getppid() != parent) _exit(0);  // the parent is already gone
  const rlimit no_core{0, 0};
  setrlimit(RLIMIT_CORE, &no_core);
  if (const int null = open("/dev/null", O_WRONLY); null >= 0) dup2(null, STDERR_FILENO);
  try {
    work([fd](const std::string& text) {
      write_all(fd, kReported + text);
      _exit(0);
    });
  } catch (...) {
  }
  write_all(fd, std::string(1, kReturned));
  _exit(0);
}

// The pipe's read end and the child, released however the parent leaves.
struct ChildHandle {
  int fd = -1;
  pid_t pid = -1;
  bool reaped = false;
  int status = 0;

  // Waits for the child's exit; false where its status cannot be had (SIGCHLD ignored, or reaped
  // by another handler of the caller's). Either way it is gone: its pid is no longer ours to kill.
  bool reap() {
    int result;
    do {
      result = waitpid(pid, &status, 0);
    } while (result < 0 && errno == EINTR);
    reaped = true;
    return result == pid;
  }

  ~ChildHandle() {
    if (fd >= 0) close(fd);
    if (pid > 0 && !reaped) {
      kill(pid, SIGKILL);
      reap();
    }
  }
};

// What the child wrote until it closed the pipe (by exiting), or nullopt past `deadline`.
std::optional<std::string> read_until_closed(int fd,
                                             std::chrono::steady_clock::time_point deadline) {
  std::string text;
  char buffer[512];
  for (;;) {
    const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(
        deadline - std::chrono::steady_clock::now());
    if (left.count() <= 0) return std::nullopt;
    pollfd ready{fd, POLLIN, 0};
    const int polled = poll(&ready, 1, static_cast<int>(std::min<long long>(left.count(), 1000)));
    if (polled < 0 && errno != EINTR) return std::nullopt;
    if (polled <= 0) continue;
    const ssize_t got = read(fd, buffer, sizeof buffer);
    if (got == 0) return text;
    if (got < 0 && errno != EINTR) return std::nullopt;
    if (got > 0) text.append(buffer, static_cast<std::size_t>(got));
  }
}

// "SIGSEGV", or what a kill by SIGKILL most likely was.
std::string signal_text(int signal) {
  if (signal == SIGKILL) return "killed (out of memory?)";
  const char* name = sigabbrev_np(signal);
  return name ? std::string("SIG") + name : "signal " + std::to_string(signal);
}

}  // namespace

ChildEnd end_of_child(const std::function<void(const ChildReport&)>& work,
                      std::chrono::steady_clock::time_point deadline) {
  int ends[2];
  if (pipe2(ends, O_CLOEXEC) != 0) return {};
  const pid_t parent = getpid();
  const pid_t pid = fork();
  if (pid == 0) {
    close(ends[0]);
    run_child(work, ends[1], parent);
  }
  close(ends[1]);
  ChildHandle child{ends[0], pid};
  if (pid < 0) return {};
  const std::optional<std::string> text = read_until_closed(child.fd, deadline);
  if (!text) return {};  // the handle kills and reaps it
  if (!text->empty() && (*text)[0] == kReported) {
    child.reap();
    return {ChildEnd::How::reported, text->substr(1)};
  }
  if (!text->empty()) {  // it returned without reporting
    child.reap();
    return {};
  }
  const bool reaped = child.reap();
  return {ChildEnd::How::died,
          reaped && WIFSIGNALED(child.status) ? signal_text(WTERMSIG(child.status)) : "it died"};
}

}  // namespace rvor
