// The rvor command-line tool: sub-commands in *_command.cpp; every error becomes one line on
// stderr and a non-zero exit code.
#include <exception>
#include <iostream>

#include "commands.h"

int main(int argc, char** argv) {
  CLI::App app{"rvor: Riemannian Voronoi diagrams and Delaunay duals on sparse canvases"};
  app.require_subcommand(1);
  rvor::cli::add_voronoi_command(app);
  rvor::cli::add_devices_command(app);
  rvor::cli::add_bench_command(app);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e);
  } catch (const std::exception& e) {
    std::cerr << "rvor: error: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
