// The straight dual's own consistency (rvor/dual.h): in rvor_core, as the writers of rvor_io and
// rvor_dual both check the duals they are given.
#include <string>

#include "rvor/dual.h"
#include "rvor/error.h"

namespace rvor {

std::array<int32_t, 4> StraightDual::top_simplex(std::size_t t) const {
  if (t >= top_count())
    throw Error("top_simplex: simplex " + std::to_string(t) + " of a dual of " +
                std::to_string(top_count()));
  if (dimension == 3) return tetrahedra[t];
  return {triangles[t][0], triangles[t][1], triangles[t][2], -1};
}

namespace {

template <std::size_t N>
void require_vertices_of(const std::vector<std::array<int32_t, N>>& simplices, std::size_t vertices,
                         const char* what, const std::string& where) {
  for (std::size_t s = 0; s < simplices.size(); ++s)
    for (const int32_t v : simplices[s])
      if (v < 0 || static_cast<std::size_t>(v) >= vertices)
        throw Error(where + ": " + what + " " + std::to_string(s) + " uses vertex " +
                    std::to_string(v) + ", not one of the dual's " + std::to_string(vertices));
}

}  // namespace

void require_consistent_dual(const StraightDual& dual, const std::string& where) {
  if (dual.dimension != 2 && dual.dimension != 3)
    throw Error(where + ": a dual of dimension " + std::to_string(dual.dimension));
  if (dual.quality.size() != dual.top_count() || dual.flags.size() != dual.top_count())
    throw Error(where + ": the dual has " + std::to_string(dual.top_count()) +
                " top simplices but " + std::to_string(dual.quality.size()) + " quality and " +
                std::to_string(dual.flags.size()) + " flags entries");
  const std::size_t n = dual.vertices.size();
  require_vertices_of(dual.edges, n, "edge", where);
  require_vertices_of(dual.triangles, n, "triangle", where);
  require_vertices_of(dual.tetrahedra, n, "tetrahedron", where);
}

}  // namespace rvor
