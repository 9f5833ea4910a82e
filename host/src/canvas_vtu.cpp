// The labeled canvas as a VTK XML unstructured grid with raw appended binary data: voxel cells
// (VTK_VOXEL in 3D, VTK_PIXEL in 2D) sharing their corner points.
#include <algorithm>
#include <array>
#include <cstdint>
#include <limits>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include "rvor/canvas_output.h"
#include "vtu_appended_writer.h"

namespace rvor {

namespace {

constexpr uint8_t kVtkPixel = 8;
constexpr uint8_t kVtkVoxel = 11;

// Lattice point (i, j, k): corner (0,0,0) of voxel (i, j, k), at its world centre - h/2 (in the
// plane of the canvas in 2D). Corner (a,b,c) of voxel (i,j,k) is lattice point (i+a, j+b, k+c).
Vec3 lattice_point(const Canvas& canvas, int i, int j, int k) {
  const double half = 0.5 * canvas.voxel_size;
  return canvas.world_of(VoxelIndex{i, j, k}) -
         Vec3(half, half, canvas.dimension == 3 ? half : 0.0);
}

// Ids are kept in blocks of 8^3 lattice points (8^2 in 2D), one per cell of the brick grid grown
// by a layer, allocated when a corner first falls in them: a hash map of every corner took about
// half of a 192^3 canvas's write (4.0 of 4.2 s against 2.1 with the blocks; a node, one
// allocation, per corner).
// Coordinates are Real: float, or double where float would merge corners (write_canvas_vtu).
template <typename Real>
class CornerPoints {
 public:
  CornerPoints(const Canvas& canvas, std::vector<Real>& points)
      : canvas_(canvas),
        points_(points),
        edge_z_(canvas.dimension == 3 ? Canvas::kBrickEdge : 1),
        grid_{canvas.brick_grid_dims[0] + 1, canvas.brick_grid_dims[1] + 1,
              canvas.dimension == 3 ? canvas.brick_grid_dims[2] + 1 : 1},
        block_of_(static_cast<std::size_t>(grid_[0]) * grid_[1] * grid_[2], -1) {}

  int64_t id(int i, int j, int k) {
    const int e = Canvas::kBrickEdge, block_size = e * e * edge_z_;
    const std::size_t cell =
        (static_cast<std::size_t>(k / edge_z_) * grid_[1] + j / e) * grid_[0] + i / e;
    int64_t& block = block_of_[cell];
    if (block < 0) {
      block = static_cast<int64_t>(ids_.size());
      ids_.resize(ids_.size() + block_size, -1);
    }
    int64_t& id = ids_[block + ((k % edge_z_) * e + j % e) * e + i % e];
    if (id < 0) {
      id = static_cast<int64_t>(points_.size() / 3);
      const Vec3 p = lattice_point(canvas_, i, j, k);
      for (int a = 0; a < 3; ++a) points_.push_back(static_cast<Real>(p[a]));
    }
    return id;
  }

 private:
  const Canvas& canvas_;
  std::vector<Real>& points_;
  int edge_z_;
  std::array<int, 3> grid_;
  std::vector<int64_t> block_of_;  // per grid cell: where its block starts in ids_, or -1
  std::vector<int64_t> ids_;       // per lattice point of an allocated block: its id, or -1
};

// Calls visit(slot) for every active slot in slot order, the cells' order.
template <typename Visit>
void for_each_active_slot(const Canvas& canvas, Visit&& visit) {
  for (std::size_t slot = 0; slot < canvas.slot_count(); ++slot)
    if (canvas.active[slot]) visit(slot);
}

// Calls corner(i, j, k) for the corners of the voxel in a slot, in VTK order (x fastest, then y,
// then z).
template <typename Corner>
void for_each_corner(const Canvas& canvas, std::size_t slot, Corner&& corner) {
  const VoxelIndex v = canvas.voxel_of(slot);
  const int corner_count = canvas.dimension == 3 ? 8 : 4;
  for (int c = 0; c < corner_count; ++c)
    corner(v.i + (c & 1), v.j + ((c >> 1) & 1), v.k + ((c >> 2) & 1));
}

// Index: int32_t where every connectivity entry fits (a third less to write), else int64_t. Only
// the points are held; the cells and their data are written from the canvas and the field as the
// file is written (at 192^3 the connectivity alone was 450 MB, and all arrays 65 bytes per voxel
// at its peak, more than a propagation on PoCL).
template <typename Index, typename Real>
void write_cells(const std::string& path, const Canvas& canvas, const VoronoiField& field) {
  std::vector<Real> points;
  CornerPoints<Real> corners(canvas, points);
  // Counted here, as the arrays below will be written: not active_voxel_count, which a canvas
  // changed without finalize() would not match (the declared sizes would then lie).
  std::size_t cells = 0;
  for_each_active_slot(canvas, [&](std::size_t slot) {
    for_each_corner(canvas, slot, [&](int i, int j, int k) { corners.id(i, j, k); });
    ++cells;
  });
  const Index corner_count = canvas.dimension == 3 ? 8 : 4;
  const auto connectivity = vtu::streamed<Index>([&](auto push) {
    for_each_active_slot(canvas, [&](std::size_t slot) {
      for_each_corner(canvas, slot,
                      [&](int i, int j, int k) { push(static_cast<Index>(corners.id(i, j, k))); });
    });
  });
  const auto offsets = vtu::streamed<Index>([&](auto push) {
    for (std::size_t cell = 1; cell <= cells; ++cell) push(static_cast<Index>(cell * corner_count));
  });
  const uint8_t type = canvas.dimension == 3 ? kVtkVoxel : kVtkPixel;
  const auto types = vtu::streamed<uint8_t>([&](auto push) {
    for (std::size_t cell = 0; cell < cells; ++cell) push(type);
  });
  // A cell's value of one of the field's arrays.
  const auto cell_values = [&](const auto& values) {
    return vtu::streamed<std::decay_t<decltype(values[0])>>([&canvas, &values](auto push) {
      for_each_active_slot(canvas, [&](std::size_t slot) { push(values[slot]); });
    });
  };
  vtu::AppendedWriter appended;
  std::string xml = vtu::grid_geometry_streamed<Index>(
      appended, points, cells, cells * static_cast<std::size_t>(corner_count), connectivity,
      offsets, types);
  xml += "<CellData Scalars=\"label\">\n";
  xml += appended.declare_streamed("Int32", "label", 1, cells * sizeof(int32_t),
                                   cell_values(field.label));
  xml += appended.declare_streamed("Float32", "distance", 1, cells * sizeof(float),
                                   cell_values(field.distance));
  xml += "</CellData>\n";
  vtu::publish(path, std::move(xml), appended);
}

// Whether float coordinates place points within a thousandth of `spacing` (the voxel size) when
// no coordinate exceeds `largest` in magnitude: float's rounding is at most 2^-24 relative, so up
// to 2^14 spacings from the origin. Farther out (a canvas at 1e5 with voxels of 0.01) neighbouring
// corners would round to one float, and points need doubles.
bool float_points_suffice(double largest, double spacing) {
  return largest <= 16384.0 * spacing;
}

// The largest magnitude of a corner coordinate: at a corner of the index box's lattice.
double largest_corner_coordinate(const Canvas& canvas) {
  const Vec3 low = lattice_point(canvas, 0, 0, 0);
  const Vec3 high = lattice_point(canvas, canvas.dims[0], canvas.dims[1],
                                  canvas.dimension == 3 ? canvas.dims[2] : 0);
  return std::max(low.cwiseAbs().maxCoeff(), high.cwiseAbs().maxCoeff());
}

template <typename Index>
void write_cells_at_precision(const std::string& path, const Canvas& canvas,
                              const VoronoiField& field) {
  if (float_points_suffice(largest_corner_coordinate(canvas), canvas.voxel_size))
    write_cells<Index, float>(path, canvas, field);
  else
    write_cells<Index, double>(path, canvas, field);
}

}  // namespace

void write_canvas_vtu(const std::string& path, const Canvas& canvas, const VoronoiField& field,
                      VtuIndices indices) {
  require_field_for(canvas, field, "cannot write " + path);
  // Corner ids and offsets are at most the connectivity's length: cells times corners.
  const std::uint64_t entries = canvas.active_voxel_count * (canvas.dimension == 3 ? 8u : 4u);
  if (indices == VtuIndices::narrowest &&
      entries <= static_cast<std::uint64_t>(std::numeric_limits<int32_t>::max()))
    write_cells_at_precision<int32_t>(path, canvas, field);
  else
    write_cells_at_precision<int64_t>(path, canvas, field);
}

}  // namespace rvor
