#pragma once
// OpenVDB helpers shared by the canvas library's .cpp files (private; includes OpenVDB, so only
// the few translation units that need it include this).
#include <functional>
#include <string>

#include <openvdb/openvdb.h>

#include "rvor/canvas.h"
#include "rvor/error.h"
#include "vdb_archive_check.h"

namespace rvor {

// Index space of every rvor VDB grid is the canvas's voxel index space: voxel (i,j,k) has its
// centre at origin + h (i,j,k), which is OpenVDB's cell-centred convention.
inline openvdb::math::Transform::Ptr canvas_transform(double voxel_size, const Vec3& origin) {
  auto transform = openvdb::math::Transform::createLinearTransform(voxel_size);
  transform->postTranslate(openvdb::Vec3d(origin.x(), origin.y(), origin.z()));
  return transform;
}

inline openvdb::Coord to_coord(const VoxelIndex& v) {
  return openvdb::Coord(v.i, v.j, v.k);
}

// "(x, y, z)", for messages.
inline std::string voxel_text(const openvdb::Coord& c) {
  return "(" + std::to_string(c.x()) + ", " + std::to_string(c.y()) + ", " + std::to_string(c.z()) +
         ")";
}

inline const char* const kMetricGridNames[6] = {"m11", "m12", "m22", "m13", "m23", "m33"};

// All grids of a VDB file, every value read (no delayed loading: callers with a memory budget
// check the file's size first, and what the archive records of its grids in `before_values`,
// called after the archive check and before OpenVDB reads); rvor::Error naming the file when it
// cannot be read (vdb_io.cpp).
openvdb::GridPtrVec read_grids(
    const std::string& path,
    const std::function<void(const VdbArchiveSummary&)>& before_values = nullptr);

// The grid called `name`; rvor::Error naming the file and the grid when missing or mistyped.
template <typename GridType>
typename GridType::Ptr find_grid(const openvdb::GridPtrVec& grids, const std::string& path,
                                 const std::string& name, const std::string& type) {
  for (const auto& grid : grids)
    if (grid && grid->getName() == name) {
      auto typed = openvdb::gridPtrCast<GridType>(grid);
      if (!typed)
        throw Error("grid '" + name + "' in VDB file " + path + " is not a " + type + " grid");
      return typed;
    }
  throw Error("VDB file " + path + " has no grid '" + name + "'");
}

}  // namespace rvor
