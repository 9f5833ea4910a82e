#pragma once
// Seeds: points in the domain; seed i carries label i.
#include <cstdint>
#include <string>
#include <vector>

#include "rvor/canvas.h"

namespace rvor {

// Reads a .xyz file: one point per line, 2 or 3 whitespace- or comma-separated coordinates;
// blank lines and lines starting with '#' are skipped. Throws "FILE:LINE: ..." on malformed lines
// and on an empty file.
std::vector<Vec3> read_xyz(const std::string& path);
// Writes points atomically, 2 or 3 coordinates per line (by dimension), full precision.
void write_xyz(const std::string& path, const std::vector<Vec3>& points, int dimension);

// Throws rvor::Error "seed N at (x, y, z) is outside the domain" when a seed's containing voxel
// is not an active canvas voxel, or its coordinates are not finite; and on an empty seed list.
void validate_seeds(const Canvas& canvas, const std::vector<Vec3>& seeds);

// `count` points: an active voxel drawn uniformly, then a point within 0.49 voxel of its centre
// along each axis, so the seed's containing voxel is that active voxel; deterministic in
// `rng_seed`.
std::vector<Vec3> random_seeds(const Canvas& canvas, std::size_t count, std::uint64_t rng_seed);

}  // namespace rvor
