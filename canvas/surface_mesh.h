#pragma once
// Closed triangle meshes bounding `mesh:FILE` domains (private to rvor_canvas).
#include <array>
#include <string>
#include <vector>

#include "rvor/metric_field.h"

namespace rvor {

struct SurfaceMesh {
  std::vector<Vec3> vertices;
  std::vector<std::array<int, 3>> triangles;  // polygons are ear-clipped (add_polygon)
};

// Reads .off, .obj or .stl (ASCII or binary) by extension. STL vertices are welded by exact
// position. Throws rvor::Error naming the file (and line, for text formats) on malformed input.
SurfaceMesh read_surface_mesh(const std::string& path);

// Appends the triangles of a planar polygon (its vertex indices in order), ear-clipped in its
// plane so that a non-convex polygon stays inside its outline; repeated corners and triangles of
// zero area (a corner on a side) are left out (polygon_triangulation.cpp).
void add_polygon(SurfaceMesh& mesh, const std::vector<int>& polygon);

// Throws rvor::Error unless every edge is shared by exactly two triangles (and there is at least
// one triangle): only closed surfaces bound a volume.
void require_closed(const SurfaceMesh& mesh, const std::string& path);

// Throws rvor::Error when two triangles cross or touch other than along the vertices and edges
// they share (a self-intersecting surface, or separate sheets that touch): then the surface does
// not bound a volume and inside and outside are not defined (mesh_self_intersection.cpp).
void require_no_self_intersection(const SurfaceMesh& mesh, const std::string& path);

// Whether a closed surface without self-intersections (require_closed,
// require_no_self_intersection) bounds a convex solid: it is one connected, orientable sheet and
// every vertex lies on the inner side of every face's plane, to a hundredth of `voxel_size` or the
// rounding of 6-digit coordinates, at most a tenth of a voxel (mesh_convexity.cpp). Triangulated
// flat faces pass.
bool is_convex(const SurfaceMesh& mesh, double voxel_size);

// Voxels [i_begin, i_end) of the row (j, k) of an index box.
struct VoxelRun {
  int j, k, i_begin, i_end;
};

// The voxel centres of the index box `dims` (voxel (i, j, k) at origin + h (i, j, k)) that lie
// inside the mesh: those whose ray in +x crosses it an odd number of times. A surface nested in
// another bounds a cavity, and a pocket is outside however narrow its opening (the surfaces must
// not cross: require_no_self_intersection). Centres on the surface go either way.
std::vector<VoxelRun> inside_runs(const SurfaceMesh& mesh, const Vec3& origin, double h,
                                  const std::array<int, 3>& dims);

// "(x, y, z)", for messages about the mesh.
std::string point_text(const Vec3& p);

// The bounding box of the vertices the triangles use.
Box bounds_of(const SurfaceMesh& mesh);

}  // namespace rvor
