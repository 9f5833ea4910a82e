// The host determination of the multi-label bricks: straightforward on purpose (Canvas::slot_of
// per corner), the truth the OpenCL kernel (kernels/nerve.cl) is tested against.
#include "rvor/error.h"
#include "rvor/propagation.h"

namespace rvor {

namespace {

// Label of voxel (i, j, k), -1 where inactive, unreached or outside the canvas.
int32_t label_at(const Canvas& canvas, const VoronoiField& field, int i, int j, int k) {
  const int64_t slot = canvas.slot_of(i, j, k);
  return slot < 0 ? -1 : field.label[static_cast<std::size_t>(slot)];
}

bool multi_label_cell(const Canvas& canvas, const VoronoiField& field, const VoxelIndex& base) {
  const int corners_z = canvas.dimension == 3 ? 2 : 1;
  int32_t first = -1;
  for (int dz = 0; dz < corners_z; ++dz)
    for (int dy = 0; dy < 2; ++dy)
      for (int dx = 0; dx < 2; ++dx) {
        const int32_t label = label_at(canvas, field, base.i + dx, base.j + dy, base.k + dz);
        if (label < 0) continue;
        if (first < 0)
          first = label;
        else if (label != first)
          return true;
      }
  return false;
}

bool has_multi_label_cell(const Canvas& canvas, const VoronoiField& field, std::size_t brick) {
  const VoxelIndex o = canvas.brick_origins[brick];
  for (int c = 0; c < canvas.brick_edge_z(); ++c)
    for (int b = 0; b < Canvas::kBrickEdge; ++b)
      for (int a = 0; a < Canvas::kBrickEdge; ++a)
        if (multi_label_cell(canvas, field, VoxelIndex{o.i + a, o.j + b, o.k + c})) return true;
  return false;
}

}  // namespace

std::vector<std::uint8_t> find_multi_label_bricks(const Canvas& canvas, const VoronoiField& field) {
  require_field_for(canvas, field, "multi-label bricks");
  std::vector<std::uint8_t> flags(canvas.brick_count());
  for (std::size_t brick = 0; brick < flags.size(); ++brick)
    flags[brick] = has_multi_label_cell(canvas, field, brick) ? 1 : 0;
  return flags;
}

std::vector<std::uint8_t> Propagator::multi_label_bricks(const Canvas& canvas,
                                                         const VoronoiField& field) {
  return find_multi_label_bricks(canvas, field);
}

}  // namespace rvor
