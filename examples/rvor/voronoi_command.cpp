#include "commands.h"

namespace rvor::cli {

void add_voronoi_command(CLI::App& app) {
  app.add_subcommand("voronoi", "Compute a Riemannian Voronoi diagram on a canvas");
}

}  // namespace rvor::cli
