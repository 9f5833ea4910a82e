#include "commands.h"

namespace rvor::cli {

// Placeholder until the OpenCL runtime lands: the command exists but lists nothing.
void add_devices_command(CLI::App& app) {
  app.add_subcommand("devices", "List the compute devices rvor can use");
}

}  // namespace rvor::cli
