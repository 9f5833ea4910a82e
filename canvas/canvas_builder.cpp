#include "rvor/canvas_builder.h"

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <mutex>
#include <optional>
#include <sstream>
#include <tuple>

#include <openvdb/tools/Morphology.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "implicit_shapes.h"
#include "memory_estimate.h"
#include "rvor/error.h"
#include "surface_mesh.h"
#include "vdb_support.h"

namespace rvor {

namespace {

using BoolTree = openvdb::BoolTree;
using BoolLeaf = BoolTree::LeafNodeType;
constexpr int kEdge = Canvas::kBrickEdge;
static_assert(BoolLeaf::DIM == kEdge, "canvas bricks are OpenVDB leaves");

constexpr int kCoarseEstimateResolution = 64;

// Where the voxels go: cell-centred, `resolution` voxels along the longest side of the bounds
// (the same placement as tests/support/box_canvas.cpp).
struct Placement {
  int dimension = 3;
  double h = 0;
  Vec3 origin = Vec3::Zero();
  std::array<int, 3> dims{};

  int edge(int axis) const { return axis == 2 && dimension == 2 ? 1 : kEdge; }
  std::array<int, 3> brick_grid() const {
    return {(dims[0] + kEdge - 1) / kEdge, (dims[1] + kEdge - 1) / kEdge,
            (dims[2] + edge(2) - 1) / edge(2)};
  }
  double index_box_voxels() const { return double(dims[0]) * dims[1] * dims[2]; }
  double brick_table_cells() const {
    const auto g = brick_grid();
    return double(g[0]) * g[1] * g[2];
  }
  bool in_box(const openvdb::Coord& c) const {
    return c.x() >= 0 && c.y() >= 0 && c.z() >= 0 && c.x() < dims[0] && c.y() < dims[1] &&
           c.z() < dims[2];
  }
  Vec3 world(const openvdb::Coord& c) const { return origin + h * Vec3(c.x(), c.y(), c.z()); }
};

// What the domain resolves to: its kind-specific geometry and bounds.
struct ResolvedDomain {
  const DomainSpec* spec = nullptr;
  int dimension = 3;
  Box bounds;
  std::optional<ImplicitShape> shape;
  std::optional<SurfaceMesh> mesh;
};

[[noreturn]] void fail_empty(const DomainSpec& domain, int resolution) {
  throw Error("domain " + domain.description() + " has no voxel inside at resolution " +
              std::to_string(resolution) + ": it is empty or thinner than a voxel");
}

double farthest_coordinate(const Box& bounds) {
  return std::max(bounds.lo.cwiseAbs().maxCoeff(), bounds.hi.cwiseAbs().maxCoeff());
}

// Distances are floats. A mesh is checked as soon as read: the checks of its geometry took a unit
// cube 1e16 from the origin (its corners rounded together) for one with slivers, and a vertex at
// 1e300 for a self-intersection.
void check_coordinates(const DomainSpec& domain, const Box& bounds) {
  constexpr double kLargestCoordinate = 1e15;
  if (farthest_coordinate(bounds) <= kLargestCoordinate) return;
  std::ostringstream problem;
  problem << "domain " << domain.description() << " has coordinates beyond +-" << kLargestCoordinate
          << " (distances are 32-bit floats): express it in larger units";
  throw Error(problem.str());
}

ResolvedDomain resolve(const DomainSpec& domain) {
  using Kind = DomainSpec::Kind;
  if (domain.kind != Kind::Box && domain.kind != Kind::Rectangle && domain.kind != Kind::Mesh &&
      domain.kind != Kind::Implicit)  // a DomainSpec made by hand: it built a box
    throw Error("domain of unknown kind " + std::to_string(static_cast<int>(domain.kind)) +
                ": make it with parse_domain");
  ResolvedDomain resolved;
  resolved.spec = &domain;
  resolved.dimension = domain.dimension();
  resolved.bounds = domain.bounds;
  if (domain.kind == DomainSpec::Kind::Rectangle)
    resolved.bounds.lo.z() = resolved.bounds.hi.z() = 0;
  if (domain.kind == DomainSpec::Kind::Implicit) {
    resolved.shape = ImplicitShape::parse(domain.implicit);
    resolved.bounds = resolved.shape->bounds();
  }
  if (domain.kind == DomainSpec::Kind::Mesh) {
    resolved.mesh = read_surface_mesh(domain.path);
    resolved.bounds = bounds_of(*resolved.mesh);
    if (!resolved.mesh->triangles.empty()) check_coordinates(domain, resolved.bounds);
    require_closed(*resolved.mesh, domain.path);
    require_no_self_intersection(*resolved.mesh, domain.path);
  }
  return resolved;
}

// What the numbers can hold: OpenVDB transforms (the canvas's, the .vdb written) refuse voxels
// with h^3 < 3e-15; voxel indices are 32-bit; distances are floats (check_coordinates).
void check_scale(const DomainSpec& domain, const Box& bounds, double h) {
  constexpr double kSmallestVoxel = 1.5e-5, kFarthestVoxel = 1e9;
  check_coordinates(domain, bounds);
  const double farthest = farthest_coordinate(bounds);
  std::ostringstream problem;
  if (h < kSmallestVoxel)
    problem << "gives voxels of size " << h << ", below " << kSmallestVoxel
            << ", the smallest an OpenVDB transform takes: express it in smaller units or lower "
               "the resolution";
  else if (farthest / h > kFarthestVoxel)
    problem << "lies " << farthest / h << " voxels from the origin, beyond the " << kFarthestVoxel
            << " that voxel indices and double coordinates resolve: move it nearer the origin";
  if (!problem.str().empty()) throw Error("domain " + domain.description() + " " + problem.str());
}

Placement place_voxels(const ResolvedDomain& domain, int resolution) {
  Placement p;
  p.dimension = domain.dimension;
  const Vec3 extent = domain.bounds.hi - domain.bounds.lo;
  const double longest = p.dimension == 3 ? extent.maxCoeff() : std::max(extent.x(), extent.y());
  if (!(longest > 0)) fail_empty(*domain.spec, resolution);
  p.h = longest / resolution;
  check_scale(*domain.spec, domain.bounds, p.h);  // an extent past double's range among others
  const bool box = domain.spec->kind == DomainSpec::Kind::Box ||
                   domain.spec->kind == DomainSpec::Kind::Rectangle;
  for (int a = 0; a < 3; ++a) {
    p.dims[a] = static_cast<int>(std::lround(std::max(0.0, extent[a]) / p.h));
    // A box thinner than half a voxel across an axis has no voxel centre inside it (every voxel
    // of a box is active); the other domains' voxels are tested, and a thin one has none.
    if (p.dims[a] == 0 && box && a < p.dimension) fail_empty(*domain.spec, resolution);
    p.dims[a] = std::max(1, p.dims[a]);
  }
  if (p.dimension == 2) p.dims[2] = 1;
  p.origin = domain.bounds.lo + 0.5 * p.h * Vec3(1, 1, p.dimension == 3 ? 1 : 0);
  return p;
}

// --- topology: the active voxels of the domain as an OpenVDB tree in canvas index space ------

BoolTree::Ptr box_topology(const Placement& p) {
  auto tree = std::make_shared<BoolTree>(false);
  const auto unwinding = freeing_on_unwind(*tree);
  tree->denseFill(openvdb::CoordBBox(openvdb::Coord(0),
                                     openvdb::Coord(p.dims[0] - 1, p.dims[1] - 1, p.dims[2] - 1)),
                  true, true);
  tree->voxelizeActiveTiles();
  return tree;
}

// A block of leaves [lo, hi) in brick-grid coordinates.
struct LeafBlock {
  std::array<int, 3> lo, hi;
};

// Visits the blocks of leaves that may touch the shape, splitting until blocks are at most
// `min_leaves` leaves wide or lie entirely inside. The signed distance bound at a block's centre
// tells whether the block can touch the surface at all: this is what keeps the work
// proportional to the surface, not the bounding box.
template <typename Visit>
void visit_shape_blocks(const ImplicitShape& shape, const Placement& p, const LeafBlock& block,
                        int min_leaves, Visit&& visit) {
  Vec3 first, last;
  for (int a = 0; a < 3; ++a) {
    first[a] = block.lo[a] * p.edge(a);
    last[a] = std::min(block.hi[a] * p.edge(a), p.dims[a]) - 1;
  }
  const double half_diagonal = 0.5 * p.h * (last - first).norm();
  const double distance = shape.signed_distance_bound(p.origin + p.h * 0.5 * (first + last));
  if (distance > half_diagonal) return;
  int widest = 0;
  for (int a = 1; a < 3; ++a)
    if (block.hi[a] - block.lo[a] > block.hi[widest] - block.lo[widest]) widest = a;
  const int width = block.hi[widest] - block.lo[widest];
  if (distance < -half_diagonal || width <= min_leaves) {
    visit(block, first, last);
    return;
  }
  LeafBlock lower = block, upper = block;
  lower.hi[widest] = upper.lo[widest] = block.lo[widest] + width / 2;
  visit_shape_blocks(shape, p, lower, min_leaves, visit);
  visit_shape_blocks(shape, p, upper, min_leaves, visit);
}

LeafBlock whole_brick_grid(const Placement& p) {
  return LeafBlock{{0, 0, 0}, p.brick_grid()};
}

// Upper bound on the active voxels of an implicit shape: the voxels of every block, at most
// 64 per axis, that may touch it.
double coarse_implicit_voxels(const ImplicitShape& shape, const Placement& p) {
  const auto grid = p.brick_grid();
  const int widest = *std::max_element(grid.begin(), grid.end());
  const int min_leaves = std::max(1, widest / kCoarseEstimateResolution);
  double voxels = 0;
  visit_shape_blocks(shape, p, whole_brick_grid(p), min_leaves,
                     [&](const LeafBlock&, const Vec3& first, const Vec3& last) {
                       voxels += (last - first + Vec3::Ones()).prod();
                     });
  return voxels;
}

std::unique_ptr<BoolLeaf> shape_leaf(const ImplicitShape& shape, const Placement& p,
                                     const openvdb::Coord& leaf_origin) {
  auto leaf = std::make_unique<BoolLeaf>(leaf_origin, false, false);
  for (openvdb::Index offset = 0; offset < BoolLeaf::SIZE; ++offset) {
    const openvdb::Coord c = leaf->offsetToGlobalCoord(offset);
    if (p.in_box(c) && shape.contains(p.world(c))) leaf->setValueOn(offset, true);
  }
  return leaf;
}

BoolTree::Ptr implicit_topology(const ImplicitShape& shape, const Placement& p) {
  std::vector<openvdb::Coord> candidates;
  visit_shape_blocks(shape, p, whole_brick_grid(p), 1,
                     [&](const LeafBlock& block, const Vec3&, const Vec3&) {
                       for (int z = block.lo[2]; z < block.hi[2]; ++z)
                         for (int y = block.lo[1]; y < block.hi[1]; ++y)
                           for (int x = block.lo[0]; x < block.hi[0]; ++x)
                             candidates.emplace_back(x * kEdge, y * kEdge, z * p.edge(2));
                     });
  std::vector<std::unique_ptr<BoolLeaf>> leaves(candidates.size());
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, candidates.size()), [&](const auto& range) {
    for (std::size_t n = range.begin(); n != range.end(); ++n)
      leaves[n] = shape_leaf(shape, p, candidates[n]);
  });
  auto tree = std::make_shared<BoolTree>(false);
  const auto unwinding = freeing_on_unwind(*tree);
  for (auto& leaf : leaves)
    if (!leaf->isEmpty()) tree->addLeaf(leaf.release());
  return tree;
}

// The voxels whose centres lie inside the mesh (inside_runs: ray parity).
BoolTree::Ptr mesh_topology(const SurfaceMesh& mesh, const Placement& p) {
  auto tree = std::make_shared<BoolTree>(false);
  const auto unwinding = freeing_on_unwind(*tree);
  openvdb::tree::ValueAccessor<BoolTree> accessor(*tree);
  for (const VoxelRun& run : inside_runs(mesh, p.origin, p.h, p.dims))
    for (int i = run.i_begin; i < run.i_end; ++i)
      accessor.setValueOn(openvdb::Coord(i, run.j, run.k));
  return tree;
}

// The mesh voxelized at a coarse resolution, interior grown by one voxel to cover the surface band,
// scaled to the requested voxel size: a cheap estimate of the active voxel count.
double coarse_mesh_voxels(const ResolvedDomain& domain, const Placement& fine) {
  const Placement coarse = place_voxels(domain, kCoarseEstimateResolution);
  auto tree = mesh_topology(*domain.mesh, coarse);
  openvdb::tools::dilateActiveValues(*tree, 1, openvdb::tools::NN_FACE_EDGE_VERTEX);
  return double(tree->activeVoxelCount()) * std::pow(coarse.h / fine.h, 3);
}

// Checks the budget, less what the metric field holds, against an exact count (box), the index
// box, or a coarse estimate.
void check_budget(const ResolvedDomain& domain, const Placement& p, int resolution,
                  const MetricField& metric, std::uint64_t budget) {
  const double cells = p.brick_table_cells();
  const double box_voxels = p.index_box_voxels();
  const bool uniform = metric.is_uniform();
  const std::uint64_t held_bytes = metric.resident_bytes();
  const bool cheap_bound_fits =
      estimated_canvas_bytes(box_voxels, cells, uniform) + double(held_bytes) <=
      double(resolved_memory_budget(budget));
  double voxels = box_voxels;
  if (domain.spec->kind != DomainSpec::Kind::Box &&
      domain.spec->kind != DomainSpec::Kind::Rectangle && !cheap_bound_fits &&
      resolution > kCoarseEstimateResolution)
    voxels =
        domain.shape ? coarse_implicit_voxels(*domain.shape, p) : coarse_mesh_voxels(domain, p);
  check_memory_budget(voxels, cells, uniform, budget, held_bytes);
}

BoolTree::Ptr topology(const ResolvedDomain& domain, const Placement& p) {
  if (domain.shape) return implicit_topology(*domain.shape, p);
  if (domain.mesh) return mesh_topology(*domain.mesh, p);
  return box_topology(p);
}

// --- packing into canvas bricks ---------------------------------------------------------------

std::vector<const BoolLeaf*> leaves_in_box(const BoolTree& tree, const Placement& p) {
  std::vector<const BoolLeaf*> leaves;
  for (auto leaf = tree.cbeginLeaf(); leaf; ++leaf)
    for (auto voxel = leaf->cbeginValueOn(); voxel; ++voxel)
      if (p.in_box(voxel.getCoord())) {
        leaves.push_back(&*leaf);
        break;
      }
  // Bricks in (z, y, x) order, like a dense scan: neighbouring bricks stay close in memory.
  std::sort(leaves.begin(), leaves.end(), [](const BoolLeaf* a, const BoolLeaf* b) {
    const auto& oa = a->origin();
    const auto& ob = b->origin();
    return std::make_tuple(oa.z(), oa.y(), oa.x()) < std::make_tuple(ob.z(), ob.y(), ob.x());
  });
  return leaves;
}

// Position of a voxel inside its brick (x fastest), as Canvas::slot_of counts it.
std::size_t local_index(const openvdb::Coord& c, const Placement& p) {
  const int z = p.dimension == 3 ? (c.z() & (kEdge - 1)) : 0;
  return static_cast<std::size_t>((c.x() & (kEdge - 1)) +
                                  kEdge * ((c.y() & (kEdge - 1)) + kEdge * z));
}

// Whether two tensors have the same bits, word by word from the first entry: where tensors vary,
// the first nearly always differs already. Inline compares, not std::memcmp: a call per voxel took
// `build/bin/bench_canvas_build`'s euclidean case from 11.3-11.6 to 15.2-16.0 ms. (A tensor is only
// kept once it passed the check, so a NaN never matches one.)
bool same_bits(const Mat3& a, const Mat3& b) {
  std::uint64_t x[9], y[9];
  std::memcpy(x, a.data(), sizeof x);
  std::memcpy(y, b.data(), sizeof y);
  for (int n = 0; n < 9; ++n)
    if (x[n] != y[n]) return false;
  return true;
}

// Samples and validates the metric at every active voxel in parallel. On failure the error of
// the first failing brick (in brick order) is rethrown, so the report does not depend on timing.
void sample_metric(Canvas& canvas, const std::vector<const BoolLeaf*>& leaves, const Placement& p,
                   const MetricField& metric, const std::optional<Mat3>& uniform) {
  const std::string name = "'" + metric.description() + "'";
  std::atomic<std::size_t> first_failure{leaves.size()};
  std::mutex failure_mutex;
  std::string failure;
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, leaves.size()), [&](const auto& range) {
    // The last tensor given, checked and converted to its stored floats: a uniform metric (or a
    // uniform region) is checked and converted once, not at every voxel (the check is an
    // eigenvalue solve, and the conversions were most of a uniform canvas's build). Compared by
    // bits, so that every voxel stores its own tensor's (-0 is not 0 there) whatever the threads'
    // split; none yet at the start of each task.
    bool have_given = false;
    Mat3 last_given = Mat3::Zero();
    std::array<float, 6> stored{};
    for (std::size_t brick = range.begin(); brick != range.end(); ++brick) {
      if (brick > first_failure.load()) return;
      try {
        for (auto voxel = leaves[brick]->cbeginValueOn(); voxel; ++voxel) {
          const openvdb::Coord c = voxel.getCoord();
          if (!p.in_box(c)) continue;
          const Vec3 world = p.world(c);
          const Mat3 given = metric.at(world);
          if (!have_given || !same_bits(given, last_given)) {
            const Mat3 G = stored_metric(given, p.dimension);
            // The message is built only on failure: formatting it per voxel would dominate.
            if (!is_storable_metric(G, p.dimension))
              require_storable_metric(G, given, p.dimension, name + " at " + point_text(world));
            // Another tensor would turn the canvas into the per-slot form, which is not safe in
            // parallel.
            if (uniform && G != *uniform)
              throw Error("metric " + name + " claims to be uniform but differs at " +
                          point_text(world));
            stored = Canvas::stored_tensor(G, p.dimension);
            last_given = given;
            have_given = true;
          }
          canvas.set_active(brick * canvas.brick_volume() + local_index(c, p), stored);
        }
      } catch (const Error& error) {
        std::lock_guard<std::mutex> lock(failure_mutex);
        if (brick < first_failure.load()) {
          first_failure = brick;
          failure = error.what();
        }
      }
    }
  });
  if (first_failure.load() < leaves.size()) throw Error(failure);
}

std::string describe(const DomainSpec& domain, const MetricField& metric, int resolution,
                     const Canvas& canvas) {
  std::ostringstream out;
  out.precision(6);
  out << domain.description() << " at resolution " << resolution << " (h = " << canvas.voxel_size
      << ", " << canvas.dims[0] << "x" << canvas.dims[1] << "x" << canvas.dims[2] << " voxels, "
      << canvas.active_voxel_count << " active in " << canvas.brick_count() << " bricks), metric "
      << metric.description();
  return out.str();
}

}  // namespace

// build_canvas itself; the public entry point names a failed allocation.
static Canvas build_canvas_itself(const DomainSpec& domain, const MetricField& metric,
                                  const CanvasOptions& options) {
  if (options.resolution < kLeastCanvasResolution || options.resolution > kMostCanvasResolution)
    throw Error("canvas resolution " + std::to_string(options.resolution) + " is not in [" +
                std::to_string(kLeastCanvasResolution) + ", " +
                std::to_string(kMostCanvasResolution) + "]");
  if (metric.dimension() != 2 && metric.dimension() != 3)
    throw Error("metric '" + metric.description() + "' says it is " +
                std::to_string(metric.dimension()) + "D: a metric field is 2D or 3D");
  const ResolvedDomain resolved = resolve(domain);
  if (metric.dimension() == 2 && resolved.dimension == 3)
    throw Error("metric '" + metric.description() + "' is 2D but domain " + domain.description() +
                " is 3D");
  const Placement placement = place_voxels(resolved, options.resolution);
  check_budget(resolved, placement, options.resolution, metric, options.memory_budget);

  openvdb::initialize();
  const BoolTree::Ptr tree = topology(resolved, placement);
  const auto unwinding = freeing_on_unwind(*tree);
  const std::vector<const BoolLeaf*> leaves = leaves_in_box(*tree, placement);
  if (leaves.empty()) fail_empty(domain, options.resolution);

  std::vector<VoxelIndex> brick_origins;
  brick_origins.reserve(leaves.size());
  for (const BoolLeaf* leaf : leaves)
    brick_origins.push_back({leaf->origin().x(), leaf->origin().y(), leaf->origin().z()});
  // A uniform field's tensor is stored once (the canvas's uniform form).
  std::optional<Mat3> uniform;
  if (metric.is_uniform())
    uniform = stored_metric(metric.at(placement.origin), placement.dimension);
  Canvas canvas;
  canvas.allocate(placement.dimension, placement.h, placement.origin, placement.dims, brick_origins,
                  uniform);
  sample_metric(canvas, leaves, placement, metric, uniform);
  canvas.finalize();
  canvas.convex_domain = resolved.shape  ? resolved.shape->is_convex()
                         : resolved.mesh ? is_convex(*resolved.mesh, placement.h)
                                         : true;  // a box or a rectangle
  canvas.description = describe(domain, metric, options.resolution, canvas);
  return canvas;
}

Canvas build_canvas(const DomainSpec& domain, const MetricField& metric,
                    const CanvasOptions& options) {
  return naming_out_of_memory("building the canvas",
                              [&] { return build_canvas_itself(domain, metric, options); });
}

}  // namespace rvor
