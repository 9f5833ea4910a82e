#pragma once
// Medit .mesh (ASCII, MeshVersionFormatted 1 or 2) and .sol (SolAtVertices) reading and writing.
#include <array>
#include <string>
#include <vector>

#include "rvor/metric.h"

namespace rvor {

struct MeditMesh {
  int dimension = 3;
  std::vector<Vec3> vertices;                                   // z = 0 in 2D
  std::vector<std::array<int, 3>> triangles;                    // 0-based vertex indices
  std::vector<std::array<int, 4>> tetrahedra;                   // 0-based vertex indices
  std::vector<std::array<int, 2>> edges;                        // 0-based vertex indices
  std::vector<int> triangle_refs, tetrahedron_refs, edge_refs;  // reference tags (0 if absent)
};

// Throws rvor::Error "FILE:LINE: ..." on malformed or truncated files, out-of-range indices,
// non-finite coordinates.
MeditMesh read_medit_mesh(const std::string& path);
void write_medit_mesh(const std::string& path, const MeditMesh& mesh);  // atomic

// Reads a .sol with one tensor (type 3) per vertex; returns the tensors (2D: m11 m12 m22 with
// the z row/column of identity). Throws on malformed input, a vertex count different from
// `expected_vertices` (when >= 0), and non-SPD tensors ("FILE: tensor of vertex N ...").
std::vector<Mat3> read_medit_sol_tensors(const std::string& path, int expected_vertices = -1);
void write_medit_sol_tensors(const std::string& path, int dimension,
                             const std::vector<Mat3>& tensors);

}  // namespace rvor
