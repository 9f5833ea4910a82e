#include "commands.h"

namespace rvor::cli {

// Placeholder until the OpenCL engine lands.
void add_bench_command(CLI::App& app) {
  app.add_subcommand("bench", "Measure propagation throughput (voxel updates per second)");
}

}  // namespace rvor::cli
