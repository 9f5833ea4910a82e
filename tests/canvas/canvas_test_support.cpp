#include "canvas_test_support.h"

#include <array>
#include <cstdint>
#include <fstream>
#include <sstream>
#include <vector>

#include "support/temp_dir.h"

namespace rvor::test {

namespace {

// Corner n of the box: bit 0 -> x, bit 1 -> y, bit 2 -> z.
std::vector<Vec3> box_corners(const Vec3& lo, const Vec3& hi) {
  std::vector<Vec3> corners;
  for (int n = 0; n < 8; ++n)
    corners.emplace_back(n & 1 ? hi.x() : lo.x(), n & 2 ? hi.y() : lo.y(), n & 4 ? hi.z() : lo.z());
  return corners;
}

// The six faces as quads of corner indices, outward oriented.
const std::array<std::array<int, 4>, 6> kBoxQuads = {
    {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}}};

std::vector<std::array<int, 3>> box_triangles() {
  std::vector<std::array<int, 3>> triangles;
  for (const auto& q : kBoxQuads) {
    triangles.push_back({q[0], q[1], q[2]});
    triangles.push_back({q[0], q[2], q[3]});
  }
  return triangles;
}

}  // namespace

void write_box_off(const std::string& path, const Vec3& lo, const Vec3& hi, bool drop_last_face) {
  const int faces = drop_last_face ? 5 : 6;
  std::ostringstream out;
  out.precision(17);
  out << "OFF\n# a box\n8 " << faces << " 0\n";
  for (const Vec3& c : box_corners(lo, hi)) out << c.x() << " " << c.y() << " " << c.z() << "\n";
  for (int f = 0; f < faces; ++f) {
    const auto& q = kBoxQuads[f];
    out << "4 " << q[0] << " " << q[1] << " " << q[2] << " " << q[3] << "\n";
  }
  write_text(path, out.str());
}

void write_boxes_off(const std::string& path, const std::vector<std::pair<Vec3, Vec3>>& boxes,
                     bool flip_first_face) {
  std::ostringstream out;
  out << "OFF\n" << 8 * boxes.size() << " " << 6 * boxes.size() << " 0\n";
  for (const auto& [lo, hi] : boxes)
    for (const Vec3& c : box_corners(lo, hi)) out << c.x() << " " << c.y() << " " << c.z() << "\n";
  for (std::size_t b = 0; b < boxes.size(); ++b)
    for (std::size_t f = 0; f < kBoxQuads.size(); ++f) {
      auto q = kBoxQuads[f];
      if (flip_first_face && b == 0 && f == 0) std::swap(q[1], q[3]);
      const std::size_t base = 8 * b;
      out << "4 " << base + q[0] << " " << base + q[1] << " " << base + q[2] << " " << base + q[3]
          << "\n";
    }
  write_text(path, out.str());
}

namespace {

// A polygon soup with vertices merged by exact position (OFF output).
class QuadSoup {
 public:
  void quad(const std::array<Vec3, 4>& corners) {
    std::array<int, 4> q{};
    for (int c = 0; c < 4; ++c) q[c] = index_of(corners[c]);
    quads_.push_back(q);
  }
  std::string off() const {
    std::ostringstream out;
    out.precision(17);
    out << "OFF\n" << vertices_.size() << " " << quads_.size() << " 0\n";
    for (const Vec3& v : vertices_) out << v.x() << " " << v.y() << " " << v.z() << "\n";
    for (const auto& q : quads_)
      out << "4 " << q[0] << " " << q[1] << " " << q[2] << " " << q[3] << "\n";
    return out.str();
  }

 private:
  int index_of(const Vec3& p) {
    for (std::size_t v = 0; v < vertices_.size(); ++v)
      if (vertices_[v] == p) return static_cast<int>(v);
    vertices_.push_back(p);
    return static_cast<int>(vertices_.size() - 1);
  }
  std::vector<Vec3> vertices_;
  std::vector<std::array<int, 4>> quads_;
};

// The square [a, b]^2 in y and z at x.
std::array<Vec3, 4> square_at(double x, double a, double b) {
  return {Vec3(x, a, a), Vec3(x, b, a), Vec3(x, b, b), Vec3(x, a, b)};
}

// The five faces of the cube [a, b]^3 other than x = a.
void cube_without_low_x(QuadSoup& soup, double a, double b) {
  const auto c = [&](int i, int j, int k) {
    return Vec3(a + (b - a) * i, a + (b - a) * j, a + (b - a) * k);
  };
  soup.quad({c(1, 0, 0), c(1, 1, 0), c(1, 1, 1), c(1, 0, 1)});
  soup.quad({c(0, 0, 0), c(1, 0, 0), c(1, 0, 1), c(0, 0, 1)});
  soup.quad({c(0, 1, 0), c(0, 1, 1), c(1, 1, 1), c(1, 1, 0)});
  soup.quad({c(0, 0, 0), c(0, 1, 0), c(1, 1, 0), c(1, 0, 0)});
  soup.quad({c(0, 0, 1), c(1, 0, 1), c(1, 1, 1), c(0, 1, 1)});
}

// The faces between a square `outer` and a square `inner` of the same plane.
void square_ring(QuadSoup& soup, const std::array<Vec3, 4>& outer,
                 const std::array<Vec3, 4>& inner) {
  for (int k = 0; k < 4; ++k)
    soup.quad({outer[k], outer[(k + 1) % 4], inner[(k + 1) % 4], inner[k]});
}

}  // namespace

void write_bottle_off(const std::string& path, double neck) {
  const double lo = 2 - neck / 2, hi = 2 + neck / 2;
  QuadSoup soup;
  cube_without_low_x(soup, 0, 4);
  square_ring(soup, square_at(0, 0, 4), square_at(0, lo, hi));
  const auto inner = square_at(1, lo, hi);
  square_ring(soup, square_at(0, lo, hi), inner);  // the neck, from its mouth inwards
  cube_without_low_x(soup, 1, 3);
  square_ring(soup, square_at(1, 1, 3), inner);
  write_text(path, soup.off());
}

bool in_bottle(const Vec3& p, double neck) {
  const auto within = [](const Vec3& q, const Vec3& lo, const Vec3& hi) {
    return (q.array() > lo.array()).all() && (q.array() < hi.array()).all();
  };
  const double lo = 2 - neck / 2, hi = 2 + neck / 2;
  return within(p, Vec3::Zero(), Vec3::Constant(4)) &&
         !within(p, Vec3::Ones(), Vec3::Constant(3)) &&
         !within(p, Vec3(-1, lo, lo), Vec3(1.5, hi, hi));
}

void write_box_obj(const std::string& path, const Vec3& lo, const Vec3& hi) {
  std::ostringstream out;
  out << "# a box\no box\n";
  for (const Vec3& c : box_corners(lo, hi))
    out << "v " << c.x() << " " << c.y() << " " << c.z() << "\n";
  out << "vt 0 0\nvn 0 0 1\n";
  const auto quads = kBoxQuads;
  for (std::size_t f = 0; f < quads.size(); ++f) {
    const auto& q = quads[f];
    if (f == 0) {  // negative (relative) indices: -8 is the first vertex
      out << "f " << q[0] - 8 << " " << q[1] - 8 << " " << q[2] - 8 << " " << q[3] - 8 << "\n";
    } else if (f % 2) {
      out << "f " << q[0] + 1 << "/1/1 " << q[1] + 1 << "/1/1 " << q[2] + 1 << "/1/1 " << q[3] + 1
          << "/1/1\n";
    } else {
      out << "f " << q[0] + 1 << "//1 " << q[1] + 1 << "//1 " << q[2] + 1 << "//1 " << q[3] + 1
          << "//1\n";
    }
  }
  write_text(path, out.str());
}

void write_box_stl_ascii(const std::string& path, const Vec3& lo, const Vec3& hi) {
  const auto corners = box_corners(lo, hi);
  std::ostringstream out;
  out << "solid box\n";
  for (const auto& t : box_triangles()) {
    out << "  facet normal 0 0 0\n    outer loop\n";
    for (int v : t)
      out << "      vertex " << corners[v].x() << " " << corners[v].y() << " " << corners[v].z()
          << "\n";
    out << "    endloop\n  endfacet\n";
  }
  out << "endsolid box\n";
  write_text(path, out.str());
}

void write_box_stl_binary(const std::string& path, const Vec3& lo, const Vec3& hi) {
  const auto corners = box_corners(lo, hi);
  const auto triangles = box_triangles();
  std::ofstream out(path, std::ios::binary);
  const std::string header = "solid binary box (header text that mimics ASCII)";
  out.write(header.c_str(), static_cast<std::streamsize>(header.size()));
  out.write(std::string(80 - header.size(), ' ').c_str(),
            static_cast<std::streamsize>(80 - header.size()));
  const std::uint32_t count = static_cast<std::uint32_t>(triangles.size());
  out.write(reinterpret_cast<const char*>(&count), 4);
  for (const auto& t : triangles) {
    float record[12] = {0, 0, 0};
    for (int v = 0; v < 3; ++v)
      for (int a = 0; a < 3; ++a) record[3 + 3 * v + a] = static_cast<float>(corners[t[v]][a]);
    out.write(reinterpret_cast<const char*>(record), sizeof record);
    const std::uint16_t attribute = 0;
    out.write(reinterpret_cast<const char*>(&attribute), 2);
  }
}

}  // namespace rvor::test
