#include "support/limited_child.h"

#include <sys/wait.h>
#include <unistd.h>

#include <cstdio>

namespace rvor::test {

int exit_code_in_a_child(rlim_t limit_above_now, const std::function<bool()>& child) {
  const pid_t pid = fork();
  if (pid < 0) return -1;
  if (pid == 0) {
    long pages = 0;
    if (FILE* statm = std::fopen("/proc/self/statm", "r")) {
      if (std::fscanf(statm, "%ld", &pages) != 1) pages = 0;
      std::fclose(statm);
    }
    const rlim_t limit = static_cast<rlim_t>(pages) * sysconf(_SC_PAGESIZE) + limit_above_now;
    const rlimit address_space{limit, limit};
    if (pages == 0 || setrlimit(RLIMIT_AS, &address_space) != 0) _exit(255);
    try {
      _exit(child() ? 0 : 1);
    } catch (...) {  // unwinding past here would run the rest of the suite in the child
      _exit(2);
    }
  }
  int status = 0;
  if (waitpid(pid, &status, 0) != pid) return -1;
  return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
}

}  // namespace rvor::test
