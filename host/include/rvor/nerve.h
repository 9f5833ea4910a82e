#pragma once
// The nerve of a labeled canvas: which seeds' discrete Voronoi cells meet, i.e. the Delaunay
// simplices the canvas witnesses. Canvas simplices are the Kuhn (Freudenthal) subdivision of the
// grid cells whose corners are voxel centres (6 tetrahedra per cube along the monotone paths
// 000 -> 111; 2 triangles per square in 2D), restricted to active voxels. A canvas simplex whose
// vertices carry k+1 >= 2 distinct labels witnesses the Delaunay k-simplex on those seeds.
#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "rvor/canvas.h"
#include "rvor/propagation.h"

namespace rvor {

// One canvas simplex witnessing a Delaunay simplex. Its distance is the largest distance at its
// vertices; its position is the centroid of its vertices (world coordinates). For a Delaunay
// simplex, the witness of largest distance approximates its (discrete) Voronoi vertex: that is
// where refinement inserts; the witness of smallest distance is where a curved edge starts.
struct Witness {
  Vec3 position = Vec3::Zero();
  float distance = 0.0f;
  int64_t slot = -1;  // the canvas slot of the witness vertex of largest distance
};

// A Delaunay simplex found on the canvas: vertex_count seeds (2 edge, 3 triangle, 4 tetrahedron),
// sorted ascending in seeds[0..vertex_count), unused entries -1.
struct NerveSimplex {
  std::array<int32_t, 4> seeds{-1, -1, -1, -1};
  int vertex_count = 0;
  Witness farthest;  // witness of largest distance (discrete Voronoi vertex / edge far end)
  Witness nearest;   // witness of smallest distance (e.g. the bisector point closest to the seeds)
  std::uint32_t witness_count = 0;  // canvas simplices witnessing it
};

// A grid cell carrying more labels than a top simplex has vertices (>= 5 in a cube in 3D, 4 in a
// square in 2D): several seeds are cospherical at canvas resolution and the Kuhn subdivision
// picks one of the possible Delaunay simplices arbitrarily.
struct DegenerateWitness {
  VoxelIndex cell_base;         // the cell's lowest corner voxel
  std::vector<int32_t> labels;  // sorted distinct labels of the cell
};

struct Nerve {
  int dimension = 3;
  std::size_t seed_count = 0;
  // Each list sorted lexicographically by seeds; no duplicates.
  std::vector<NerveSimplex> edges, triangles, tetrahedra;
  std::size_t degenerate_witness_count = 0;
  std::vector<DegenerateWitness> degenerate_witnesses;  // the first kMaxDegenerateListed of them
  double seconds = 0.0;

  static constexpr std::size_t kMaxDegenerateListed = 10000;

  // Top simplices: tetrahedra in 3D, triangles in 2D.
  const std::vector<NerveSimplex>& top_simplices() const {
    return dimension == 3 ? tetrahedra : triangles;
  }
  // The simplex on the given seeds (any order, 2 to 4 of them), or nullptr when not witnessed.
  const NerveSimplex* find(std::vector<int32_t> seeds) const;
};

// Scans the multi-label grid cells of the labeled canvas (bricks whose labels are all equal are
// skipped; bricks are scanned in parallel). `seed_count` bounds the labels (labels outside
// [0, seed_count) are an error). Throws rvor::Error when the field does not match the canvas.
Nerve extract_nerve(const Canvas& canvas, const VoronoiField& field, std::size_t seed_count);
// The same, visiting only the bricks flagged in `bricks_to_scan` (one entry per brick, as
// Propagator::multi_label_bricks returns them): the result is that of the full scan when every
// brick holding a multi-label cell is flagged. Throws rvor::Error when the flags do not match.
Nerve extract_nerve(const Canvas& canvas, const VoronoiField& field, std::size_t seed_count,
                    const std::vector<std::uint8_t>& bricks_to_scan);

}  // namespace rvor
