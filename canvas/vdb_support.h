#pragma once
// OpenVDB helpers shared by the canvas library's .cpp files (private; includes OpenVDB, so only
// the few translation units that need it include this).
#include <exception>
#include <functional>
#include <string>
#include <utility>

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

// Runs `on_unwind` when an exception leaves the guard's scope (declare it after what it cleans up,
// so that it runs first).
template <typename OnUnwind>
class UnwindGuard {
 public:
  explicit UnwindGuard(OnUnwind on_unwind)
      : on_unwind_(std::move(on_unwind)), exceptions_before_(std::uncaught_exceptions()) {}
  UnwindGuard(const UnwindGuard&) = delete;
  UnwindGuard& operator=(const UnwindGuard&) = delete;
  ~UnwindGuard() {
    if (std::uncaught_exceptions() > exceptions_before_) on_unwind_();
  }

 private:
  OnUnwind on_unwind_;
  int exceptions_before_;
};

// Deletes a tree's nodes without allocating, for a tree that an exception is about to destroy.
// ~Tree calls Tree::clear, which gathers the nodes into vectors before deleting them: after
// std::bad_alloc that gathering can throw again, from a destructor, and the process ended in
// std::terminate (a 2D canvas of 30000² under `ulimit -v 3000000`). RootNode::clear deletes the
// nodes as it walks them.
template <typename TreeType>
auto freeing_on_unwind(TreeType& tree) {
  return UnwindGuard([&tree] { tree.root().clear(); });
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
