// connected_surfaces (surface_mesh.h): the separate closed surfaces of a domain mesh.
#include <numeric>
#include <vector>

#include "surface_mesh.h"

namespace rvor {

namespace {

// Union-find over vertices, with path halving.
class VertexSets {
 public:
  explicit VertexSets(std::size_t count) : parent_(count) {
    std::iota(parent_.begin(), parent_.end(), 0);
  }
  int root(int v) {
    while (parent_[v] != v) v = parent_[v] = parent_[parent_[v]];
    return v;
  }
  void join(int a, int b) { parent_[root(a)] = root(b); }

 private:
  std::vector<int> parent_;
};

}  // namespace

std::vector<SurfaceMesh> connected_surfaces(const SurfaceMesh& mesh) {
  VertexSets sets(mesh.vertices.size());
  for (const auto& t : mesh.triangles) sets.join(t[0], t[1]), sets.join(t[1], t[2]);
  std::vector<int> part_of_root(mesh.vertices.size(), -1), new_index(mesh.vertices.size(), -1);
  std::vector<SurfaceMesh> parts;
  for (const auto& t : mesh.triangles) {
    int& part = part_of_root[sets.root(t[0])];
    if (part < 0) part = static_cast<int>(parts.size()), parts.emplace_back();
    SurfaceMesh& out = parts[part];
    std::array<int, 3> triangle{};
    for (int c = 0; c < 3; ++c) {
      if (new_index[t[c]] < 0) {
        new_index[t[c]] = static_cast<int>(out.vertices.size());
        out.vertices.push_back(mesh.vertices[t[c]]);
      }
      triangle[c] = new_index[t[c]];
    }
    out.triangles.push_back(triangle);
  }
  return parts;
}

}  // namespace rvor
