#pragma once
// A picture of a 2D result: each Voronoi cell in its own colour, shaded by distance to its seed
// (iso-distance bands show the metric's anisotropy), with the seeds and optionally the straight
// dual (dark straight segments) and the curved dual's edges (red geodesic polylines) drawn over
// it. Written with cairo, atomically.
#include <string>
#include <vector>

#include "rvor/canvas.h"
#include "rvor/propagation.h"

namespace rvor {

struct StraightDual;
struct CurvedDual;

// Throws rvor::Error for 3D canvases. One canvas voxel becomes `pixels_per_voxel`^2 pixels
// (0 = choose so the longest side is about 1024 pixels). `dual` and `curved` may be null.
void write_canvas_png(const std::string& path, const Canvas& canvas, const VoronoiField& field,
                      const std::vector<Vec3>& seeds, const StraightDual* dual,
                      const CurvedDual* curved = nullptr, int pixels_per_voxel = 0);

}  // namespace rvor
