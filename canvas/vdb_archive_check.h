#pragma once
// A check of a .vdb archive's lengths before OpenVDB reads it (private to the canvas library).
// OpenVDB reads a string as a 32-bit length and allocates that many bytes before it reads them,
// so one damaged length cost up to 4 GiB and seconds before the read failed. This walks the parts
// of the archive that hold strings (the header, the file's metadata, the grid descriptors, each
// grid's metadata and the name of its transform's map) without allocating, and refuses a length
// that runs past the end of the file, or a grid that ends past it. The voxel data that follows
// is left to OpenVDB, as are archives of format versions other than 222 to this OpenVDB's.
#include <cstdint>
#include <istream>
#include <map>
#include <string>

namespace rvor {

// What the walk learned of the grids before their values: the active voxel count (tiles
// included) that OpenVDB's writers record in a grid's metadata as file_voxel_count, by grid
// name, for the grids that carry one (every grid of a seekable archive, the first of a stream).
struct VdbArchiveSummary {
  std::map<std::string, std::int64_t> recorded_voxels;
};

// Walks `in`, the file at `path` opened for reading, from its start; leaves it at no particular
// place. Throws rvor::Error "cannot read VDB file PATH: ..." naming what runs past the end and
// where. A file that is no VDB archive passes (with an empty summary): OpenVDB names it.
VdbArchiveSummary check_vdb_archive(std::istream& in, const std::string& path);

}  // namespace rvor
