#include "dual/mesh_domain.h"

#include <Eigen/Geometry>

#include <array>
#include <cmath>
#include <fstream>
#include <limits>
#include <map>
#include <stdexcept>

#include "rvor/canvas_builder.h"
#include "rvor/domain.h"
#include "rvor/metric_field.h"

namespace rvor::test {

namespace {

using Face = std::array<int, 3>;

struct Mesh {
  std::vector<Vec3> vertices;  // on the unit sphere
  std::vector<Face> faces;
};

Mesh icosahedron() {
  const double t = (1.0 + std::sqrt(5.0)) / 2.0;
  Mesh m;
  for (const Vec3& v : {Vec3(-1, t, 0), Vec3(1, t, 0), Vec3(-1, -t, 0), Vec3(1, -t, 0),
                        Vec3(0, -1, t), Vec3(0, 1, t), Vec3(0, -1, -t), Vec3(0, 1, -t),
                        Vec3(t, 0, -1), Vec3(t, 0, 1), Vec3(-t, 0, -1), Vec3(-t, 0, 1)})
    m.vertices.push_back(v.normalized());
  m.faces = {{0, 11, 5},  {0, 5, 1},  {0, 1, 7},  {0, 7, 10}, {0, 10, 11}, {1, 5, 9}, {5, 11, 4},
             {11, 10, 2}, {10, 7, 6}, {7, 1, 8},  {3, 9, 4},  {3, 4, 2},   {3, 2, 6}, {3, 6, 8},
             {3, 8, 9},   {4, 9, 5},  {2, 4, 11}, {6, 2, 10}, {8, 6, 7},   {9, 8, 1}};
  return m;
}

// Each triangle into four, new vertices projected on the sphere.
Mesh subdivide(const Mesh& in) {
  Mesh out{in.vertices, {}};
  std::map<std::pair<int, int>, int> midpoints;
  auto midpoint = [&](int a, int b) {
    const auto key = std::minmax(a, b);
    auto [it, inserted] = midpoints.try_emplace(key, static_cast<int>(out.vertices.size()));
    if (inserted) out.vertices.push_back((in.vertices[a] + in.vertices[b]).normalized());
    return it->second;
  };
  for (const Face& f : in.faces) {
    const int ab = midpoint(f[0], f[1]), bc = midpoint(f[1], f[2]), ca = midpoint(f[2], f[0]);
    out.faces.insert(out.faces.end(), {Face{f[0], ab, ca}, Face{f[1], bc, ab}, Face{f[2], ca, bc},
                                       Face{ab, bc, ca}});
  }
  return out;
}

}  // namespace

double Icosphere::depth(const Vec3& x) const {
  double d = std::numeric_limits<double>::infinity();
  for (const Plane& p : planes) d = std::min(d, p.offset - p.normal.dot(x));
  return d;
}

Icosphere write_icosphere_off(const std::string& path, const Vec3& centre, double radius) {
  Mesh mesh = subdivide(subdivide(icosahedron()));
  Icosphere shape;
  std::ofstream out(path);
  out.precision(17);
  out << "OFF\n" << mesh.vertices.size() << " " << mesh.faces.size() << " 0\n";
  for (const Vec3& v : mesh.vertices) {
    const Vec3 p = centre + radius * v;
    out << p.x() << " " << p.y() << " " << p.z() << "\n";
  }
  for (Face& f : mesh.faces) {
    const Vec3 a = centre + radius * mesh.vertices[f[0]], b = centre + radius * mesh.vertices[f[1]],
               c = centre + radius * mesh.vertices[f[2]];
    Vec3 n = (b - a).cross(c - a).normalized();
    if (n.dot(a - centre) < 0) {  // keep every face's winding outward
      std::swap(f[1], f[2]);
      n = -n;
    }
    shape.planes.push_back({n, n.dot(a)});
    out << "3 " << f[0] << " " << f[1] << " " << f[2] << "\n";
  }
  if (!out) throw std::runtime_error("cannot write " + path);
  return shape;
}

namespace {

// The metric G everywhere.
class UniformField : public MetricField {
 public:
  explicit UniformField(const Mat3& G) : G_(G) {}
  int dimension() const override { return 3; }
  Mat3 at(const Vec3&) const override { return G_; }
  std::string description() const override { return "uniform (test)"; }

 private:
  Mat3 G_;
};

}  // namespace

Canvas build_uniform_mesh_canvas(const std::string& path, const Mat3& G, int resolution) {
  CanvasOptions options;
  options.resolution = resolution;
  return build_canvas(parse_domain("mesh:" + path), UniformField(G), options);
}

}  // namespace rvor::test
