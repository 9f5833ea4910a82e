#pragma once
// OpenVDB helpers shared by the canvas library's .cpp files (private; includes OpenVDB, so only
// the few translation units that need it include this).
#include <fstream>
#include <ios>
#include <new>
#include <stdexcept>
#include <string>

#include <openvdb/io/File.h>
#include <openvdb/io/Stream.h>
#include <openvdb/openvdb.h>

#include "rvor/canvas.h"
#include "rvor/error.h"
#include "rvor/input_file.h"
#include "rvor/spec_text.h"
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

inline const char* const kMetricGridNames[6] = {"m11", "m12", "m22", "m13", "m23", "m33"};

// All grids of a VDB file; rvor::Error naming the file when it cannot be read. OpenVDB reads a
// string as its length, then that many bytes into a string it allocates first; in a file cut short
// the length is read past the end and is garbage, and its error message then held up to 4 GB of
// blanks (16.7 GB of peak memory and 59 s for a file missing its last byte). So the file is read
// through a stream that throws at the first read past its end, and the message quotes at most
// the start of OpenVDB's; check_vdb_archive refuses a damaged string length first. (io::Stream has
// no delayed loading: every value of every grid is read here, so callers with a memory budget
// check the file's size first.)
inline openvdb::GridPtrVec read_grids(const std::string& path) {
  openvdb::initialize();
  std::ifstream in = open_input_file(path, "VDB file");
  in.exceptions(std::ios::failbit | std::ios::badbit);
  const std::string cannot = "cannot read VDB file " + path + ": ";
  check_vdb_archive(path);
  try {
    openvdb::io::Stream stream(in, /*delayLoad=*/false);
    return *stream.getGrids();
  } catch (const std::ios_base::failure&) {
    throw Error(cannot + "it ends early or is damaged");
  } catch (const openvdb::Exception& error) {
    throw Error(cannot + quoted_text(error.what(), 200));
  } catch (const std::bad_alloc&) {
    throw Error(cannot + "it is damaged (it gives a size too large to allocate)");
  } catch (const std::length_error&) {
    throw Error(cannot + "it is damaged (it gives a size too large to allocate)");
  }
}

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
