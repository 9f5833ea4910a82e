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

// Throws rvor::Error when two triangles cross or touch other than along the vertices and edges
// they share (a self-intersecting surface, or separate sheets that touch): then the surface does
// not bound a volume and inside and outside are not defined (mesh_self_intersection.cpp).
void require_no_self_intersection(const SurfaceMesh& mesh, const std::string& path);

// The mesh's connected surfaces (triangles joined through shared vertices), each with its own
// vertices, in the order of their first triangles.
std::vector<SurfaceMesh> connected_surfaces(const SurfaceMesh& mesh);

Box bounds_of(const SurfaceMesh& mesh);

}  // namespace rvor
