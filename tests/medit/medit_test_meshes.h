#pragma once
// Meshes and helpers shared by the Medit tests.
#include <functional>
#include <string>

#include "rvor/medit.h"

namespace rvor::test {

// The unit cube cut into n^3 cubes of 6 tetrahedra each (Kuhn subdivision along 000 -> 111),
// with conforming faces between cubes. Vertex (i, j, k) has index i + (n+1) (j + (n+1) k).
MeditMesh unit_cube_tetrahedra(int n);

// The unit square cut into n^2 squares of 2 triangles each.
MeditMesh unit_square_triangles(int n);

// The message of the rvor::Error that `action` throws; fails the test and returns "" when it
// throws nothing.
std::string error_message(const std::function<void()>& action);

}  // namespace rvor::test
