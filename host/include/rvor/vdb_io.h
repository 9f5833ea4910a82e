#pragma once
// OpenVDB files: the Voronoi result (float grid `distance` with background +inf for unreached
// voxels, int grid `label` with background -1, world transform of
// the canvas) and metric fields as six float grids m11 m12 m22 m13 m23 m33.
#include <string>

#include "rvor/canvas.h"
#include "rvor/propagation.h"

namespace rvor {

void write_voronoi_vdb(const std::string& path, const Canvas& canvas, const VoronoiField& field);
// Reads back what write_voronoi_vdb wrote, onto the slots of `canvas` (tests, later stages).
VoronoiField read_voronoi_vdb(const std::string& path, const Canvas& canvas);
// Writes the canvas's per-voxel metric as six float grids (a file load_vdb_metric reads).
void write_metric_vdb(const std::string& path, const Canvas& canvas);

}  // namespace rvor
