// Files of the straight dual: a VTK .vtu of the top simplices with quality and validity as cell
// data, and a Medit .mesh (readable by MMG, Gmsh and meshio).
#include <algorithm>
#include <map>
#include <utility>

#include "dual/dual_internal.h"
#include "rvor/dual.h"
#include "rvor/medit.h"
#include "vtu_appended_writer.h"

namespace rvor {

namespace {

constexpr uint8_t kVtkTriangle = 5;
constexpr uint8_t kVtkTetra = 10;

struct DualCells {
  std::vector<double> points;  // doubles: a dual far from the origin keeps its shape
  std::vector<int32_t> labels;
  std::vector<int64_t> connectivity, offsets;
  std::vector<uint8_t> types, inverted, intersecting, non_manifold, flags;
  std::vector<float> quality, min_angle, max_angle, min_edge, max_edge;
};

using Top = std::array<int32_t, 4>;

// The top simplices in the vertex order the files give them: positively oriented (counter-
// clockwise triangles, tetrahedra of positive volume), as mesh readers expect, where the sorted
// order the dual keeps is either; an inverted element negatively, which is how it comes out when
// oriented consistently with its neighbours (DualChecks), so a reader sees the fold. Flat ones as
// they are.
std::vector<Top> written_order(const StraightDual& dual) {
  std::vector<Top> written;
  written.reserve(dual.top_count());
  for (std::size_t t = 0; t < dual.top_count(); ++t) {
    Top s = dual.top_simplex(t);
    const int wanted = (dual.flags[t] & kDualInverted) ? -1 : 1;
    if (dual::orientation_sign(dual, s) == -wanted) std::swap(s[0], s[1]);
    written.push_back(s);
  }
  return written;
}

DualCells collect_cells(const StraightDual& dual, bool only_flagged) {
  DualCells c;
  const std::vector<Top> written = written_order(dual);
  for (std::size_t v = 0; v < dual.vertices.size(); ++v) {
    for (int a = 0; a < 3; ++a) c.points.push_back(dual.vertices[v][a]);
    c.labels.push_back(static_cast<int32_t>(v));
  }
  for (std::size_t t = 0; t < dual.top_count(); ++t) {
    const uint8_t f = dual.flags[t];
    if (only_flagged && f == 0) continue;
    for (int v = 0; v <= dual.dimension; ++v) c.connectivity.push_back(written[t][v]);
    c.offsets.push_back(static_cast<int64_t>(c.connectivity.size()));
    c.types.push_back(dual.dimension == 3 ? kVtkTetra : kVtkTriangle);
    c.flags.push_back(f);
    c.inverted.push_back((f & kDualInverted) ? 1 : 0);
    c.intersecting.push_back((f & kDualIntersecting) ? 1 : 0);
    c.non_manifold.push_back((f & kDualNonManifold) ? 1 : 0);
    const ElementQuality& q = dual.quality[t];
    c.quality.push_back(static_cast<float>(q.quality));
    c.min_angle.push_back(static_cast<float>(q.min_angle));
    c.max_angle.push_back(static_cast<float>(q.max_angle));
    c.min_edge.push_back(static_cast<float>(q.min_edge_length));
    c.max_edge.push_back(static_cast<float>(q.max_edge_length));
  }
  return c;
}

// Triangles of exactly one tetrahedron, with the tetrahedron they bound, facing out of it: the
// orientation the written tetrahedron induces on them (its opposite vertex behind a positive
// tetrahedron's face, in front of an inverted one's).
std::vector<std::pair<std::array<int, 3>, std::size_t>> boundary_triangles(
    const StraightDual& dual, const std::vector<Top>& written) {
  std::map<std::array<int, 3>, std::pair<int, std::size_t>> uses;
  for (std::size_t t = 0; t < dual.tetrahedra.size(); ++t) {
    const auto& s = dual.tetrahedra[t];
    for (int skip = 0; skip < 4; ++skip) {
      std::array<int, 3> f{};
      int m = 0;
      for (int v = 0; v < 4; ++v)
        if (v != skip) f[m++] = s[v];
      auto& [count, owner] = uses[f];
      ++count;
      owner = t;
    }
  }
  std::vector<std::pair<std::array<int, 3>, std::size_t>> out;
  for (const auto& [facet, use] : uses) {
    if (use.first != 1) continue;
    std::array<int, 3> f = facet;
    const Top& s = dual.tetrahedra[use.second];
    const int32_t opposite = *std::find_if(
        s.begin(), s.end(), [&](int32_t v) { return std::find(f.begin(), f.end(), v) == f.end(); });
    const int tetrahedron = dual::orientation_sign(dual, written[use.second]);
    if (dual::orientation_sign(dual, {f[0], f[1], f[2], opposite}) == tetrahedron)
      std::swap(f[1], f[2]);
    out.push_back({f, use.second});
  }
  return out;
}

int reference_of(uint8_t flags) {
  return flags == 0 ? 1 : 2;
}

}  // namespace

void write_dual_vtu(const std::string& path, const StraightDual& dual, bool only_flagged) {
  require_consistent_dual(dual, "cannot write " + path);
  const DualCells c = collect_cells(dual, only_flagged);
  vtu::AppendedWriter appended;
  std::string xml = vtu::grid_geometry(appended, c.points, c.connectivity, c.offsets, c.types);
  xml += "<PointData Scalars=\"label\">\n";
  xml += appended.declare("Int32", "label", 1, c.labels);
  xml += "</PointData>\n<CellData Scalars=\"quality\">\n";
  xml += appended.declare("Float32", "quality", 1, c.quality);
  xml += appended.declare("Float32", "min_angle", 1, c.min_angle);
  xml += appended.declare("Float32", "max_angle", 1, c.max_angle);
  xml += appended.declare("Float32", "min_edge_length", 1, c.min_edge);
  xml += appended.declare("Float32", "max_edge_length", 1, c.max_edge);
  xml += appended.declare("UInt8", "inverted", 1, c.inverted);
  xml += appended.declare("UInt8", "intersecting", 1, c.intersecting);
  xml += appended.declare("UInt8", "non_manifold", 1, c.non_manifold);
  xml += appended.declare("UInt8", "flags", 1, c.flags);
  xml += "</CellData>\n";
  vtu::publish(path, std::move(xml), appended);
}

void write_dual_medit(const std::string& path, const StraightDual& dual) {
  require_consistent_dual(dual, "cannot write " + path);
  MeditMesh mesh;
  mesh.dimension = dual.dimension;
  mesh.vertices = dual.vertices;
  const std::vector<Top> written = written_order(dual);
  if (dual.dimension == 2) {
    for (std::size_t t = 0; t < written.size(); ++t) {
      const auto& s = written[t];
      mesh.triangles.push_back({s[0], s[1], s[2]});
      mesh.triangle_refs.push_back(reference_of(dual.flags[t]));
    }
  } else {
    for (std::size_t t = 0; t < written.size(); ++t) {
      const auto& s = written[t];
      mesh.tetrahedra.push_back({s[0], s[1], s[2], s[3]});
      mesh.tetrahedron_refs.push_back(reference_of(dual.flags[t]));
    }
    for (const auto& [f, owner] : boundary_triangles(dual, written)) {
      mesh.triangles.push_back(f);
      mesh.triangle_refs.push_back(reference_of(dual.flags[owner]));
    }
  }
  write_medit_mesh(path, mesh);
}

}  // namespace rvor
