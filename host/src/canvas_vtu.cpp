// The labeled canvas as a VTK XML unstructured grid with raw appended binary data: voxel cells
// (VTK_VOXEL in 3D, VTK_PIXEL in 2D) sharing their corner points.
#include <cstdint>
#include <string>
#include <unordered_map>
#include <utility>
#include <vector>

#include "rvor/canvas_output.h"
#include "vtu_appended_writer.h"

namespace rvor {

namespace {

constexpr uint8_t kVtkPixel = 8;
constexpr uint8_t kVtkVoxel = 11;

struct VtuArrays {
  std::vector<float> points;
  std::vector<int64_t> connectivity, offsets;
  std::vector<uint8_t> types;
  std::vector<int32_t> labels;
  std::vector<float> distances;
};

// Corner (a,b,c) of voxel (i,j,k) is the lattice point (i+a, j+b, k+c), at world centre - h/2.
class CornerPoints {
 public:
  CornerPoints(const Canvas& canvas, std::vector<float>& points)
      : canvas_(canvas), points_(points) {}
  int64_t id(int i, int j, int k) {
    const uint64_t key =
        static_cast<uint64_t>(i + 1) +
        static_cast<uint64_t>(canvas_.dims[0] + 3) *
            (static_cast<uint64_t>(j + 1) + static_cast<uint64_t>(canvas_.dims[1] + 3) * k);
    auto [found, inserted] = ids_.emplace(key, static_cast<int64_t>(points_.size() / 3));
    if (inserted) {
      const double half = 0.5 * canvas_.voxel_size;
      const Vec3 p = canvas_.world_of(VoxelIndex{i, j, k}) -
                     Vec3(half, half, canvas_.dimension == 3 ? half : 0.0);
      for (int a = 0; a < 3; ++a) points_.push_back(static_cast<float>(p[a]));
    }
    return found->second;
  }

 private:
  const Canvas& canvas_;
  std::vector<float>& points_;
  std::unordered_map<uint64_t, int64_t> ids_;
};

VtuArrays collect_cells(const Canvas& canvas, const VoronoiField& field) {
  VtuArrays arrays;
  CornerPoints corners(canvas, arrays.points);
  const bool volume = canvas.dimension == 3;
  const int corner_count = volume ? 8 : 4;
  for (std::size_t slot = 0; slot < canvas.slot_count(); ++slot) {
    if (!canvas.active[slot]) continue;
    const VoxelIndex v = canvas.voxel_of(slot);
    for (int c = 0; c < corner_count; ++c)  // VTK order: x fastest, then y, then z
      arrays.connectivity.push_back(
          corners.id(v.i + (c & 1), v.j + ((c >> 1) & 1), v.k + ((c >> 2) & 1)));
    arrays.offsets.push_back(static_cast<int64_t>(arrays.connectivity.size()));
    arrays.types.push_back(volume ? kVtkVoxel : kVtkPixel);
    arrays.labels.push_back(field.label[slot]);
    arrays.distances.push_back(field.distance[slot]);
  }
  return arrays;
}

}  // namespace

void write_canvas_vtu(const std::string& path, const Canvas& canvas, const VoronoiField& field) {
  require_field_for(canvas, field, "cannot write " + path);
  const VtuArrays arrays = collect_cells(canvas, field);
  vtu::AppendedWriter appended;
  std::string xml = vtu::grid_geometry(appended, arrays.points, arrays.connectivity, arrays.offsets,
                                       arrays.types);
  xml += "<CellData Scalars=\"label\">\n";
  xml += appended.declare("Int32", "label", 1, arrays.labels);
  xml += appended.declare("Float32", "distance", 1, arrays.distances);
  xml += "</CellData>\n";
  vtu::publish(path, std::move(xml), appended);
}

}  // namespace rvor
