#pragma once
// Canvas outputs for people: the labeled canvas as a VTK .vtu (ParaView) and probe samples.
#include <string>
#include <vector>

#include "rvor/canvas.h"
#include "rvor/propagation.h"

namespace rvor {

// The integer type of a .vtu's connectivity and offsets: Int32 wherever they fit (cells times
// corners below 2^31: a third less to write than Int64), else Int64; or Int64 always.
enum class VtuIndices { narrowest, int64 };

// Active voxels as VTK_VOXEL cells with cell data `label` (int) and `distance` (float);
// binary appended data. Atomic.
void write_canvas_vtu(const std::string& path, const Canvas& canvas, const VoronoiField& field,
                      VtuIndices indices = VtuIndices::narrowest);

struct ProbeSample {
  Vec3 query;         // the probe point as given
  Vec3 voxel_centre;  // centre of the nearest active voxel
  float distance;
  int label;
};
// For each point, the nearest active voxel to the point itself (by distance in index space; in 2D
// z is ignored), wherever it lies: a point beyond a billion voxels from the canvas is taken that
// far along the same direction. Of equally near voxels, the one nearest the rounded point.
std::vector<ProbeSample> probe_field(const Canvas& canvas, const VoronoiField& field,
                                     const std::vector<Vec3>& points);
// CSV with header x,y,z,distance,label (x,y,z = the voxel centre). Atomic.
void write_probe_csv(const std::string& path, const std::vector<ProbeSample>& samples);

}  // namespace rvor
