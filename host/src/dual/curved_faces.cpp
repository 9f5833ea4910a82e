// Curved faces: geodesic patches from a triangle's curved opposite edge to its apex, and their
// VTK file (rvor/curved_dual.h).
#include "curved_faces.h"

#include <algorithm>
#include <cmath>

#include "vtu_appended_writer.h"

namespace rvor {

namespace detail {

constexpr uint8_t kVtkTriangle = 5;

namespace {

// Voxels between geodesics along the edge, and between the points of a geodesic; at most
// kMaxIntervals of each per face, so that long faces stay a few hundred triangles.
constexpr double kSpacing = 2.0;
constexpr std::size_t kMaxIntervals = 16;

double polyline_length(const std::vector<Vec3>& line) {
  double length = 0.0;
  for (std::size_t p = 1; p < line.size(); ++p) length += (line[p] - line[p - 1]).norm();
  return length;
}

// `intervals` + 1 points at equal arc length along the polyline, both ends included.
std::vector<Vec3> resample(const std::vector<Vec3>& line, std::size_t intervals) {
  const double total = polyline_length(line);
  std::vector<Vec3> out;
  out.reserve(intervals + 1);
  std::size_t segment = 1;
  double before = 0.0;  // arc length at line[segment - 1]
  for (std::size_t n = 0; n <= intervals; ++n) {
    const double target = total * static_cast<double>(n) / static_cast<double>(intervals);
    while (segment + 1 < line.size() &&
           before + (line[segment] - line[segment - 1]).norm() < target) {
      before += (line[segment] - line[segment - 1]).norm();
      ++segment;
    }
    if (line.size() < 2) {
      out.push_back(line.front());
      continue;
    }
    const double piece = (line[segment] - line[segment - 1]).norm();
    const double t = piece > 0.0 ? std::clamp((target - before) / piece, 0.0, 1.0) : 0.0;
    out.push_back(line[segment - 1] + t * (line[segment] - line[segment - 1]));
  }
  out.back() = line.back();  // exact end: the apex when reached
  return out;
}

std::size_t intervals_for(double length_voxels) {
  return std::clamp<std::size_t>(static_cast<std::size_t>(std::ceil(length_voxels / kSpacing)), 2,
                                 kMaxIntervals);
}

Vec3 index_point(const Canvas& canvas, const Vec3& world) {
  Vec3 x = canvas.index_coordinates(world);
  if (canvas.dimension == 2) x.z() = 0.0;
  return x;
}

// Rows of points from the edge to the apex, joined into triangles; a row that reached the apex
// ends on the shared apex point 0, so the last strip between two such rows is one triangle.
void triangulate(const Canvas& canvas, const std::vector<std::vector<Vec3>>& rows,
                 const std::vector<bool>& reached, CurvedFace& face) {
  const std::size_t m = rows.front().size() - 1;
  std::vector<std::vector<uint32_t>> ids(rows.size());
  for (std::size_t i = 0; i < rows.size(); ++i)
    for (std::size_t j = 0; j <= m; ++j) {
      if (j == m && reached[i]) {
        ids[i].push_back(0);
        continue;
      }
      ids[i].push_back(static_cast<uint32_t>(face.points.size()));
      face.points.push_back(world_of_index(canvas, rows[i][j]));
    }
  for (std::size_t i = 0; i + 1 < rows.size(); ++i)
    for (std::size_t j = 0; j < m; ++j) {
      const uint32_t p00 = ids[i][j], p10 = ids[i + 1][j], p01 = ids[i][j + 1],
                     p11 = ids[i + 1][j + 1];
      if (p01 == p11) {
        face.triangles.push_back({p00, p10, p01});
      } else {
        face.triangles.push_back({p00, p10, p11});
        face.triangles.push_back({p00, p11, p01});
      }
    }
}

}  // namespace

CurvedFace build_curved_face(const Canvas& canvas, const GeodesicTracer& tracer,
                             const NerveSimplex& triangle, const CurvedEdge& opposite,
                             const std::vector<Vec3>& seeds) {
  CurvedFace face;
  face.seeds = {triangle.seeds[0], triangle.seeds[1], triangle.seeds[2]};
  const Vec3& apex_world = seeds[static_cast<std::size_t>(face.seeds[0])];
  const Vec3 apex = index_point(canvas, apex_world);
  face.points.push_back(apex_world);

  std::vector<Vec3> edge;
  for (const Vec3& p : opposite.points) edge.push_back(index_point(canvas, p));
  const std::vector<Vec3> starts = resample(edge, intervals_for(polyline_length(edge)));

  std::vector<std::vector<Vec3>> geodesics(starts.size());
  std::vector<bool> reached(starts.size());
  double longest = 0.0;
  for (std::size_t i = 0; i < starts.size(); ++i) {
    geodesics[i].push_back(starts[i]);
    bool staircase = false;
    reached[i] = tracer.trace(starts[i], apex, face.seeds[0], geodesics[i], &staircase);
    face.staircase_geodesics += staircase ? 1 : 0;
    longest = std::max(longest, polyline_length(geodesics[i]));
  }
  face.geodesics = starts.size();
  face.unreached_geodesics =
      static_cast<std::size_t>(std::count(reached.begin(), reached.end(), false));

  const std::size_t rows_intervals = intervals_for(longest);
  std::vector<std::vector<Vec3>> rows;
  for (const std::vector<Vec3>& g : geodesics) rows.push_back(resample(g, rows_intervals));
  triangulate(canvas, rows, reached, face);
  return face;
}

}  // namespace detail

void write_curved_faces_vtu(const std::string& path, const CurvedDual& dual) {
  require_consistent_curved_dual(dual, "cannot write " + path);
  std::vector<double> points;  // doubles: faces far from the origin keep their shape
  std::vector<int64_t> connectivity, offsets;
  std::vector<uint8_t> types, reached;
  std::vector<int32_t> face_index, seed_a, seed_b, seed_c;
  for (std::size_t f = 0; f < dual.faces.size(); ++f) {
    const CurvedFace& face = dual.faces[f];
    const auto base = static_cast<int64_t>(points.size() / 3);
    for (const Vec3& p : face.points)
      for (int a = 0; a < 3; ++a) points.push_back(p[a]);
    for (const std::array<uint32_t, 3>& t : face.triangles) {
      for (uint32_t v : t) connectivity.push_back(base + v);
      offsets.push_back(static_cast<int64_t>(connectivity.size()));
      types.push_back(detail::kVtkTriangle);
      reached.push_back(face.reached() ? 1 : 0);
      face_index.push_back(static_cast<int32_t>(f));
      seed_a.push_back(face.seeds[0]);
      seed_b.push_back(face.seeds[1]);
      seed_c.push_back(face.seeds[2]);
    }
  }
  vtu::AppendedWriter appended;
  std::string xml = vtu::grid_geometry(appended, points, connectivity, offsets, types);
  xml += "<CellData Scalars=\"face\">\n";
  xml += appended.declare("Int32", "face", 1, face_index);
  xml += appended.declare("UInt8", "reached", 1, reached);
  xml += appended.declare("Int32", "seed_a", 1, seed_a);
  xml += appended.declare("Int32", "seed_b", 1, seed_b);
  xml += appended.declare("Int32", "seed_c", 1, seed_c);
  xml += "</CellData>\n";
  vtu::publish(path, std::move(xml), appended);
}

}  // namespace rvor
