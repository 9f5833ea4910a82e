// The rvor command-line tool: sub-commands in *_command.cpp; every error becomes one line on
// stderr and a non-zero exit code.
#include <csignal>
#include <exception>
#include <iostream>
#include <new>
#include <string>

#include "commands.h"
#include "interrupt_cleanup.h"
#include "rvor/devices.h"
#include "rvor/input_file.h"
#include "rvor/spec_text.h"
#include "terminal.h"

int main(int argc, char** argv) {
  rvor::cli::record_ignored_signals();  // before OpenCL's LLVM installs its handlers
  // Past a file size limit the kernel sends SIGXFSZ, whose default kills the process: ignored, the
  // write fails with EFBIG and the writer reports it, naming the file.
  std::signal(SIGXFSZ, SIG_IGN);
  const std::string pocl_cache = rvor::pocl_kernel_cache_directory();
  rvor::cli::report_aborts(
      rvor::printable_text("the run aborted in a library it calls (its own message is above); "
                           "PoCL aborts so on a damaged kernel cache: remove PoCL's, " +
                           pocl_cache + ", and run again, or use --device cpu"),
      rvor::printable_text("a library it calls ended the run (its own message is above); an "
                           "'LLVM ERROR' on output is PoCL's compiler failing to write its kernel "
                           "cache, " +
                           pocl_cache +
                           " (a full disk, a quota or a file size limit): free space there or set "
                           "POCL_CACHE_DIR elsewhere, or use --device cpu"));
  rvor::set_fifo_wait_notice(rvor::cli::print_fifo_wait);
  CLI::App app{"rvor: Riemannian Voronoi diagrams and Delaunay duals on sparse canvases"};
  app.require_subcommand(1);
  app.set_version_flag("--version", "rvor " RVOR_VERSION);
  app.footer(
      "Examples:\n"
      "  rvor voronoi --domain box:-1,-1,-1,1,1,1 --metric hyperbolic_shock --resolution 96 \\\n"
      "               --random-seeds 300 --dual straight --vtu --out out/demo\n"
      "  rvor voronoi --domain rect:-1,-1,1,1 --metric swirl --random-seeds 100 --png --out "
      "out/swirl\n"
      "  rvor devices\n"
      "  rvor bench --resolution 64 --seeds 1000\n"
      "Run `rvor SUBCOMMAND --help` for every option of a sub-command. Errors: one line on "
      "stderr,\n"
      "exit code 1.");
  rvor::cli::add_voronoi_command(app);
  rvor::cli::add_devices_command(app);
  rvor::cli::add_bench_command(app);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    if (e.get_exit_code() == 0) return app.exit(e);  // --help
    std::cerr << "rvor: error: "
              << rvor::printable_text(rvor::cli::parse_error_text(app, e, argc, argv)) << "\n";
    return 1;
  } catch (const std::bad_alloc&) {
    // What ran out is memory the estimates did not foresee (they check the canvas against
    // --memory-budget): say so, rather than "std::bad_alloc".
    std::cerr << "rvor: error: out of memory (std::bad_alloc): the run needs more memory than "
                 "this process may use; lower --resolution or the seed count, or free memory\n";
    return 1;
  } catch (const std::exception& e) {
    // What the user typed (a spec, a path, $RVOR_DEVICE) is echoed in errors: its escape
    // sequences are shown, not obeyed by the terminal.
    std::cerr << "rvor: error: " << rvor::printable_text(rvor::cli::one_line(e.what())) << "\n";
    return 1;
  }
  return 0;
}
