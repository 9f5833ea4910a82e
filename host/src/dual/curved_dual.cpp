// The curved dual (curved_dual.h): nerve edges traced as geodesics by descending each side's
// distance from the edge's bisector point of smallest distance, faces (curved_faces.cpp) when
// local fields are given, and the edges' VTK file.
#include "rvor/curved_dual.h"

#include <Eigen/Dense>
#include <algorithm>
#include <chrono>
#include <cmath>

#include "curved_faces.h"
#include "dual/dual_internal.h"
#include "geodesic_tracer.h"
#include "parallel_for.h"
#include "rvor/error.h"
#include "vtu_appended_writer.h"

namespace rvor {

namespace {

constexpr uint8_t kVtkPolyLine = 4;

using detail::GeodesicTracer;
using detail::world_of_index;

// A geodesic is the shortest path between its seeds, so a traced edge longer than the straight
// segment between them (in the same measure, on the canvas) is no better an approximation of it
// than that segment: the edge becomes the segment, split at its metric midpoint (the bisector
// point of two seeds alone). Where the canvas does not resolve the seeds or the metric varies
// fast between them, the bisector point and the descents went astray: two swirl seeds a voxel
// apart at 64^2 gave an edge 2.3 times the segment's length, two in one voxel 6.9 times.
void keep_straight_if_shorter(const Canvas& canvas, const GeodesicTracer& tracer,
                              const std::array<Vec3, 2>& ends, const std::vector<Vec3>& seeds,
                              CurvedEdge& out) {
  if (!out.reached()) return;
  const double straight = canvas.voxel_size * tracer.segment_length(ends[0], ends[1]);
  if (!(straight < out.length) || !tracer.segment_on_canvas(ends[0], ends[1])) return;
  double lo = 0.0, hi = 1.0;  // the parameter of the metric midpoint, by bisection
  for (int n = 0; n < 40; ++n) {
    const double t = 0.5 * (lo + hi);
    const Vec3 x = ends[0] + t * (ends[1] - ends[0]);
    (2.0 * canvas.voxel_size * tracer.segment_length(ends[0], x) < straight ? lo : hi) = t;
  }
  const Vec3 middle = ends[0] + 0.5 * (lo + hi) * (ends[1] - ends[0]);
  out.points = {seeds[static_cast<std::size_t>(out.seeds[0])], world_of_index(canvas, middle),
                seeds[static_cast<std::size_t>(out.seeds[1])]};
  out.bisector_index = 1;
  out.length = canvas.voxel_size *
               (tracer.segment_length(ends[0], middle) + tracer.segment_length(middle, ends[1]));
  out.straightened = true;
}

CurvedEdge trace_edge(const Canvas& canvas, const GeodesicTracer& tracer, const NerveSimplex& edge,
                      const std::vector<Vec3>& seeds, bool straighten) {
  CurvedEdge out;
  out.seeds = {edge.seeds[0], edge.seeds[1]};
  Vec3 start;
  if (!tracer.bisector_minimum(out.seeds[0], out.seeds[1], start)) {
    start = canvas.index_coordinates(edge.nearest.position);
    if (canvas.dimension == 2) start.z() = 0.0;
  }
  start = tracer.refine_bisector_point(start, out.seeds[0], out.seeds[1]);
  std::array<std::vector<Vec3>, 2> sides;  // index coordinates, from the bisector outwards
  for (int s = 0; s < 2; ++s) {
    Vec3 target = canvas.index_coordinates(seeds[static_cast<std::size_t>(out.seeds[s])]);
    if (canvas.dimension == 2) target.z() = 0.0;
    bool staircase = false;
    out.side_reached[s] = tracer.trace(start, target, out.seeds[s], sides[s], &staircase);
    out.side_staircase[s] = staircase;
  }
  std::vector<Vec3> index_points(sides[0].rbegin(), sides[0].rend());
  out.bisector_index = index_points.size();
  index_points.push_back(start);
  index_points.insert(index_points.end(), sides[1].begin(), sides[1].end());

  out.points.reserve(index_points.size());
  for (std::size_t p = 0; p < index_points.size(); ++p) {
    const bool seed_end =
        (p == 0 && out.side_reached[0]) || (p + 1 == index_points.size() && out.side_reached[1]);
    out.points.push_back(seed_end ? seeds[static_cast<std::size_t>(out.seeds[p == 0 ? 0 : 1])]
                                  : world_of_index(canvas, index_points[p]));
  }
  for (std::size_t p = 1; p < index_points.size(); ++p)
    out.length += canvas.voxel_size * tracer.segment_length(index_points[p - 1], index_points[p]);
  if (straighten)
    keep_straight_if_shorter(canvas, tracer, {index_points.front(), index_points.back()}, seeds,
                             out);
  return out;
}

// Local fields of other seeds (the same count, other places or order) gave geodesics that
// descended towards the wrong seed's distance, with no error.
void require_seeds_of_locals(const LocalFields& locals, const std::vector<Vec3>& seeds) {
  for (std::size_t s = 0; s < seeds.size(); ++s)
    if (s >= locals.seeds.size() || locals.seeds[s] != seeds[s])
      throw Error("curved dual: the local fields were computed for other seeds (seed " +
                  std::to_string(s) + " differs); compute them for these seeds");
}

// A field solved for these seeds holds, at each seed's voxel, at most that seed's own distance
// there (the engines start a seed's voxel at it; another seed only lowers it). Seeds that are not
// the field's (another run's, moved) were traced with no error, from a nerve of other seeds. The
// bound allows a voxel diagonal in the metric beyond that distance, for fields not solved by an
// engine (an exact one under a varying metric); a seed moved by a voxel or so passes.
void require_seeds_of_field(const Canvas& canvas, const VoronoiField& field,
                            const std::vector<Vec3>& seeds) {
  const Vec3 diagonal = canvas.voxel_size * (canvas.dimension == 3 ? Vec3(1, 1, 1) : Vec3(1, 1, 0));
  for (std::size_t s = 0; s < seeds.size(); ++s) {
    const VoxelIndex v = canvas.voxel_containing(seeds[s]);
    const auto slot = static_cast<std::size_t>(canvas.slot_of(v));  // active: checked before
    const Mat3 G = canvas.metric_at(slot);
    const double own = metric_length(G, canvas.world_of(slot) - seeds[s]);
    const double bound = own + metric_length(G, diagonal);
    if (!(field.distance[slot] <= bound))
      throw Error("curved dual: seed " + std::to_string(s) + " is not one the field was solved " +
                  "for: its voxel (" + std::to_string(v.i) + ", " + std::to_string(v.j) + ", " +
                  std::to_string(v.k) + ") holds distance " + std::to_string(field.distance[slot]) +
                  ", where the seed is " + std::to_string(own) +
                  " away; pass the seeds the field was solved for, in its order");
  }
}

void check_inputs(const Canvas& canvas, const VoronoiField& field, const std::vector<Vec3>& seeds,
                  const LocalFields* locals) {
  if (field.distance.size() != canvas.slot_count() || field.label.size() != canvas.slot_count())
    throw Error("curved dual: the field has " + std::to_string(field.distance.size()) +
                " distances and " + std::to_string(field.label.size()) + " labels, the canvas " +
                std::to_string(canvas.slot_count()) + " slots");
  // As the nerve checks it (the seeds were, by checked_dual_seeds): bad labels and NaN distances
  // gave edges and faces with no error, unreached.
  require_insertable_field(canvas, field, seeds.size(), "curved dual");
  require_seeds_of_field(canvas, field, seeds);
  if (locals && locals->fields.size() != seeds.size())
    throw Error("curved dual: " + std::to_string(locals->fields.size()) + " local fields for " +
                std::to_string(seeds.size()) + " seeds");
  if (locals && locals->canvas_hash != canvas.content_hash())
    throw Error(
        "curved dual: the local fields were computed on another canvas (or this one "
        "changed since)");
  if (locals) require_seeds_of_locals(*locals, seeds);
}

// Faces need u_a beyond a's cell: only with local fields. The opposite edge of a triangle is a
// face of it, hence a nerve edge (the nerve is closed under faces). A face traced towards the
// apex seeds[0] with geodesics that missed it is traced again towards each other seed of the
// triangle, from that seed's opposite edge, and the patch with the smallest share of missed
// geodesics is kept: the smallest seed is an arbitrary apex, and its opposite edge can lie where
// its local field is not known or its descent does not lead back (3D hyperbolic_shock, 48^3, 400
// seeds: 378 unreached faces of 5440 with seeds[0] as apex, 85 with the best of the three, before
// the tracer's fallbacks; none now). Where the metric is nearly uniform, the other seeds' local
// fields hold the triangle only in part (a top simplex is then in the stars of its triangles'
// first apexes only, local_fields.cpp).
void build_faces(const Canvas& canvas, const GeodesicTracer& tracer, const Nerve& nerve,
                 const std::vector<Vec3>& seeds, CurvedDual& dual) {
  dual.faces.resize(nerve.triangles.size());
  detail::parallel_for(nerve.triangles.size(), 16, [&](std::size_t t) {
    const NerveSimplex& triangle = nerve.triangles[t];
    CurvedFace& face = dual.faces[t];
    for (int apex = 0; apex < 3 && !face.reached(); ++apex) {
      NerveSimplex rotated = triangle;  // the apex first, its opposite edge ascending
      rotated.seeds = {triangle.seeds[apex], triangle.seeds[apex == 0 ? 1 : 0],
                       triangle.seeds[apex == 2 ? 1 : 2], -1};
      const NerveSimplex* opposite = nerve.find({rotated.seeds[1], rotated.seeds[2]});
      if (!opposite)
        throw Error("curved dual: the nerve has triangle (" + std::to_string(triangle.seeds[0]) +
                    ", " + std::to_string(triangle.seeds[1]) + ", " +
                    std::to_string(triangle.seeds[2]) + ") but not its edge (" +
                    std::to_string(rotated.seeds[1]) + ", " + std::to_string(rotated.seeds[2]) +
                    ")");
      const auto e = static_cast<std::size_t>(opposite - nerve.edges.data());
      CurvedFace traced = detail::build_curved_face(canvas, tracer, rotated, dual.edges[e], seeds);
      if (apex == 0 ||
          traced.unreached_geodesics * face.geodesics < face.unreached_geodesics * traced.geodesics)
        face = std::move(traced);
    }
  });
  for (const CurvedFace& f : dual.faces) {
    dual.unreached_faces += f.reached() ? 0 : 1;
    dual.staircase_faces += f.staircase_geodesics > 0 ? 1 : 0;
  }
}

}  // namespace

// build_curved_dual itself; the public entry point names a failed allocation.
static CurvedDual build_curved_dual_itself(const Canvas& canvas, const VoronoiField& field,
                                           const Nerve& nerve, const std::vector<Vec3>& given_seeds,
                                           const LocalFields* locals,
                                           const CurvedDualOptions& options) {
  const auto t0 = std::chrono::steady_clock::now();
  const std::vector<Vec3> seeds =
      dual::checked_dual_seeds(canvas, nerve, given_seeds, "curved dual");
  check_inputs(canvas, field, seeds, locals);
  CurvedDual dual;
  dual.dimension = canvas.dimension;
  dual.vertices = seeds;
  dual.local_fields = locals != nullptr;
  dual.edges.resize(nerve.edges.size());
  GeodesicTracer tracer(canvas, field, locals);
  tracer.set_pull_staircases(options.pull_staircases);
  detail::parallel_for(nerve.edges.size(), 64, [&](std::size_t e) {
    dual.edges[e] =
        trace_edge(canvas, tracer, nerve.edges[e], seeds, options.straighten_longer_edges);
  });
  for (const CurvedEdge& e : dual.edges) {
    dual.unreached_edges += e.reached() ? 0 : 1;
    dual.staircase_edges += e.staircase() ? 1 : 0;
    dual.straightened_edges += e.straightened ? 1 : 0;
  }
  if (locals) build_faces(canvas, tracer, nerve, seeds, dual);
  dual.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return dual;
}

CurvedDual build_curved_dual(const Canvas& canvas, const VoronoiField& field, const Nerve& nerve,
                             const std::vector<Vec3>& given_seeds, const LocalFields* locals,
                             const CurvedDualOptions& options) {
  return naming_out_of_memory("building the curved dual", [&] {
    return build_curved_dual_itself(canvas, field, nerve, given_seeds, locals, options);
  });
}

namespace {

template <std::size_t N>
void require_seeds_of(const std::array<int32_t, N>& seeds, std::size_t vertices, const char* what,
                      std::size_t index, const std::string& where) {
  for (const int32_t seed : seeds)
    if (seed < 0 || static_cast<std::size_t>(seed) >= vertices)
      throw Error(where + ": curved " + what + " " + std::to_string(index) + " names seed " +
                  std::to_string(seed) + ", not one of the dual's " + std::to_string(vertices));
}

}  // namespace

void require_consistent_curved_dual(const CurvedDual& dual, const std::string& where) {
  const std::size_t n = dual.vertices.size();
  for (std::size_t e = 0; e < dual.edges.size(); ++e) {
    const CurvedEdge& edge = dual.edges[e];
    require_seeds_of(edge.seeds, n, "edge", e, where);
    if (!edge.points.empty() && edge.bisector_index >= edge.points.size())
      throw Error(where + ": curved edge " + std::to_string(e) + " has its bisector point at " +
                  std::to_string(edge.bisector_index) + " of " +
                  std::to_string(edge.points.size()) + " points");
  }
  for (std::size_t f = 0; f < dual.faces.size(); ++f) {
    const CurvedFace& face = dual.faces[f];
    require_seeds_of(face.seeds, n, "face", f, where);
    for (const std::array<uint32_t, 3>& t : face.triangles)
      for (const uint32_t v : t)
        if (v >= face.points.size())
          throw Error(where + ": curved face " + std::to_string(f) + " has a triangle on point " +
                      std::to_string(v) + " of " + std::to_string(face.points.size()));
  }
}

void write_curved_dual_vtu(const std::string& path, const CurvedDual& dual) {
  require_consistent_curved_dual(dual, "cannot write " + path);
  std::vector<double> points;  // doubles: a dual far from the origin keeps its shape
  std::vector<int64_t> connectivity, offsets;
  std::vector<uint8_t> types, reached, staircase, straightened;
  std::vector<double> length;
  std::vector<int32_t> seed_a, seed_b;
  for (const CurvedEdge& e : dual.edges) {
    for (const Vec3& p : e.points) {
      connectivity.push_back(static_cast<int64_t>(points.size() / 3));
      for (int a = 0; a < 3; ++a) points.push_back(p[a]);
    }
    offsets.push_back(static_cast<int64_t>(connectivity.size()));
    types.push_back(kVtkPolyLine);
    reached.push_back(e.reached() ? 1 : 0);
    staircase.push_back(e.staircase() ? 1 : 0);
    straightened.push_back(e.straightened ? 1 : 0);
    length.push_back(e.length);
    seed_a.push_back(e.seeds[0]);
    seed_b.push_back(e.seeds[1]);
  }
  vtu::AppendedWriter appended;
  std::string xml = vtu::grid_geometry(appended, points, connectivity, offsets, types);
  xml += "<CellData Scalars=\"length\">\n";
  xml += appended.declare("Float64", "length", 1, length);
  xml += appended.declare("UInt8", "reached", 1, reached);
  xml += appended.declare("UInt8", "staircase", 1, staircase);
  xml += appended.declare("UInt8", "straightened", 1, straightened);
  xml += appended.declare("Int32", "seed_a", 1, seed_a);
  xml += appended.declare("Int32", "seed_b", 1, seed_b);
  xml += "</CellData>\n";
  vtu::publish(path, std::move(xml), appended);
}

}  // namespace rvor
