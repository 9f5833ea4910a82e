#include "support/run_command.h"

#include <sys/wait.h>
#include <cstdlib>

#include "support/temp_dir.h"

namespace rvor::test {

CommandResult run_command(const std::string& command_line) {
  TempDir capture;
  const std::string out = capture.file("out"), err = capture.file("err");
  const int status = std::system((command_line + " >" + out + " 2>" + err + " </dev/null").c_str());
  CommandResult result;
  if (WIFEXITED(status))
    result.exit_code = WEXITSTATUS(status);
  else if (WIFSIGNALED(status))
    result.exit_code = 128 + WTERMSIG(status);
  result.out = read_text(out);
  result.err = read_text(err);
  return result;
}

std::string rvor_binary() {
  return std::string(RVOR_BINARY_DIR) + "/bin/rvor";
}

std::string debian_python() {
  // -s -E: without the user's site-packages and PYTHON* variables, whose packages would shadow
  // Debian's (a NumPy 2 installed with `pip install --user` broke Debian's meshio, and with it a
  // test of the dual's files).
  return "/usr/bin/python3 -s -E";
}

CommandResult run_python_script(const std::string& script_path, const std::string& script,
                                const std::string& arguments) {
  write_text(script_path, script);
  return run_command(debian_python() + " " + script_path + " " + arguments);
}

}  // namespace rvor::test
