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
