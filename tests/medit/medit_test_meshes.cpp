#include "medit_test_meshes.h"

#include <algorithm>
#include <array>

#include <gtest/gtest.h>

#include "rvor/error.h"

namespace rvor::test {

MeditMesh unit_cube_tetrahedra(int n) {
  MeditMesh mesh;
  mesh.dimension = 3;
  const auto index = [n](int i, int j, int k) { return i + (n + 1) * (j + (n + 1) * k); };
  for (int k = 0; k <= n; ++k)
    for (int j = 0; j <= n; ++j)
      for (int i = 0; i <= n; ++i) mesh.vertices.emplace_back(i, j, k);
  for (Vec3& v : mesh.vertices) v /= n;
  for (int k = 0; k < n; ++k)
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) {
        // One tetrahedron per order in which the path 000 -> 111 steps along the three axes.
        std::array<int, 3> axes{0, 1, 2};
        do {
          std::array<int, 3> corner{i, j, k};
          std::array<int, 4> tet{};
          tet[0] = index(corner[0], corner[1], corner[2]);
          for (int step = 0; step < 3; ++step) {
            ++corner[axes[step]];
            tet[step + 1] = index(corner[0], corner[1], corner[2]);
          }
          mesh.tetrahedra.push_back(tet);
          mesh.tetrahedron_refs.push_back(1);
        } while (std::next_permutation(axes.begin(), axes.end()));
      }
  return mesh;
}

MeditMesh unit_square_triangles(int n) {
  MeditMesh mesh;
  mesh.dimension = 2;
  const auto index = [n](int i, int j) { return i + (n + 1) * j; };
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i) mesh.vertices.emplace_back(double(i) / n, double(j) / n, 0.0);
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      mesh.triangles.push_back({index(i, j), index(i + 1, j), index(i + 1, j + 1)});
      mesh.triangles.push_back({index(i, j), index(i + 1, j + 1), index(i, j + 1)});
      mesh.triangle_refs.insert(mesh.triangle_refs.end(), {1, 2});
    }
  return mesh;
}

std::string error_message(const std::function<void()>& action) {
  try {
    action();
  } catch (const Error& error) {
    return error.what();
  }
  ADD_FAILURE() << "expected an rvor::Error, none was thrown";
  return "";
}

}  // namespace rvor::test
