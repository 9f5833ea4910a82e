#pragma once
// The straight Riemannian Delaunay dual: the seeds joined by straight simplices, one per simplex
// of the nerve (nerve.h), checked with exact predicates and measured in the metric.
//
// Top simplices are tetrahedra in 3D and triangles in 2D. The checks (counted in DualChecks, the
// offending elements listed so they can be written out and refined):
//  - inverted: the element's orientation disagrees with the majority of its connected component,
//    once elements are oriented consistently across shared facets (flat elements count too);
//  - intersecting: two top simplices whose intersection is more than their common face (exact
//    tests on the pairs whose bounding boxes overlap);
//  - non_manifold: facets of more than two top simplices, and boundary facets that do not close
//    into a manifold (3D: a boundary edge not in exactly two boundary triangles; 2D: a boundary
//    vertex not in exactly two boundary edges);
//  - is_triangulation: there are top simplices, none inverted, none intersecting, no
//    non-manifold facet, and the complex of the top simplices has the domain's topology as far
//    as Euler characteristics tell: the canvas's (its active voxels as closed cubes: 1 for a ball,
//    0 for a solid torus, 2 for two balls or a ball with a cavity), its boundary twice that in 3D
//    (closed surfaces; circles in 2D, 0). It then is an embedded triangulation of its own polytope;
//    near the domain boundary this polytope can be smaller than the domain, because a Delaunay
//    simplex is witnessed only where its Voronoi vertex lies in the domain (the lower simplices
//    witnessed there stay listed as "dangling"), and a part of the domain too thin for a simplex
//    can leave seeds out (unused_vertices).
#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "rvor/canvas.h"
#include "rvor/nerve.h"

namespace rvor {

struct DualChecks {
  std::size_t inverted = 0;      // top simplices
  std::size_t intersecting = 0;  // top simplices in at least one intersecting pair
  std::size_t intersecting_pairs = 0;
  std::size_t non_manifold = 0;          // facets (and boundary edges/vertices) as defined above
  std::size_t degenerate_witnesses = 0;  // from the nerve
  // Top simplices with another seed within half a voxel diameter (the voxel's diagonal along the
  // metric's strongest axis, in the metric at the witness) of their circumsphere: the canvas
  // cannot order such seeds, the metric decided (see build_straight_dual). Witnessed simplices
  // with a seed inside their circumsphere were removed (`near_degenerate_removed`); Delaunay
  // simplices of such configurations that the canvas missed were added (`near_degenerate_added`).
  std::size_t near_degenerate = 0;
  std::size_t near_degenerate_removed = 0;
  std::size_t near_degenerate_added = 0;
  std::size_t dangling = 0;  // lower simplices of the nerve that are no face of a top simplex
  std::size_t unused_vertices = 0;        // seeds in no top simplex
  int euler_characteristic = 0;           // of the complex of the top simplices and their faces
  int boundary_euler_characteristic = 0;  // of its boundary (3D: triangles; 2D: edges)
  int domain_euler_characteristic = 1;    // of the canvas's active voxels as closed cubes
  bool is_triangulation = false;

  // Indices into the top simplices, ascending.
  std::vector<std::size_t> inverted_elements, intersecting_elements;
  std::vector<std::array<std::size_t, 2>> intersecting_element_pairs;  // first kMaxListed pairs
  // Non-manifold facets as sorted seed tuples (2D: the edge in entries 0,1; entry 2 is -1).
  std::vector<std::array<int32_t, 3>> non_manifold_facets;
  static constexpr std::size_t kMaxListed = 100000;
};

// Per top simplex, in the metric. Lengths of an edge: in the metric of either endpoint's seed
// voxel, averaged. Shape quality (1 for a regular simplex of the metric, 0 for a flat one):
// triangles 4 sqrt(3) A / sum l^2, tetrahedra 216 sqrt(3) V^2 / (sum face areas)^3, evaluated in
// each vertex's metric, the minimum kept. Angles (triangle angles in 2D, dihedral angles in 3D,
// degrees) in the mean of the vertices' metrics.
struct ElementQuality {
  double quality = 0.0;
  double min_edge_length = 0.0, max_edge_length = 0.0;
  double min_angle = 0.0, max_angle = 0.0;
};

struct QualitySummary {
  std::size_t elements = 0;
  double min_quality = 0.0, mean_quality = 0.0;
  std::array<std::size_t, 10> quality_histogram{};  // bins of width 0.1 on [0, 1]
  double min_angle = 0.0, max_angle = 0.0;          // degrees, over all elements
  double min_edge_length = 0.0, mean_edge_length = 0.0, max_edge_length = 0.0;  // all dual edges
};

// Bits of StraightDual::flags.
enum DualFlag : uint8_t {
  kDualInverted = 1,
  kDualIntersecting = 2,
  kDualNonManifold = 4,     // has a non-manifold facet
  kDualNearDegenerate = 8,  // decided by the metric, not confirmed by the canvas (DualChecks)
};

struct StraightDual {
  int dimension = 3;
  std::vector<Vec3> vertices;        // the seeds (vertex i = seed i)
  std::vector<Mat3> vertex_metrics;  // the metric at each seed's voxel
  std::vector<std::array<int32_t, 2>> edges;
  std::vector<std::array<int32_t, 3>> triangles;
  std::vector<std::array<int32_t, 4>> tetrahedra;  // empty in 2D
  std::vector<ElementQuality> quality;             // per top simplex
  std::vector<uint8_t> flags;                      // per top simplex, DualFlag bits
  DualChecks checks;
  QualitySummary quality_summary;
  double seconds = 0.0;

  std::size_t top_count() const { return dimension == 3 ? tetrahedra.size() : triangles.size(); }
  // Vertices of top simplex t (3 entries in 2D, the 4th is -1). Throws rvor::Error for t past
  // top_count().
  std::array<int32_t, 4> top_simplex(std::size_t t) const;
};

// Throws rvor::Error naming `where` unless `dual` holds together as build_straight_dual makes it:
// dimension 2 or 3, a quality and flags entry per top simplex, every simplex's and edge's vertex
// among the vertices. The writers check a dual they are given (one built or edited by hand read
// past its vertices).
void require_consistent_dual(const StraightDual& dual, const std::string& where);

// Builds and checks the straight dual of the nerve. `seeds` are the propagation's seeds (label
// i = seeds[i]; on a 2D canvas their z is read as 0, as the propagators read it); each must lie
// in an active voxel. Throws rvor::Error on a nerve/seed mismatch (counts, dimension, a simplex
// naming a seed that is not there). Top simplices are the nerve's, except where d+2 or more seeds
// are cospherical to within about a voxel (a Voronoi edge the canvas cannot resolve): there the
// Delaunay triangulation of the configuration in the metric at the witness (CGAL, exact
// predicates, so that exactly cospherical seeds get one triangulation) decides which of its
// simplices are Delaunay (exact for uniform metrics, the locally uniform approximation
// otherwise), and they are flagged near-degenerate. The metric is frozen only where it measures
// the configuration's sphere as every seed's own metric does to within that voxel; elsewhere (a
// strongly varying metric, coarse seeds) the simplex stays as witnessed.
// Lower simplices: the faces of the top simplices and the nerve's dangling ones.
struct StraightDualOptions {
  // Decide near-degenerate configurations in the metric (above). Off: the top simplices are
  // exactly the nerve's, as the canvas witnesses them (near_degenerate stays 0), e.g. to see how
  // well the canvas alone resolves the diagram. On a canvas too coarse for its seeds, deciding
  // can hide that: most top simplices are then flagged near-degenerate.
  bool decide_near_degenerate = true;
};

StraightDual build_straight_dual(const Canvas& canvas, const Nerve& nerve,
                                 const std::vector<Vec3>& seeds,
                                 const StraightDualOptions& options = {});

// The nerve with its near-degenerate configurations decided as build_straight_dual decides them:
// the faces of the top simplices the decision removes go, unless a kept or added top simplex has
// them too, and so does a simplex that is a face of no top once one of its faces went (the result
// stays closed under faces); those it adds come with their faces, unwitnessed (witness_count 0,
// both witnesses at the centroid of their seeds). The curved dual takes it, so that both duals
// have the same combinatorics.
Nerve decided_nerve(const Canvas& canvas, const Nerve& nerve, const std::vector<Vec3>& seeds);

// The dimension of the seeds' affine hull, by exact predicates on their coordinates (z read as 0
// where `dimension` is 2): -1 for no seed, 0 where they all coincide, 1 where they are collinear,
// 2 coplanar, else 3. Below `dimension`, a straight dual can have no element that is not flat.
int seeds_affine_dimension(const std::vector<Vec3>& seeds, int dimension);

// The `dual` object of report.json as JSON text: vertices, edges, triangles, tetrahedra,
// inverted, intersecting, intersecting_pairs, non_manifold, degenerate_witnesses,
// near_degenerate (and _removed, _added), dangling,
// unused_vertices, euler_characteristic, boundary_euler_characteristic,
// domain_euler_characteristic, is_triangulation, seconds, and `quality` (min, mean,
// histogram, angles, edge lengths).
std::string dual_report_json(const StraightDual& dual);

// Both writers give each element positively oriented (counter-clockwise triangles, tetrahedra of
// positive volume) unless it is inverted, which they give as its neighbours orient it: negatively.
// VTK .vtu of the top simplices (tetrahedra / triangles). Cell data: quality, min_angle,
// max_angle, min_edge_length, max_edge_length, inverted, intersecting, non_manifold, flags;
// point data: label. With only_flagged, just the offending elements. Atomic.
void write_dual_vtu(const std::string& path, const StraightDual& dual, bool only_flagged = false);

// Medit .mesh: triangles in 2D; tetrahedra and their boundary triangles in 3D, facing out of
// their tetrahedron (into an inverted one). Reference tags:
// 1 for valid elements, 2 for flagged ones. Atomic.
void write_dual_medit(const std::string& path, const StraightDual& dual);

}  // namespace rvor
