#pragma once
// A picture of a 2D result: each Voronoi cell in its own colour, shaded by distance to its seed
// (iso-distance bands show the metric's anisotropy), with the seeds and optionally the straight
// dual (dark straight segments) and the curved dual's edges (red geodesic polylines) drawn over
// it. Written with cairo, atomically.
#include <array>
#include <string>
#include <vector>

#include "rvor/canvas.h"
#include "rvor/propagation.h"

namespace rvor {

struct StraightDual;
struct CurvedDual;

// The longest side cairo draws a picture with (its MAX_IMAGE_SIZE): a longer one cannot be made.
constexpr int kLargestPngSide = 32767;

// The picture's width and height in pixels for a 2D canvas: `pixels_per_voxel` per voxel side (0 =
// about 1024 pixels along the longest side, at least one per voxel).
std::array<long long, 2> canvas_png_size(const Canvas& canvas, int pixels_per_voxel = 0);

// Throws rvor::Error (prefixed with `where`) where that picture has a side over kLargestPngSide.
// Known once the canvas is built, so a caller can refuse the picture before computing the field.
void require_drawable_png(const Canvas& canvas, int pixels_per_voxel, const std::string& where);

// Throws rvor::Error for 3D canvases and pictures with a side over kLargestPngSide. One canvas
// voxel becomes `pixels_per_voxel`^2 pixels (0 = choose so the longest side is about 1024 pixels).
// `dual` and `curved` may be null.
void write_canvas_png(const std::string& path, const Canvas& canvas, const VoronoiField& field,
                      const std::vector<Vec3>& seeds, const StraightDual* dual,
                      const CurvedDual* curved = nullptr, int pixels_per_voxel = 0);

}  // namespace rvor
