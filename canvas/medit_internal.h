#pragma once
// Private to rvor_medit: the .sol reader with the dimension the file declares, so that the mesh
// metric field can reject a 2D .sol on a 3D mesh (and vice versa).
#include <string>
#include <vector>

#include "rvor/metric.h"

namespace rvor::detail {

struct MeditSolTensors {
  int dimension = 0;
  std::vector<Mat3> tensors;  // 2D: the z row and column are those of the identity
};

// Same checks as read_medit_sol_tensors(), and a Dimension other than `expected_dimension` (0:
// any) is an error at its line.
MeditSolTensors read_medit_sol(const std::string& path, int expected_vertices,
                               int expected_dimension);

}  // namespace rvor::detail
