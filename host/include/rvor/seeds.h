#pragma once
// Seeds: points in the domain; seed i carries label i.
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "rvor/canvas.h"

namespace rvor {

// Reads a .xyz file: one point per line, 2 or 3 coordinates separated by blanks, by commas or by
// semicolons (one kind per line, blanks after every separator or after none: "0.5 0,5", "1;2,5"
// and "0.5, 0,5" are refused, their comma likely a decimal one), the same count on every line;
// blank lines and lines starting with '#' are skipped. Throws "FILE:LINE: ..." on malformed lines
// and on an empty file.
std::vector<Vec3> read_xyz(const std::string& path);
// The same for a domain of `dimension`: 3D needs 3 coordinates; 2D takes 2, or 3 with z = 0.
std::vector<Vec3> read_xyz(const std::string& path, int dimension);
// read_xyz with a dimension, and the line each point came from (for messages about a point).
struct XyzPoints {
  std::vector<Vec3> points;
  std::vector<int> lines;
};
XyzPoints read_xyz_with_lines(const std::string& path, int dimension);
// Writes points atomically, 2 or 3 coordinates per line (by dimension), full precision.
// Refuses a point that is not finite, which read_xyz would refuse.
void write_xyz(const std::string& path, const std::vector<Vec3>& points, int dimension);

// What the engines say of a canvas without active voxels (a hand-built one: build_canvas refuses
// an empty domain), whatever the seeds.
inline constexpr const char* kEmptyCanvasMessage =
    "the canvas has no active voxel: nothing to propagate on";

// Throws rvor::Error "seed N at (x, y, z) is outside the domain" when a seed's containing voxel
// is not an active canvas voxel, or its coordinates are not finite; on an empty canvas
// (kEmptyCanvasMessage), an empty seed list, and more seeds than active voxels.
// A 2D canvas ignores z, which must still be finite (read_xyz with a dimension checks files). Seeds
// before `first_unchecked` are taken as checked already (an insertion's solved seeds); the count is
// always checked. Seeds that share a voxel are accepted (the engines give the voxel to the smaller
// label, so the other seed's cell may be empty: FieldSummary::empty_cells, which `rvor voronoi`
// reports).
void validate_seeds(const Canvas& canvas, const std::vector<Vec3>& seeds,
                    std::size_t first_unchecked = 0);
// The same, naming seed n by name(n) instead of "seed N" (say, "seeds.xyz:4: seed 2").
void validate_seeds(const Canvas& canvas, const std::vector<Vec3>& seeds,
                    std::size_t first_unchecked,
                    const std::function<std::string(std::size_t)>& name);

// `count` points: distinct active voxels drawn uniformly, then in each a point within 0.49 voxel
// of its centre along each axis, so the seed's containing voxel is that active voxel;
// deterministic in `rng_seed`. Throws when `count` exceeds the active voxels.
std::vector<Vec3> random_seeds(const Canvas& canvas, std::size_t count, std::uint64_t rng_seed);

}  // namespace rvor
