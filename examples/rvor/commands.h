#pragma once
// Sub-commands of the rvor tool. Each add_*_command registers its options on `app` and a
// callback that runs the job; errors propagate as exceptions to main(), which prints one line.
#include <CLI/CLI.hpp>

namespace rvor::cli {

void add_voronoi_command(CLI::App& app);
void add_devices_command(CLI::App& app);
void add_bench_command(CLI::App& app);

}  // namespace rvor::cli
