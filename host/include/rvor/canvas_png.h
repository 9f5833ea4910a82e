#pragma once
// A picture of a 2D result: each Voronoi cell in its own colour, shaded by distance to its seed
// (iso-distance bands show the metric's anisotropy), with the seeds and optionally the straight
// dual drawn over it. Written with cairo, atomically.
#include <string>
#include <vector>

#include "rvor/canvas.h"
#include "rvor/propagation.h"

namespace rvor {

struct StraightDual;

// Throws rvor::Error for 3D canvases. One canvas voxel becomes `pixels_per_voxel`^2 pixels
// (0 = choose so the longest side is about 1024 pixels). `dual` may be null.
void write_canvas_png(const std::string& path, const Canvas& canvas, const VoronoiField& field,
                      const std::vector<Vec3>& seeds, const StraightDual* dual,
                      int pixels_per_voxel = 0);

}  // namespace rvor
