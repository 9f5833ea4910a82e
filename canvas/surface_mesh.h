#pragma once
// Closed triangle meshes bounding `mesh:FILE` domains (private to rvor_canvas).
#include <array>
#include <string>
#include <vector>

#include "rvor/metric_field.h"

namespace rvor {

struct SurfaceMesh {
  std::vector<Vec3> vertices;
  std::vector<std::array<int, 3>> triangles;  // polygons are fan-triangulated
};

// Reads .off, .obj or .stl (ASCII or binary) by extension. STL vertices are welded by exact
// position. Throws rvor::Error naming the file (and line, for text formats) on malformed input.
SurfaceMesh read_surface_mesh(const std::string& path);

// Throws rvor::Error unless every edge is shared by exactly two triangles (and there is at least
// one triangle): only closed surfaces bound a volume.
void require_closed(const SurfaceMesh& mesh, const std::string& path);

Box bounds_of(const SurfaceMesh& mesh);

}  // namespace rvor
