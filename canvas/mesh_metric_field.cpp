// The metric field defined by tensors at the vertices of a Medit mesh (triangles in 2D,
// tetrahedra in 3D): point location in a uniform grid of buckets, barycentric coordinates, and
// Log-Euclidean interpolation G(p) = exp(sum_i lambda_i log G_i).
//
// Points outside the mesh take the interpolated metric at the closest point of the mesh (so the
// field is continuous across the mesh boundary): the closest point is searched exactly, ring of
// buckets by ring of buckets, until no unvisited bucket can hold anything closer.
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <optional>

#include <Eigen/Geometry>
#include <Eigen/LU>

#include "closest_element_tree.h"
#include "medit_internal.h"
#include "rvor/error.h"
#include "rvor/medit.h"
#include "rvor/metric_field.h"

namespace rvor {

namespace {

using Index3 = std::array<int, 3>;
using Barycentric = std::array<double, 4>;  // the 4th is 0 for triangles

// A point counts as inside an element when no barycentric coordinate is below this: shared
// faces then belong to both neighbours, which interpolate to the same value there.
constexpr double kInsideTolerance = 1e-12;

// Where a query lands: an element, and barycentric coordinates (>= 0, sum 1) in it.
struct Location {
  int element = -1;
  Barycentric weights{};
};

// The half-space normal . x <= offset.
struct Plane {
  Vec3 normal = Vec3::Zero();
  double offset = 0;
};

// Closest point of segment [a, b] to p.
Vec3 closest_point_on_segment(const Vec3& p, const Vec3& a, const Vec3& b) {
  const Vec3 ab = b - a;
  const double length2 = ab.squaredNorm();
  if (length2 <= 0) return a;
  const double t = std::clamp((p - a).dot(ab) / length2, 0.0, 1.0);
  return a + t * ab;
}

// Closest point of triangle abc to p (Ericson, Real-Time Collision Detection, 5.1.5): finds
// the Voronoi region of the triangle's features that holds p.
Vec3 closest_point_on_triangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
  const Vec3 ab = b - a, ac = c - a, ap = p - a;
  const double d1 = ab.dot(ap), d2 = ac.dot(ap);
  if (d1 <= 0 && d2 <= 0) return a;
  const Vec3 bp = p - b;
  const double d3 = ab.dot(bp), d4 = ac.dot(bp);
  if (d3 >= 0 && d4 <= d3) return b;
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) return a + d1 / (d1 - d3) * ab;
  const Vec3 cp = p - c;
  const double d5 = ab.dot(cp), d6 = ac.dot(cp);
  if (d6 >= 0 && d5 <= d6) return c;
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) return a + d2 / (d2 - d6) * ac;
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0)
    return b + (d4 - d3) / ((d4 - d3) + (d5 - d6)) * (c - b);
  const double denominator = va + vb + vc;
  if (denominator <= 0) return closest_point_on_segment(p, a, b);  // degenerate face
  return a + (vb / denominator) * ab + (vc / denominator) * ac;
}

// Negative weights (points slightly outside, rounding) clamped to 0, the rest renormalised.
Barycentric clamped(Barycentric weights) {
  double sum = 0;
  for (double& w : weights) sum += (w = std::max(w, 0.0));
  for (double& w : weights) w /= sum;
  return weights;
}

// The simplices of the mesh with the affine frames that give barycentric coordinates.
class SimplexSet {
 public:
  SimplexSet(int dimension, std::vector<Vec3> vertices, std::vector<std::array<int, 4>> cells)
      : dimension_(dimension), vertices_(std::move(vertices)), cells_(std::move(cells)) {
    frames_.reserve(cells_.size());
    for (const auto& cell : cells_) frames_.push_back(make_frame(cell));
  }

  int dimension() const { return dimension_; }
  int vertex_count() const { return dimension_ + 1; }
  std::size_t size() const { return cells_.size(); }
  bool degenerate(std::size_t e) const { return !frames_[e].valid; }
  const std::array<int, 4>& cell(std::size_t e) const { return cells_[e]; }
  const Vec3& vertex(std::size_t e, int k) const { return vertices_[cells_[e][k]]; }
  // The bounding box of element e.
  Box box(std::size_t e) const {
    Box b{vertex(e, 0), vertex(e, 0)};
    for (int k = 1; k < vertex_count(); ++k)
      b.lo = b.lo.cwiseMin(vertex(e, k)), b.hi = b.hi.cwiseMax(vertex(e, k));
    return b;
  }
  // The bounding box of the elements (vertices no element uses do not count).
  Box bounds() const {
    Box b{Vec3::Constant(std::numeric_limits<double>::infinity()),
          Vec3::Constant(-std::numeric_limits<double>::infinity())};
    for (std::size_t e = 0; e < size(); ++e) {
      const Box element = box(e);
      b.lo = b.lo.cwiseMin(element.lo), b.hi = b.hi.cwiseMax(element.hi);
    }
    return b;
  }

  // The planes of the faces (edges in 2D) of element e, with normals pointing out of it.
  std::array<Plane, 4> outward_faces(std::size_t e) const {
    std::array<Plane, 4> faces{};
    for (int k = 0; k < vertex_count(); ++k) {
      const Vec3& opposite = vertex(e, k);
      const Vec3& a = vertex(e, (k + 1) % vertex_count());
      const Vec3& b = vertex(e, (k + 2) % vertex_count());
      Vec3 normal = dimension_ == 2 ? Vec3(b.y() - a.y(), a.x() - b.x(), 0)
                                    : Vec3((b - a).cross(vertex(e, (k + 3) % 4) - a));
      if (normal.dot(opposite - a) > 0) normal = -normal;
      faces[k] = {normal, normal.dot(a)};
    }
    return faces;
  }

  Barycentric barycentric(std::size_t e, const Vec3& p) const {
    const Vec3 local = frames_[e].inverse * (p - frames_[e].origin);
    if (dimension_ == 2) return {1 - local[0] - local[1], local[0], local[1], 0};
    return {1 - local[0] - local[1] - local[2], local[0], local[1], local[2]};
  }

  // The closest point of element e to p, which lies outside it.
  Vec3 closest_point(std::size_t e, const Vec3& p) const {
    Vec3 best = vertex(e, 0);
    double best_distance2 = std::numeric_limits<double>::infinity();
    const auto consider = [&](const Vec3& q) {
      const double d2 = (q - p).squaredNorm();
      if (d2 < best_distance2) {
        best_distance2 = d2;
        best = q;
      }
    };
    if (dimension_ == 2) {
      for (int k = 0; k < 3; ++k)
        consider(closest_point_on_segment(p, vertex(e, k), vertex(e, (k + 1) % 3)));
    } else {
      for (int k = 0; k < 4; ++k)
        consider(closest_point_on_triangle(p, vertex(e, (k + 1) % 4), vertex(e, (k + 2) % 4),
                                           vertex(e, (k + 3) % 4)));
    }
    return best;
  }

 private:
  struct Frame {
    Vec3 origin = Vec3::Zero();
    Mat3 inverse = Mat3::Identity();
    bool valid = false;
  };

  Frame make_frame(const std::array<int, 4>& cell) const {
    Frame frame;
    frame.origin = vertices_[cell[0]];
    Mat3 edges = Mat3::Identity();  // 2D: the third column stays e_z, so z never matters
    double scale = 0;
    for (int k = 1; k <= dimension_; ++k) {
      edges.col(k - 1) = vertices_[cell[k]] - frame.origin;
      scale = std::max(scale, edges.col(k - 1).norm());
    }
    const double determinant = edges.determinant();
    // Zero-volume elements hold no point of their own: their neighbours cover them.
    frame.valid =
        std::isfinite(determinant) && std::abs(determinant) > 1e-12 * std::pow(scale, dimension_);
    if (frame.valid) frame.inverse = edges.inverse();
    return frame;
  }

  int dimension_;
  std::vector<Vec3> vertices_;
  std::vector<std::array<int, 4>> cells_;
  std::vector<Frame> frames_;
};

// A uniform grid over the mesh's bounding box; each bucket lists the elements whose bounding
// box overlaps it (compressed rows: bucket b holds items_[start_[b] .. start_[b+1])).
class BucketGrid {
 public:
  explicit BucketGrid(const SimplexSet& simplices) {
    size_grid(simplices);
    fill_buckets(simplices);
  }

  // The bucket holding p, or the nearest one when p is outside the grid.
  Index3 bucket_of(const Vec3& p) const {
    Index3 index{};
    for (int a = 0; a < 3; ++a) {
      const double t = std::floor((p[a] - lo_[a]) / size_[a]);
      index[a] = static_cast<int>(std::clamp(t, 0.0, static_cast<double>(counts_[a] - 1)));
    }
    return index;
  }

  template <typename Visit>
  void for_each_element(const Index3& bucket, Visit visit) const {
    const std::size_t b = linear(bucket);
    for (int i = start_[b]; i < start_[b + 1]; ++i) visit(items_[i]);
  }

 private:
  // About one bucket per element, in cubes (squares in 2D) as far as the box allows.
  void size_grid(const SimplexSet& simplices) {
    // Over the elements only: a vertex no element uses (one far away, say) would otherwise
    // stretch the grid until the mesh falls into a few buckets.
    const Box bounds = simplices.bounds();
    const Vec3 lo = bounds.lo, hi = bounds.hi;
    const int d = simplices.dimension();
    const Vec3 extent = (hi - lo).cwiseMax(1e-300);
    double volume = 1;
    for (int a = 0; a < d; ++a) volume *= extent[a];
    const double target = std::max<double>(1.0, static_cast<double>(simplices.size()));
    double side = std::pow(volume / target, 1.0 / d);
    // A flat box rounds its thin axes up to one bucket, multiplying the others: widen the
    // buckets until their number is back near the target.
    while (set_counts(extent, side, d) > 2 * target + 8) side *= 1.25;
    lo_ = lo;
    if (d == 2) lo_[2] = -0.5;  // z is ignored in 2D: one layer of buckets around z = 0
  }

  // Returns the number of buckets.
  double set_counts(const Vec3& extent, double side, int d) {
    constexpr int kMaxPerAxis = 1 << 10;
    double buckets = 1;
    for (int a = 0; a < 3; ++a) {
      const double wanted = a < d ? std::ceil(extent[a] / side) : 1.0;
      counts_[a] = static_cast<int>(std::clamp(wanted, 1.0, static_cast<double>(kMaxPerAxis)));
      size_[a] = a < d ? extent[a] / counts_[a] : 1.0;
      buckets *= counts_[a];
    }
    return buckets;
  }

  void fill_buckets(const SimplexSet& simplices) {
    const std::size_t buckets =
        static_cast<std::size_t>(counts_[0]) * static_cast<std::size_t>(counts_[1]) * counts_[2];
    std::vector<int> count(buckets + 1, 0);
    for_each_overlap(simplices, [&](std::size_t b, int) { ++count[b + 1]; });
    for (std::size_t b = 0; b < buckets; ++b) count[b + 1] += count[b];
    start_ = count;
    items_.resize(static_cast<std::size_t>(count[buckets]));
    for_each_overlap(simplices, [&](std::size_t b, int e) { items_[count[b]++] = e; });
  }

  template <typename Visit>
  void for_each_overlap(const SimplexSet& simplices, Visit visit) const {
    for (std::size_t e = 0; e < simplices.size(); ++e) {
      if (simplices.degenerate(e)) continue;
      const Box box = simplices.box(e);
      const auto faces = simplices.outward_faces(e);
      visit_block(faces, simplices.vertex_count(), bucket_of(box.lo), bucket_of(box.hi),
                  [&](const Index3& bucket) { visit(linear(bucket), static_cast<int>(e)); });
    }
  }

  // The buckets of the block [first, last] that may meet the element: the block is split in two
  // along its longest side while it may, so that a long thin element across the grid (an
  // anisotropic mesh's) costs the buckets along it, not every bucket of its bounding box.
  template <typename Visit>
  void visit_block(const std::array<Plane, 4>& faces, int face_count, const Index3& first,
                   const Index3& last, Visit&& visit) const {
    if (!may_intersect(faces, face_count, first, last)) return;
    int axis = 0;
    for (int a = 1; a < 3; ++a)
      if (last[a] - first[a] > last[axis] - first[axis]) axis = a;
    if (last[axis] == first[axis]) return visit(first);  // one bucket
    const int middle = (first[axis] + last[axis]) / 2;
    Index3 low_last = last, high_first = first;
    low_last[axis] = middle;
    high_first[axis] = middle + 1;
    visit_block(faces, face_count, first, low_last, visit);
    visit_block(faces, face_count, high_first, last, visit);
  }

  // False when the block of buckets [first, last] lies entirely outside one face of the
  // element. Most buckets that only overlap an element's bounding box go (a Kuhn tetrahedron
  // fills 1/6 of its box), so queries test fewer candidates. It never drops a bucket the element
  // meets.
  bool may_intersect(const std::array<Plane, 4>& faces, int face_count, const Index3& first,
                     const Index3& last) const {
    const Vec3 block_lo = lo_ + Vec3(first[0], first[1], first[2]).cwiseProduct(size_);
    const Vec3 block_hi = lo_ + Vec3(last[0] + 1, last[1] + 1, last[2] + 1).cwiseProduct(size_);
    const Vec3 half = 0.5 * (block_hi - block_lo);
    const Vec3 center = block_lo + half;
    for (int f = 0; f < face_count; ++f) {
      const Plane& face = faces[f];
      const double nearest_corner = face.normal.dot(center) - face.normal.cwiseAbs().dot(half);
      const double slack = 1e-9 * face.normal.norm() * size_.norm();
      if (nearest_corner > face.offset + slack) return false;
    }
    return true;
  }

  std::size_t linear(const Index3& index) const {
    return (static_cast<std::size_t>(index[2]) * counts_[1] + index[1]) * counts_[0] + index[0];
  }

  Vec3 lo_ = Vec3::Zero();
  Vec3 size_ = Vec3::Ones();
  Index3 counts_{1, 1, 1};
  std::vector<int> start_;
  std::vector<int> items_;
};

// Point location: the element holding p, else the closest point of the mesh.
class PointLocator {
 public:
  explicit PointLocator(const SimplexSet& simplices)
      : simplices_(simplices), grid_(simplices), tree_(element_boxes(simplices)) {}

  Location locate(const Vec3& p) const {
    if (const auto inside = containing_element(grid_.bucket_of(p), p)) return *inside;
    return closest_location(p);
  }

 private:
  // Bounding boxes of the elements, empty for degenerate ones (never the closest).
  static std::vector<Box> element_boxes(const SimplexSet& simplices) {
    std::vector<Box> boxes(simplices.size(), Box{Vec3::Constant(1), Vec3::Constant(0)});
    for (std::size_t e = 0; e < simplices.size(); ++e)
      if (!simplices.degenerate(e)) boxes[e] = simplices.box(e);
    return boxes;
  }

  // Every element holding p overlaps p's bucket, so one bucket decides whether p is inside.
  std::optional<Location> containing_element(const Index3& bucket, const Vec3& p) const {
    std::optional<Location> found;
    grid_.for_each_element(bucket, [&](int e) {
      if (found) return;
      const Barycentric weights = simplices_.barycentric(e, p);
      if (*std::min_element(weights.begin(), weights.end()) >= -kInsideTolerance)
        found = Location{e, clamped(weights)};
    });
    return found;
  }

  Location closest_location(const Vec3& p) const {
    const int e = tree_.closest(
        p, [&](int element) { return (simplices_.closest_point(element, p) - p).norm(); });
    return {e, clamped(simplices_.barycentric(e, simplices_.closest_point(e, p)))};
  }

  const SimplexSet& simplices_;
  BucketGrid grid_;
  detail::ClosestElementTree tree_;
};

class MeshMetricField final : public MetricField {
 public:
  MeshMetricField(SimplexSet simplices, const std::vector<Mat3>& tensors, std::string description)
      : simplices_(std::move(simplices)),
        locator_(simplices_),
        description_(std::move(description)),
        box_(simplices_.bounds()) {
    // Logarithms once per vertex: a query is then a weighted sum and one exponential.
    vertex_logs_.reserve(tensors.size());
    for (const Mat3& G : tensors) vertex_logs_.push_back(metric_log(G));
  }

  MeshMetricField(const MeshMetricField&) = delete;  // locator_ refers to simplices_
  MeshMetricField& operator=(const MeshMetricField&) = delete;

  int dimension() const override { return simplices_.dimension(); }

  Mat3 at(const Vec3& position) const override {
    Vec3 p = position;
    if (simplices_.dimension() == 2) p[2] = 0;
    if (!p.allFinite()) throw Error(description_ + ": query at a non-finite position");
    const Location location = locator_.locate(p);
    Mat3 log_sum = Mat3::Zero();
    for (int k = 0; k < simplices_.vertex_count(); ++k)
      log_sum += location.weights[k] * vertex_logs_[simplices_.cell(location.element)[k]];
    Mat3 G = metric_exp(log_sum);
    if (simplices_.dimension() == 2) {  // the 2D convention, exactly rather than to rounding
      G.row(2).setZero();
      G.col(2).setZero();
      G(2, 2) = 1.0;
    }
    return G;
  }

  std::string description() const override { return description_; }
  std::optional<Box> natural_domain() const override { return box_; }

 private:
  SimplexSet simplices_;
  PointLocator locator_;
  std::vector<Mat3> vertex_logs_;
  std::string description_;
  Box box_;  // the elements' bounds (vertices no element uses do not count)
};

// Triangles of a 2D mesh, tetrahedra of a 3D one, as 4-vertex cells.
std::vector<std::array<int, 4>> interpolation_cells(const MeditMesh& mesh,
                                                    const std::string& mesh_path) {
  std::vector<std::array<int, 4>> cells;
  if (mesh.dimension == 2) {
    for (const auto& t : mesh.triangles) cells.push_back({t[0], t[1], t[2], t[2]});
  } else {
    cells.assign(mesh.tetrahedra.begin(), mesh.tetrahedra.end());
  }
  if (cells.empty())
    throw Error(mesh_path + ": no " + (mesh.dimension == 2 ? "Triangles" : "Tetrahedra") +
                " to interpolate the metric on");
  return cells;
}

}  // namespace

std::unique_ptr<MetricField> load_mesh_metric(const std::string& mesh_path,
                                              const std::string& sol_path) {
  MeditMesh mesh = read_medit_mesh(mesh_path);
  auto cells = interpolation_cells(mesh, mesh_path);
  const auto sol =
      detail::read_medit_sol(sol_path, static_cast<int>(mesh.vertices.size()), mesh.dimension);
  SimplexSet simplices(mesh.dimension, std::move(mesh.vertices), std::move(cells));
  bool any_valid = false;
  for (std::size_t e = 0; e < simplices.size() && !any_valid; ++e)
    any_valid = !simplices.degenerate(e);
  if (!any_valid)
    throw Error(mesh_path +
                ": every element is degenerate: flat (the determinant of its edges from its first "
                "vertex below 1e-12 of the longest one's length to the power 2 in 2D, 3 in 3D) "
                "or too large for double precision");
  return std::make_unique<MeshMetricField>(std::move(simplices), sol.tensors,
                                           "metric from " + sol_path + " on " + mesh_path);
}

}  // namespace rvor
