// The checks every dual entry point makes of what the caller passes (dual_internal.h).
#include <string>

#include "dual/dual_internal.h"
#include "rvor/error.h"
#include "rvor/seeds.h"

namespace rvor::dual {

namespace {

void require_simplices(const std::vector<NerveSimplex>& simplices, int vertex_count,
                       std::size_t seed_count, const std::string& who) {
  for (const NerveSimplex& s : simplices) {
    bool named = s.vertex_count == vertex_count;
    for (int v = 0; v < vertex_count && named; ++v)
      named = s.seeds[v] >= 0 && static_cast<std::size_t>(s.seeds[v]) < seed_count;
    if (!named) {
      std::string listed;
      for (int v = 0; v < 4 && s.seeds[v] != -1; ++v)
        listed += (v ? ", " : "") + std::to_string(s.seeds[v]);
      throw Error(who + ": a nerve simplex (" + listed + ") does not name " +
                  std::to_string(vertex_count) + " of the " + std::to_string(seed_count) +
                  " seeds");
    }
  }
}

}  // namespace

std::vector<Vec3> checked_dual_seeds(const Canvas& canvas, const Nerve& nerve,
                                     const std::vector<Vec3>& seeds, const std::string& who) {
  if (nerve.seed_count != seeds.size() || nerve.dimension != canvas.dimension)
    throw Error(who + ": the nerve was extracted for " + std::to_string(nerve.seed_count) +
                " seeds in " + std::to_string(nerve.dimension) + "D, not " +
                std::to_string(seeds.size()) + " in " + std::to_string(canvas.dimension) + "D");
  require_simplices(nerve.edges, 2, seeds.size(), who);
  require_simplices(nerve.triangles, 3, seeds.size(), who);
  require_simplices(nerve.tetrahedra, 4, seeds.size(), who);
  // As the propagators check them, with the position ("dual: seed 1 is not in an active voxel",
  // under another entry point's name, was all the local fields said).
  if (!seeds.empty())
    validate_seeds(canvas, seeds, 0,
                   [&](std::size_t n) { return who + ": seed " + std::to_string(n); });
  std::vector<Vec3> planar = seeds;
  if (canvas.dimension == 2)
    for (Vec3& seed : planar) seed.z() = 0.0;  // as the propagators read a 2D seed
  return planar;
}

}  // namespace rvor::dual
