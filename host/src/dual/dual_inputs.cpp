// The checks every dual entry point makes of what the caller passes (dual_internal.h).
#include <cstdint>
#include <string>

#include "dual/dual_internal.h"
#include "rvor/error.h"
#include "rvor/seeds.h"

namespace rvor::dual {

namespace {

// A witness's slot is read (its metric) by the duals: -1 (none) or a slot of the canvas. A
// hand-made or altered nerve with a slot past the canvas crashed them.
bool witness_in_canvas(const Witness& witness, std::size_t slot_count) {
  return witness.slot >= -1 && witness.slot < static_cast<std::int64_t>(slot_count);
}

void require_simplices(const std::vector<NerveSimplex>& simplices, int vertex_count,
                       std::size_t seed_count, std::size_t slot_count, const std::string& who) {
  for (const NerveSimplex& s : simplices) {
    if (!witness_in_canvas(s.farthest, slot_count) || !witness_in_canvas(s.nearest, slot_count))
      throw Error(who + ": a nerve simplex of seeds " + std::to_string(s.seeds[0]) + ", " +
                  std::to_string(s.seeds[1]) + "... has a witness at slot " +
                  std::to_string(witness_in_canvas(s.farthest, slot_count) ? s.nearest.slot
                                                                           : s.farthest.slot) +
                  ", not in the canvas (" + std::to_string(slot_count) +
                  " slots): the nerve was extracted from another canvas, or altered");
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
  require_simplices(nerve.edges, 2, seeds.size(), canvas.slot_count(), who);
  require_simplices(nerve.triangles, 3, seeds.size(), canvas.slot_count(), who);
  require_simplices(nerve.tetrahedra, 4, seeds.size(), canvas.slot_count(), who);
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
