#pragma once
// Curved faces of the dual (private to rvor_dual; method in rvor/curved_dual.h).
#include <vector>

#include "geodesic_tracer.h"
#include "rvor/curved_dual.h"
#include "rvor/nerve.h"

namespace rvor::detail {

// The geodesic patch of `triangle` (apex triangle.seeds[0]) from its curved opposite edge
// (seeds[1], seeds[2]). `tracer` must have local fields.
CurvedFace build_curved_face(const Canvas& canvas, const GeodesicTracer& tracer,
                             const NerveSimplex& triangle, const CurvedEdge& opposite,
                             const std::vector<Vec3>& seeds);

}  // namespace rvor::detail
