#pragma once
// The canvas: a sparse voxel grid covering the domain, with the metric sampled at every active
// voxel. It is built on OpenVDB (canvas_builder.h) and stored here in the packed form the solvers
// use: active 8^3 leaves (8x8x1 in 2D) as bricks of consecutive "slots", a dense brick table for
// neighbour look-ups at any offset, and the metric: six floats per slot, or six in all where one
// tensor holds everywhere (the uniform form). No OpenVDB type appears here.
#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "rvor/metric.h"

namespace rvor {

struct VoxelIndex {
  int i = 0, j = 0, k = 0;
};

class Canvas {
 public:
  static constexpr int kBrickEdge = 8;

  int dimension = 3;
  double voxel_size = 0.0;     // h, world units
  Vec3 origin = Vec3::Zero();  // world position of the centre of voxel (0,0,0)
  std::array<int, 3> dims{};   // index bounding box [0,dims) in voxels; dims[2] == 1 in 2D
  std::array<int, 3> brick_grid_dims{};   // ceil(dims / brick edge) per axis
  std::vector<int32_t> brick_table;       // brick grid (x fastest) -> brick id, -1 where empty
  std::vector<VoxelIndex> brick_origins;  // voxel index of each brick's (0,0,0) corner
  std::vector<uint8_t> active;            // per slot: 1 inside the domain
  std::size_t active_voxel_count = 0;
  // The builder knew the domain convex (a box or rectangle, a sphere, ellipsoid or disk, a convex
  // mesh): a straight segment between two of its points stays inside it, so under a uniform metric
  // the geodesic distance is the straight one (the exact start, rvor/nearest_seeds.h).
  bool convex_domain = false;
  std::string description;  // domain, metric and resolution, for reports

  int brick_edge_z() const { return dimension == 3 ? kBrickEdge : 1; }
  int brick_volume() const { return kBrickEdge * kBrickEdge * brick_edge_z(); }
  std::size_t brick_count() const { return brick_origins.size(); }
  std::size_t slot_count() const {
    return brick_count() * static_cast<std::size_t>(brick_volume());
  }

  // Id of the brick at brick-grid coordinates (bi, bj, bk): -1 outside the grid or where empty.
  int32_t brick_at(int bi, int bj, int bk) const;
  // Slot of voxel (i,j,k): -1 outside the bounding box, in an empty brick, or inactive.
  int64_t slot_of(int i, int j, int k) const;
  int64_t slot_of(const VoxelIndex& v) const { return slot_of(v.i, v.j, v.k); }
  VoxelIndex voxel_of(std::size_t slot) const;
  Vec3 world_of(const VoxelIndex& v) const;
  Vec3 world_of(std::size_t slot) const { return world_of(voxel_of(slot)); }
  // Continuous index coordinates of a world point (voxel centres are at integers).
  Vec3 index_coordinates(const Vec3& world) const;
  // The voxel whose cell contains the world point (rounded index; may lie outside dims). A point
  // on the index box's faces, to a millionth of a voxel, belongs to the boundary voxel.
  VoxelIndex voxel_containing(const Vec3& world) const;
  // A slot's tensor: six floats in .sol order, or as a matrix. Inactive slots read zeros in the
  // uniform form, and what was last written in the per-slot form (zeros unless written). The slot
  // must be below slot_count(): these run in the engines' inner loops and do not check.
  const float* metric_of(std::size_t slot) const {
    if (!uniform_metric_) return &metric_[6 * slot];
    return active[slot] ? uniform_metric_->data() : kNoTensor.data();
  }
  Mat3 metric_at(std::size_t slot) const;
  // The one tensor of every active voxel when the canvas stores it once (the uniform form, from
  // allocate(): 24 bytes per voxel less, 3.2 GB at 512^3); none when tensors are stored per slot,
  // even if they happen to be equal. In the uniform form a slot made active by writing `active`
  // has that tensor; in the per-slot form it has what was last written there.
  std::optional<Mat3> uniform_metric() const;
  // The six floats of a slot's tensor, to write by hand (then finalize()). A canvas in the uniform
  // form is first turned into the per-slot form (its tensor at every active slot), which must not
  // run beside any other use of the canvas.
  float* mutable_metric(std::size_t slot);
  // Slots whose tensor is stored or implied: slot_count() as allocate() made it.
  std::size_t metric_slot_count() const {
    return uniform_metric_ ? active.size() : metric_.size() / 6;
  }

  // Allocates bricks for the given voxel index bounding box and brick origins, all inactive.
  // Used by builders; brick origins must be multiples of the brick edge inside the box. With
  // `uniform_metric` the canvas takes the uniform form: that tensor (as stored_metric makes it)
  // at every voxel that becomes active.
  void allocate(int dimension, double voxel_size, const Vec3& origin,
                const std::array<int, 3>& dims, const std::vector<VoxelIndex>& brick_origins,
                const std::optional<Mat3>& uniform_metric = std::nullopt);
  // Marks a voxel active with the given metric, stored as stored_metric
  // (rvor/metric.h) makes it: in 2D only the xy block is kept, with 1 along z. (A 2D tensor stored
  // with another zz entry made the engines weigh the source factorization differently: the
  // reference judged the fit with it and the kernels without, and their fields differed by 10%.)
  // Calls for distinct slots may run in parallel, except where a canvas in the uniform form gets
  // another tensor: it turns into the per-slot form first (as mutable_metric() does).
  // Throws rvor::Error for a slot past slot_count(), and for a tensor the builder would refuse
  // (metric_problem, require_storable_metric).
  void set_active(std::size_t slot, const Mat3& G);
  // set_active with the tensor already as the six floats it is stored as (stored_tensor(G)), for
  // callers that mark many voxels with one tensor and would convert it at each. Other floats skip
  // the 2D rule above until finalize(), which refuses them.
  void set_active(std::size_t slot, const std::array<float, 6>& stored);
  // The six floats set_active stores for G (metric_of's layout).
  static std::array<float, 6> stored_tensor(const Mat3& G, int dimension);
  // Recounts active voxels and records the content hash (after set_active calls, or after writing
  // `active` or mutable_metric() directly). Throws rvor::Error for a geometry the solvers cannot
  // index by (dimension, voxel size, index box, brick grid and table, brick origins not as
  // allocate() made them) and, on a 2D canvas, an active tensor whose z row is not (0, 0, 1).
  // Tensors are not checked here (the builder checks them): one that is not SPD is an error of the
  // solve that meets it, naming its voxel.
  void finalize();
  // finalize()'s checks of the geometry and of the arrays' sizes, without recounting or hashing:
  // the propagators' first step, so that a canvas whose bricks or arrays were edited without
  // finalize() is an error naming what does not fit, not an out-of-bounds read.
  void require_consistent() const;
  // A hash of what the propagators read: the geometry (h, origin, dims, bricks) and every slot's
  // activity and tensor; a canvas changed in one of them always hashes differently, one changed in
  // many by chance only. Both forms of the same tensors hash the same. Recorded by finalize(); none
  // after allocate() or set_active() until finalize() runs again. A propagator keeps what it
  // derived from a canvas only while this hash stays the same (rvor/propagation.h), so a change
  // made without finalize() may go unseen.
  std::optional<std::uint64_t> content_hash() const { return content_hash_; }

 private:
  static constexpr std::array<float, 6> kNoTensor{};
  void store_metric_per_slot();
  // Throws rvor::Error naming `caller` unless slot < slot_count().
  void require_slot(std::size_t slot, const char* caller) const;

  std::vector<float> metric_;  // the per-slot form: 6 floats per slot
  std::optional<std::array<float, 6>> uniform_metric_;
  std::optional<std::uint64_t> content_hash_;
};

}  // namespace rvor
