#include "rvor/canvas.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <string>

#include "../host/src/canvas_identity.h"
#include "../host/src/slot_hash.h"
#include "../host/src/slot_ranges.h"
#include "rvor/error.h"

namespace rvor {

namespace {
// Bricks along an axis of `voxels` (at least 1, allocate() checks) with `edge` voxels each.
int bricks_along(int voxels, int edge) {
  return (voxels + edge - 1) / edge;
}

std::uint64_t bits_of(double value) {
  std::uint64_t bits;
  std::memcpy(&bits, &value, sizeof bits);
  return bits;
}

// Each slot as four words (its activity and its six floats in pairs) at indices 4 slot + n, its
// floats at metric + stride * slot: stride 6 for tensors per slot, 0 for the uniform form's one.
// An inactive slot's floats count as zeros: the solvers do not read them, and the uniform form has
// none, so both forms of the same tensors hash the same.
template <std::size_t stride>
RVOR_CLONED_FOR_AVX2 std::uint64_t hash_slots(const std::uint8_t* active, const float* metric,
                                              std::size_t begin, std::size_t end) {
  std::uint64_t sum = 0;
  for (std::size_t slot = begin; slot < end; ++slot) {
    std::uint64_t pairs[3];
    std::memcpy(pairs, metric + stride * slot, sizeof pairs);
    const std::uint64_t on = active[slot] ? ~std::uint64_t{0} : 0;
    sum += indexed_word_hash(4 * slot, active[slot]);
    for (int n = 0; n < 3; ++n) sum += indexed_word_hash(4 * slot + 1 + n, pairs[n] & on);
  }
  return sum;
}

// The geometry's scalars, at indices from `first` on, above every slot's.
std::uint64_t hash_scalars(const Canvas& canvas, std::uint64_t first) {
  std::uint64_t index = first, sum = 0;
  auto add = [&](std::uint64_t word) { sum += indexed_word_hash(index++, word); };
  add(static_cast<std::uint64_t>(canvas.dimension));
  add(bits_of(canvas.voxel_size));
  for (int a = 0; a < 3; ++a) add(bits_of(canvas.origin[a]));
  for (int a = 0; a < 3; ++a) add(static_cast<std::uint64_t>(canvas.dims[a]));
  return sum;
}

// The scalars and the bricks' origins.
std::uint64_t hash_geometry(const Canvas& canvas) {
  std::uint64_t index = std::uint64_t{1} << 62;
  std::uint64_t sum = hash_scalars(canvas, index - 16);
  for (const VoxelIndex& o : canvas.brick_origins) {
    sum += indexed_word_hash(index++,
                             static_cast<std::uint32_t>(o.i) |
                                 static_cast<std::uint64_t>(static_cast<std::uint32_t>(o.j)) << 32);
    sum += indexed_word_hash(index++, static_cast<std::uint32_t>(o.k));
  }
  return sum;
}
[[noreturn]] void fail_geometry(const std::string& problem) {
  throw Error("canvas: " + problem + " (a canvas changed by hand? build_canvas or allocate() " +
              "keep its bricks consistent)");
}

// What the solvers index by without checking: the dimension, the voxel size and origin, the index
// box and brick grid, and a brick table that holds every brick once, at its origin's cell.
void require_consistent_geometry(const Canvas& c) {
  if (c.dimension != 2 && c.dimension != 3) fail_geometry("dimension must be 2 or 3");
  if (!(std::isfinite(c.voxel_size) && c.voxel_size > 0) || !c.origin.allFinite())
    fail_geometry("voxel size must be positive and origin finite");
  for (int a = 0; a < 3; ++a) {
    const int edge = a == 2 ? c.brick_edge_z() : Canvas::kBrickEdge;
    if (c.dims[a] < 1 || c.brick_grid_dims[a] != bricks_along(c.dims[a], edge))
      fail_geometry("index box and brick grid do not match along axis " + std::to_string(a));
  }
  if (c.dimension == 2 && c.dims[2] != 1) fail_geometry("a 2D index box has one layer");
  const auto& g = c.brick_grid_dims;
  if (c.brick_table.size() != static_cast<std::size_t>(g[0]) * g[1] * g[2])
    fail_geometry("brick table of " + std::to_string(c.brick_table.size()) +
                  " cells for a brick grid of " + std::to_string(g[0]) + "x" +
                  std::to_string(g[1]) + "x" + std::to_string(g[2]));
  // Cells in table order, their coordinates counted rather than divided out: the engines run this
  // at every solve and insertion (Canvas::require_consistent), 107 us at 256^3 with divisions.
  std::size_t listed = 0, cell = 0;
  for (int bk = 0; bk < g[2]; ++bk)
    for (int bj = 0; bj < g[1]; ++bj)
      for (int bi = 0; bi < g[0]; ++bi, ++cell) {
        const int32_t brick = c.brick_table[cell];
        if (brick == -1) continue;
        if (brick < 0 || static_cast<std::size_t>(brick) >= c.brick_count())
          fail_geometry("brick table cell " + std::to_string(cell) + " holds brick " +
                        std::to_string(brick) + " of " + std::to_string(c.brick_count()));
        const VoxelIndex& o = c.brick_origins[brick];
        if (o.i != bi * Canvas::kBrickEdge || o.j != bj * Canvas::kBrickEdge ||
            o.k != bk * c.brick_edge_z())
          fail_geometry("brick " + std::to_string(brick) + " is listed at brick cell (" +
                        std::to_string(bi) + ", " + std::to_string(bj) + ", " + std::to_string(bk) +
                        ") but its origin is voxel (" + std::to_string(o.i) + ", " +
                        std::to_string(o.j) + ", " + std::to_string(o.k) + ")");
        ++listed;
      }
  // Each listed brick matches its cell's origin, so no brick is listed twice; every one must be.
  if (listed != c.brick_count())
    fail_geometry(std::to_string(c.brick_count() - listed) + " of " +
                  std::to_string(c.brick_count()) + " bricks are missing from the brick table");
}

// A 2D canvas's tensors are their xy block, with the identity along z (set_active's form): the
// engines read the z row differently, so another one would make them disagree.
void require_planar_tensors(const Canvas& c) {
  const auto off_plane = [&](std::size_t slot) {
    const float* m = c.metric_of(slot);
    return c.active[slot] && (m[3] != 0.0f || m[4] != 0.0f || m[5] != 1.0f);
  };
  // Counted over slot ranges in parallel, as the content hash reads them; the first one only
  // for the message.
  if (sum_over_slot_ranges(c.slot_count(), [&](std::size_t begin, std::size_t end) {
        std::uint64_t count = 0;
        for (std::size_t slot = begin; slot < end; ++slot) count += off_plane(slot);
        return count;
      }) == 0)
    return;
  for (std::size_t slot = 0; slot < c.slot_count(); ++slot) {
    if (off_plane(slot)) {
      const float* m = c.metric_of(slot);
      const VoxelIndex v = c.voxel_of(slot);
      throw Error("canvas voxel (" + std::to_string(v.i) + ", " + std::to_string(v.j) +
                  ") of a 2D canvas: m13, m23, m33 must be 0, 0, 1 (set_active stores the xy " +
                  "block so), got " + std::to_string(m[3]) + ", " + std::to_string(m[4]) + ", " +
                  std::to_string(m[5]));
    }
  }
}

}  // namespace

int32_t Canvas::brick_at(int bi, int bj, int bk) const {
  const auto& g = brick_grid_dims;
  if (bi < 0 || bj < 0 || bk < 0 || bi >= g[0] || bj >= g[1] || bk >= g[2]) return -1;
  return brick_table[bi +
                     static_cast<std::size_t>(g[0]) * (bj + static_cast<std::size_t>(g[1]) * bk)];
}

int64_t Canvas::slot_of(int i, int j, int k) const {
  if (i < 0 || j < 0 || k < 0 || i >= dims[0] || j >= dims[1] || k >= dims[2]) return -1;
  const int bz = brick_edge_z();
  const int bi = i / kBrickEdge, bj = j / kBrickEdge, bk = k / bz;
  const int32_t brick = brick_at(bi, bj, bk);
  if (brick < 0) return -1;
  const int local =
      (i - bi * kBrickEdge) + kBrickEdge * ((j - bj * kBrickEdge) + kBrickEdge * (k - bk * bz));
  const int64_t slot = static_cast<int64_t>(brick) * brick_volume() + local;
  return active[slot] ? slot : -1;
}

VoxelIndex Canvas::voxel_of(std::size_t slot) const {
  const std::size_t brick = slot / brick_volume();
  const int local = static_cast<int>(slot % brick_volume());
  const VoxelIndex& o = brick_origins[brick];
  return {o.i + local % kBrickEdge, o.j + (local / kBrickEdge) % kBrickEdge,
          o.k + local / (kBrickEdge * kBrickEdge)};
}

Vec3 Canvas::world_of(const VoxelIndex& v) const {
  return origin + voxel_size * Vec3(v.i, v.j, v.k);
}

Vec3 Canvas::index_coordinates(const Vec3& world) const {
  return (world - origin) / voxel_size;
}

VoxelIndex Canvas::voxel_containing(const Vec3& world) const {
  const Vec3 c = index_coordinates(world);
  // Cells are half-open, so a point on the index box's upper face (a box domain's upper side)
  // would round one past the last voxel, and rounding can put one on the lower face just below
  // the first: within a millionth of a voxel of the box, such a point belongs to the boundary
  // voxel.
  constexpr double kOnTheFace = 1e-6;
  auto to_int = [](double x, int count) {
    if (x >= count - 0.5 && x <= count - 0.5 + kOnTheFace) return count - 1;
    if (x < -0.5 && x >= -0.5 - kOnTheFace) return 0;
    const double r = std::floor(x + 0.5);
    return r > 2e9 ? 2000000000 : (r < -2e9 ? -2000000000 : static_cast<int>(r));
  };
  return {to_int(c.x(), dims[0]), to_int(c.y(), dims[1]),
          dimension == 3 ? to_int(c.z(), dims[2]) : 0};
}

void Canvas::require_slot(std::size_t slot, const char* caller) const {
  if (slot >= active.size())
    throw Error(std::string(caller) + ": slot " + std::to_string(slot) + " is past the canvas's " +
                std::to_string(active.size()) + " slots");
}

Mat3 Canvas::metric_at(std::size_t slot) const {
  const float* m = metric_of(slot);
  return tensor_from_sol({m[0], m[1], m[2], m[3], m[4], m[5]});
}

std::optional<Mat3> Canvas::uniform_metric() const {
  if (!uniform_metric_) return std::nullopt;
  const std::array<float, 6>& m = *uniform_metric_;
  return tensor_from_sol({m[0], m[1], m[2], m[3], m[4], m[5]});
}

float* Canvas::mutable_metric(std::size_t slot) {
  require_slot(slot, "mutable_metric");
  content_hash_.reset();
  store_metric_per_slot();
  return &metric_[6 * slot];
}

void Canvas::store_metric_per_slot() {
  if (!uniform_metric_) return;
  metric_.assign(6 * active.size(), 0.0f);
  for (std::size_t slot = 0; slot < active.size(); ++slot)
    if (active[slot])
      std::copy(uniform_metric_->begin(), uniform_metric_->end(), &metric_[6 * slot]);
  uniform_metric_.reset();
}

namespace {

// The brick table holds an int32 per brick of the index box; past 2^31 cells its size wrapped (a
// box of 2^30 voxels a side: a table of 0 cells, then a write past it).
void require_brick_table_fits(const std::array<int, 3>& brick_grid_dims,
                              const std::array<int, 3>& dims) {
  const double cells = static_cast<double>(brick_grid_dims[0]) * brick_grid_dims[1] *
                       static_cast<double>(brick_grid_dims[2]);
  if (cells > static_cast<double>(std::numeric_limits<std::int32_t>::max()))
    throw Error("canvas index box of " + std::to_string(dims[0]) + " x " + std::to_string(dims[1]) +
                " x " + std::to_string(dims[2]) + " voxels is too large: its brick table would " +
                "hold " + std::to_string(cells) + " cells, past 2^31");
}

}  // namespace

void Canvas::allocate(int dim, double h, const Vec3& world_origin,
                      const std::array<int, 3>& index_dims, const std::vector<VoxelIndex>& origins,
                      const std::optional<Mat3>& uniform_metric) {
  if (dim != 2 && dim != 3) throw Error("canvas dimension must be 2 or 3");
  if (std::any_of(index_dims.begin(), index_dims.begin() + dim, [](int n) { return n < 1; }))
    throw Error("canvas index box must have at least one voxel along each axis");
  dimension = dim;
  voxel_size = h;
  origin = world_origin;
  dims = index_dims;
  if (dimension == 2) dims[2] = 1;
  for (int a = 0; a < 3; ++a) {
    const int edge = a == 2 ? brick_edge_z() : kBrickEdge;
    brick_grid_dims[a] = bricks_along(dims[a], edge);
  }
  require_brick_table_fits(brick_grid_dims, dims);
  brick_table.assign(
      static_cast<std::size_t>(brick_grid_dims[0]) * brick_grid_dims[1] * brick_grid_dims[2], -1);
  brick_origins = origins;
  for (std::size_t b = 0; b < origins.size(); ++b) {
    const VoxelIndex& o = origins[b];
    const int bi = o.i / kBrickEdge, bj = o.j / kBrickEdge, bk = o.k / brick_edge_z();
    const bool aligned =
        o.i % kBrickEdge == 0 && o.j % kBrickEdge == 0 && o.k % brick_edge_z() == 0;
    if (!aligned || bi < 0 || bj < 0 || bk < 0 || bi >= brick_grid_dims[0] ||
        bj >= brick_grid_dims[1] || bk >= brick_grid_dims[2])
      throw Error("canvas brick origin is not aligned or outside the index box");
    brick_table[bi + static_cast<std::size_t>(brick_grid_dims[0]) *
                         (bj + static_cast<std::size_t>(brick_grid_dims[1]) * bk)] =
        static_cast<int32_t>(b);
  }
  active.assign(slot_count(), 0);
  if (uniform_metric) {
    uniform_metric_ = stored_tensor(*uniform_metric, dimension);
    std::vector<float>().swap(metric_);
  } else {
    uniform_metric_.reset();
    metric_.assign(6 * slot_count(), 0.0f);
  }
  active_voxel_count = 0;
  content_hash_.reset();
}

void Canvas::set_active(std::size_t slot, const Mat3& G) {
  // As the builder checks its fields (a tensor of eigenvalue 1e-35 was solved), and G itself (a
  // non-symmetric one kept its upper triangle); the messages are built only on failure.
  const Mat3 stored = stored_metric(G, dimension);
  if (!is_storable_metric(stored, dimension) || !metric_problem(G, dimension).empty()) {
    const std::string where = "set_active: slot " + std::to_string(slot);
    if (const std::string problem = metric_problem(G, dimension); !problem.empty())
      throw Error(where + ": metric " + problem);
    require_storable_metric(stored, G, dimension, where);
  }
  set_active(slot, stored_tensor(stored, dimension));
}

std::array<float, 6> Canvas::stored_tensor(const Mat3& G, int dimension) {
  if (dimension != 2 && dimension != 3)
    throw Error("stored_tensor: dimension " + std::to_string(dimension) + " is not 2 or 3");
  const SolTensor c = tensor_to_sol(stored_metric(G, dimension));
  std::array<float, 6> out;
  for (int n = 0; n < 6; ++n) out[n] = static_cast<float>(c[n]);
  return out;
}

void Canvas::set_active(std::size_t slot, const std::array<float, 6>& stored) {
  require_slot(slot, "set_active");
  // Only when set: the builder calls this from many threads after allocate() reset it.
  if (content_hash_) content_hash_.reset();
  if (uniform_metric_ && stored != *uniform_metric_) store_metric_per_slot();
  active[slot] = 1;
  if (!uniform_metric_) std::copy(stored.begin(), stored.end(), &metric_[6 * slot]);
}

void Canvas::require_consistent() const {
  require_consistent_geometry(*this);
  if (active.size() != slot_count() || metric_slot_count() != slot_count())
    throw Error("canvas: " + std::to_string(active.size()) + " activity flags and tensors for " +
                std::to_string(metric_slot_count()) + " slots in a canvas of " +
                std::to_string(slot_count()) + " slots");
}

void Canvas::finalize() {
  content_hash_.reset();
  require_consistent();
  active_voxel_count = 0;
  for (uint8_t a : active) active_voxel_count += a;
  // 1 marks a voxel active; a 2 was counted twice and taken as active by the engines.
  if (const auto odd = std::find_if(active.begin(), active.end(), [](uint8_t a) { return a > 1; });
      odd != active.end())
    throw Error("canvas: slot " + std::to_string(odd - active.begin()) + " has activity flag " +
                std::to_string(*odd) + ", not 0 or 1");
  if (dimension == 2) require_planar_tensors(*this);
  content_hash_ = hash_geometry(*this) +
                  sum_over_slot_ranges(slot_count(), [&](std::size_t begin, std::size_t end) {
                    return uniform_metric_
                               ? hash_slots<0>(active.data(), uniform_metric_->data(), begin, end)
                               : hash_slots<6>(active.data(), metric_.data(), begin, end);
                  });
}

std::optional<std::uint64_t> canvas_identity(const Canvas& canvas) {
  if (!canvas.content_hash()) return std::nullopt;
  // Indices above the content hash's: the scalars as they are now (not the bricks: 65 536 words
  // at 256^3, a tenth of a millisecond each call, and only allocate() sets them).
  std::uint64_t index = std::uint64_t{3} << 62;
  std::uint64_t sum = *canvas.content_hash() + hash_scalars(canvas, index);
  index += 16;
  auto add = [&](std::uint64_t word) { sum += indexed_word_hash(index++, word); };
  add(canvas.convex_domain ? 1 : 0);
  add(canvas.slot_count());
  add(canvas.active_voxel_count);
  // Whole tensors of sampled slots: a stride over the floats that is a multiple of 6 (96 at 256^2)
  // read one component only, so canvases differing in m22 or m33 alone looked the same.
  const std::size_t step = std::max<std::size_t>(1, canvas.slot_count() / 4096);
  for (std::size_t slot = 0; slot < canvas.slot_count(); slot += step) {
    if (slot >= canvas.active.size() || slot >= canvas.metric_slot_count()) break;
    add(canvas.active[slot]);
    const float* m = canvas.metric_of(slot);
    for (int n = 0; n < 6; ++n) add(bits_of(m[n]));
  }
  return sum;
}

}  // namespace rvor
