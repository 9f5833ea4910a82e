#pragma once
// A metric field: an SPD tensor at every point of space. Implementations are immutable after
// construction, so at() may be called from many threads at once.
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "rvor/metric.h"

namespace rvor {

struct Box {
  Vec3 lo = Vec3::Zero();
  Vec3 hi = Vec3::Zero();
};

class MetricField {
 public:
  virtual ~MetricField() = default;
  // 2 or 3. Fields that make sense in both (euclidean, uniform 3D) report the dimension they
  // were created for.
  virtual int dimension() const = 0;
  // The tensor at world position p (z ignored in 2D). May return a non-SPD matrix for a
  // malformed input field: callers validate with require_spd().
  virtual Mat3 at(const Vec3& p) const = 0;
  // Human-readable description, e.g. "swirl (scale 1)" or "sol:metric.sol on mesh.mesh".
  virtual std::string description() const = 0;
  // The domain the field was designed for (radial_shock_3d: [1,11]^3), if any.
  virtual std::optional<Box> natural_domain() const { return std::nullopt; }
  // The same tensor at every point (euclidean, uniform): a canvas stores it once.
  virtual bool is_uniform() const { return false; }
  // Bytes the field keeps in memory while a canvas is built from it, which the canvas has to
  // share the memory budget with: a VDB file's grids. Analytic fields hold nothing; mesh fields
  // are not counted (their .mesh and .sol, usually far smaller than a canvas).
  virtual std::uint64_t resident_bytes() const { return 0; }
};

// Builds an analytic field from a spec "NAME[:key=value,...]" for a domain of the given
// dimension (2 or 3). Names: euclidean, uniform, swirl, starred, hyperbolic_shock,
// unidimensional_shock, radial_shock_3d. Every analytic field takes key `scale` (> 0,
// default 1): G is multiplied by scale^2, so distances grow by `scale`.
// `uniform:m11,m12,m22` (2D) or `uniform:m11,m12,m22,m13,m23,m33` (3D) gives a constant tensor.
// Throws rvor::Error naming the spec on unknown names, bad keys or values, a dimension the field
// does not support, or a non-SPD uniform tensor.
std::unique_ptr<MetricField> make_analytic_metric(const std::string& spec, int dimension);
// The names make_analytic_metric() knows, in a stable order (for --help texts).
std::vector<std::string> analytic_metric_names();

// Metric given at the vertices of a Medit .mesh (triangles in 2D, tetrahedra in 3D) by a .sol
// (SolAtVertices, type 3 = symmetric tensor), interpolated with Log-Euclidean barycentric
// weights after point location. Points outside the mesh take the metric of the nearest element.
std::unique_ptr<MetricField> load_mesh_metric(const std::string& mesh_path,
                                              const std::string& sol_path);

// Metric stored in an OpenVDB file as six float grids named m11 m12 m22 m13 m23 m33
// (world-space transform), sampled trilinearly. Implemented in the canvas library. The file is
// read whole (every grid in it); refused before any value is read when it is larger than
// `memory_budget` bytes or its grids' voxel counts as OpenVDB's writers record them (tiles
// counted voxel by voxel) would not fit, and after reading when the counts themselves do not (0:
// default_memory_budget(), as CanvasOptions::memory_budget). A damaged file is an rvor::Error.
std::unique_ptr<MetricField> load_vdb_metric(const std::string& vdb_path,
                                             std::uint64_t memory_budget = 0);

}  // namespace rvor
