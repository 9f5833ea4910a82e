#include <algorithm>
#include <array>
#include <cstdint>
#include <filesystem>
#include <sstream>
#include <string>
#include <system_error>
#include <utility>
#include <vector>

#include <openvdb/tools/Interpolation.h>
#include <openvdb/tools/Morphology.h>

#include "memory_estimate.h"
#include "rvor/canvas_builder.h"
#include "rvor/error.h"
#include "rvor/metric_field.h"
#include "rvor/spec_text.h"
#include "vdb_support.h"

namespace rvor {

namespace {

using openvdb::FloatGrid;
using UnsafeAccessor = openvdb::tree::ValueAccessor<const openvdb::FloatTree, false>;

// Trilinear interpolation near the edge of the stored region would mix in the background (0,
// not a metric). One shell of voxels around the active region, each the mean of its active
// neighbours, makes sampling up to a voxel outside the stored centres meaningful.
void extend_by_one_voxel(FloatGrid& grid) {  // tiles voxelized before (VdbMetricField)
  openvdb::MaskTree shell(grid.tree(), false, openvdb::TopologyCopy());
  openvdb::tools::dilateActiveValues(shell, 1, openvdb::tools::NN_FACE_EDGE_VERTEX,
                                     openvdb::tools::IGNORE_TILES);
  shell.topologyDifference(grid.tree());
  // Shell values are computed first and written after, so that they average stored values only.
  const auto stored = grid.getConstAccessor();
  std::vector<std::pair<openvdb::Coord, float>> extension;
  for (auto voxel = shell.cbeginValueOn(); voxel; ++voxel) {
    const openvdb::Coord c = voxel.getCoord();
    double sum = 0;
    int count = 0;
    for (int dz = -1; dz <= 1; ++dz)
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) {
          float value = 0;
          if (stored.probeValue(c.offsetBy(dx, dy, dz), value)) {
            sum += value;
            ++count;
          }
        }
    if (count > 0) extension.emplace_back(c, static_cast<float>(sum / count));
  }
  auto output = grid.getAccessor();
  for (const auto& [c, value] : extension) output.setValue(c, value);
}

// Every stored tensor, not only those the canvas happens to sample: a bad voxel between the
// samples would still bend the interpolated field. Identical neighbours are checked once.
void validate_stored_tensors(const std::string& path, const std::array<FloatGrid::Ptr, 6>& grids,
                             int dimension) {
  std::array<FloatGrid::ConstAccessor, 6> accessors{
      grids[0]->getConstAccessor(), grids[1]->getConstAccessor(), grids[2]->getConstAccessor(),
      grids[3]->getConstAccessor(), grids[4]->getConstAccessor(), grids[5]->getConstAccessor()};
  SolTensor checked{};
  bool any_checked = false;
  for (auto voxel = grids[0]->cbeginValueOn(); voxel; ++voxel) {
    if (!voxel.isVoxelValue()) continue;  // none: the tiles were voxelized before
    const openvdb::Coord c = voxel.getCoord();
    SolTensor t{};
    for (int n = 0; n < 6; ++n) {
      float value = 0;
      accessors[n].probeValue(c, value);  // present: require_same_voxels
      t[n] = value;
    }
    if (dimension == 2) t[3] = t[4] = 0, t[5] = 1;
    if (any_checked && t == checked) continue;
    require_spd(tensor_from_sol(t), "in VDB file " + path + " at voxel " + voxel_text(c));
    checked = t;
    any_checked = true;
  }
}

// Tiles stand for many voxels: voxelized, six grids of a small file could fill the memory.
// Sampling needs the voxels (the shell of extend_by_one_voxel, per-voxel validation), so a field
// whose voxels would not fit in the memory budget (--memory-budget) is refused up front.
// `counted`: how the count was taken ("hold", or "record" for the writer's metadata).
void require_voxel_count_fits(const std::string& path, double voxels, const std::string& counted,
                              std::uint64_t memory_budget) {
  constexpr double kBytesPerVoxel = 4.5;  // a float and the leaf's share of mask and header
  const double bytes = kBytesPerVoxel * voxels;
  const double budget = static_cast<double>(resolved_memory_budget(memory_budget));
  if (bytes > budget) {
    std::ostringstream count;
    count << voxels;
    throw Error("VDB metric file " + path + ": its six grids " + counted + " " + count.str() +
                " active voxels in all (many as tiles), which need ~" + format_bytes(bytes) +
                " once voxelized, over the memory budget of " + format_bytes(budget) +
                " (--memory-budget): store the metric over the domain only, or coarser");
  }
}

void require_voxels_fit(const std::string& path, const std::array<FloatGrid::Ptr, 6>& grids,
                        std::uint64_t memory_budget) {
  double voxels = 0;
  for (const auto& grid : grids) voxels += static_cast<double>(grid->activeVoxelCount());
  require_voxel_count_fits(path, voxels, "hold", memory_budget);
}

// The same from the counts OpenVDB's writers record in each grid's metadata (file_voxel_count),
// before any value is read: decompressed, a small file can take far more than its size (six
// constant 300^3 grids: 73 MB on disk, a 749 MB peak before the refusal after reading, 40 MB now;
// docs/measurements/vdb_guard.sh). A file without them is counted once read.
void require_recorded_voxels_fit(const std::string& path, const VdbArchiveSummary& summary,
                                 std::uint64_t memory_budget) {
  double voxels = 0;
  for (const char* name : kMetricGridNames) {
    const auto recorded = summary.recorded_voxels.find(name);
    if (recorded != summary.recorded_voxels.end())
      voxels += static_cast<double>(std::max<std::int64_t>(recorded->second, 0));
  }
  require_voxel_count_fits(path, voxels, "record (as written)", memory_budget);
}

// read_grids reads every value of every grid in the file (io::Stream, to fail cleanly on a
// truncated file) before require_voxels_fit can count them; their values take at least the
// file's compressed bytes once read, so a file larger than the budget is refused first. (A small
// file can still hold far more once decompressed: require_recorded_voxels_fit catches that
// before reading where the writer recorded the counts, require_voxels_fit after it elsewhere.)
void require_file_fits(const std::string& path, std::uint64_t memory_budget) {
  std::error_code error;
  const std::uintmax_t size = std::filesystem::file_size(path, error);
  if (error) return;  // read_grids names what is wrong with the path
  const double budget = static_cast<double>(resolved_memory_budget(memory_budget));
  if (static_cast<double>(size) > budget)
    throw Error("VDB metric file " + path + " holds " + format_bytes(static_cast<double>(size)) +
                ", over the memory budget of " + format_bytes(budget) +
                " (--memory-budget), even before its grids are decompressed");
}

// The six grids must have values at the same voxels (m13, m23, m33 may be absent in 2D): a
// component stored where m11 is not would be read by the interpolation without ever being
// validated, and one missing where m11 has a value would blend in the background 0.
void require_same_voxels(const std::string& path, const std::array<FloatGrid::Ptr, 6>& grids,
                         int dimension) {
  for (int n = 1; n < (dimension == 2 ? 3 : 6); ++n) {
    for (const bool extra : {true, false}) {
      openvdb::MaskTree difference(extra ? grids[n]->tree() : grids[0]->tree(), false,
                                   openvdb::TopologyCopy());
      difference.topologyDifference(extra ? grids[0]->tree() : grids[n]->tree());
      const auto voxel = difference.cbeginValueOn();
      if (!voxel) continue;
      throw Error("VDB metric file " + path + ": grid '" + kMetricGridNames[n] +
                  (extra ? "' has a value at voxel " : "' has no value at voxel ") +
                  voxel_text(voxel.getCoord()) +
                  (extra ? ", where 'm11' has none" : ", where 'm11' has one"));
    }
  }
}

// The field's dimension: the file's rvor_dimension metadata where it has one, else 2 for values
// on one z layer (files from elsewhere). A file marked 2D must hold one layer: which one would be
// the plane is not for the reader to guess.
int stored_dimension(const std::string& path, const FloatGrid& grid) {
  const openvdb::CoordBBox box = grid.evalActiveVoxelBoundingBox();
  const bool one_layer = box.min().z() == box.max().z();
  const openvdb::Metadata::ConstPtr any = grid["rvor_dimension"];
  if (!any) return one_layer ? 2 : 3;
  // Of another type it was ignored, and the layers decided, whatever it said. An int64 is what
  // pyopenvdb stores for a Python int.
  std::int64_t value = 0;
  if (const auto int32 = grid.getMetadata<openvdb::Int32Metadata>("rvor_dimension"))
    value = int32->value();
  else if (const auto int64 = grid.getMetadata<openvdb::Int64Metadata>("rvor_dimension"))
    value = int64->value();
  else
    throw Error("VDB metric file " + path + ": metadata rvor_dimension is of type " +
                any->typeName() + " (" + quoted_text(any->str(), 40) + "), not an integer 2 or 3");
  if (value != 2 && value != 3)
    throw Error("VDB metric file " + path + ": metadata rvor_dimension is " +
                std::to_string(value) + ", not 2 or 3");
  if (value == 2 && !one_layer)
    throw Error("VDB metric file " + path +
                ": marked 2D (metadata rvor_dimension = 2) but grid 'm11' holds values on z " +
                "layers " + std::to_string(box.min().z()) + " to " + std::to_string(box.max().z()) +
                " (a 2D metric is one layer)");
  return static_cast<int>(value);
}

class VdbMetricField : public MetricField {
 public:
  VdbMetricField(const std::string& path, std::array<FloatGrid::Ptr, 6> grids,
                 std::uint64_t memory_budget)
      : path_(path), grids_(std::move(grids)) {
    dimension_ = stored_dimension(path, *grids_[0]);
    guessed_2d_ =
        dimension_ == 2 && !grids_[0]->getMetadata<openvdb::Int32Metadata>("rvor_dimension");
    const openvdb::CoordBBox box = grids_[0]->evalActiveVoxelBoundingBox();
    layer_z_ = box.min().z();
    bounds_ = world_bounds(box);
    for (const auto& grid : grids_)
      if (grid->transform() != grids_[0]->transform())
        throw Error("VDB metric file " + path + ": grids m11 ... m33 have different transforms");
    require_voxels_fit(path, grids_, memory_budget);
    for (const auto& grid : grids_) grid->tree().voxelizeActiveTiles();
    require_same_voxels(path, grids_, dimension_);
    validate_stored_tensors(path, grids_, dimension_);
    for (const auto& grid : grids_) extend_by_one_voxel(*grid);
  }

  int dimension() const override { return dimension_; }
  // Says why a file without rvor_dimension is 2D: a 3D domain refuses it by this description.
  std::string description() const override {
    return "vdb:" + path_ + (guessed_2d_ ? " (2D: its values lie on one z layer)" : "");
  }
  std::optional<Box> natural_domain() const override { return bounds_; }
  std::uint64_t resident_bytes() const override {
    std::uint64_t bytes = 0;
    for (const auto& grid : grids_) bytes += grid->memUsage();
    return bytes;
  }

  Mat3 at(const Vec3& p) const override {
    openvdb::Vec3d index = grids_[0]->transform().worldToIndex(openvdb::Vec3d(p.x(), p.y(), p.z()));
    if (dimension_ == 2) index.z() = layer_z_;  // a 2D field is one voxel layer
    require_covered(index, p);
    SolTensor c{};
    for (int n = 0; n < 6; ++n) {
      // A private, unregistered accessor per call: thread-safe, and its cache serves the eight
      // corner look-ups of the interpolation.
      UnsafeAccessor accessor(grids_[n]->tree());
      c[n] = openvdb::tools::BoxSampler::sample(accessor, index);
    }
    if (dimension_ == 2) {
      c[3] = c[4] = 0;
      c[5] = 1;
    }
    return tensor_from_sol(c);
  }

 private:
  // The interpolation's eight corners must hold values (stored, or the shell around them), else
  // it blends in the background 0, which is no metric.
  void require_covered(const openvdb::Vec3d& index, const Vec3& p) const {
    const openvdb::Coord lo = openvdb::Coord::floor(index);
    UnsafeAccessor accessor(grids_[0]->tree());
    for (int corner = 0; corner < 8; ++corner) {
      const openvdb::Coord c =
          lo.offsetBy(corner & 1, (corner >> 1) & 1, dimension_ == 2 ? 0 : (corner >> 2) & 1);
      if (!accessor.isValueOn(c))
        throw Error("the metric of VDB file " + path_ + " does not cover (" +
                    std::to_string(p.x()) + ", " + std::to_string(p.y()) + ", " +
                    std::to_string(p.z()) + "): the domain reaches beyond its grids' values");
    }
  }

  Box world_bounds(const openvdb::CoordBBox& box) const {
    const auto& transform = grids_[0]->transform();
    const auto lo = transform.indexToWorld(box.min().asVec3d() - openvdb::Vec3d(0.5));
    const auto hi = transform.indexToWorld(box.max().asVec3d() + openvdb::Vec3d(0.5));
    Box bounds{Vec3(lo.x(), lo.y(), lo.z()), Vec3(hi.x(), hi.y(), hi.z())};
    if (dimension_ == 2) bounds.lo.z() = bounds.hi.z() = 0;
    return bounds;
  }

  std::string path_;
  std::array<FloatGrid::Ptr, 6> grids_;
  int dimension_ = 3;
  bool guessed_2d_ = false;  // one z layer and no rvor_dimension metadata
  int layer_z_ = 0;
  Box bounds_;
};

}  // namespace

std::unique_ptr<MetricField> load_vdb_metric(const std::string& vdb_path,
                                             std::uint64_t memory_budget) {
  require_file_fits(vdb_path, memory_budget);
  const openvdb::GridPtrVec grids = read_grids(vdb_path, [&](const VdbArchiveSummary& summary) {
    require_recorded_voxels_fit(vdb_path, summary, memory_budget);
  });
  std::array<FloatGrid::Ptr, 6> components;
  for (int n = 0; n < 6; ++n)
    components[n] = find_grid<FloatGrid>(grids, vdb_path, kMetricGridNames[n], "float");
  if (components[0]->activeVoxelCount() == 0)
    throw Error("VDB metric file " + vdb_path + ": grid 'm11' has no active voxel");
  return std::make_unique<VdbMetricField>(vdb_path, std::move(components), memory_budget);
}

}  // namespace rvor
