#pragma once
// Runs a command line through the shell and captures its exit status, stdout and stderr.
#include <string>

namespace rvor::test {

struct CommandResult {
  int exit_code = -1;  // the process's exit status; 128 + N when killed by signal N
  std::string out, err;
};

CommandResult run_command(const std::string& command_line);
// Path of the built rvor tool.
std::string rvor_binary();
// Debian's interpreter, where python3-vtk9 and python3-meshio are installed (the `python3` on PATH
// may be another installation without them), as a command prefix that ignores the user's own
// packages.
std::string debian_python();
// Writes `script` to script_path and runs it with debian_python(), followed by `arguments`.
CommandResult run_python_script(const std::string& script_path, const std::string& script,
                                const std::string& arguments);

}  // namespace rvor::test
