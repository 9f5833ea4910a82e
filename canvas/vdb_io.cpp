#include "rvor/vdb_io.h"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <ios>
#include <limits>
#include <memory>
#include <new>
#include <stdexcept>
#include <string>
#include <system_error>
#include <vector>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <openvdb/io/Archive.h>
#include <openvdb/io/Stream.h>

#include "child_check.h"
#include "rvor/atomic_file.h"
#include "rvor/error.h"
#include "rvor/input_file.h"
#include "rvor/spec_text.h"
#include "vdb_support.h"

namespace rvor {

namespace {

// Unreached voxels hold +inf in VoronoiField; the grid's background is the same +inf, so what
// is not stored reads back exactly as "unreached" (OpenVDB stores and reads IEEE inf as is).
constexpr float kDistanceBackground = std::numeric_limits<float>::infinity();
constexpr std::int32_t kLabelBackground = -1;

// OpenVDB transforms need a positive voxel size (a default Canvas has 0, and OpenVDB's own
// exception said only "Non-zero scale values required").
void require_placed(const Canvas& canvas, const std::string& what) {
  if (!(canvas.voxel_size > 0) || !std::isfinite(canvas.voxel_size) || !canvas.origin.allFinite())
    throw Error(what + ": the canvas has no placement (voxel size " +
                std::to_string(canvas.voxel_size) +
                "): build it with build_canvas, or allocate() it");
}

template <typename GridType>
typename GridType::Ptr make_canvas_grid(const Canvas& canvas, const std::string& name,
                                        typename GridType::ValueType background) {
  auto grid = GridType::create(background);
  grid->setName(name);
  grid->setTransform(canvas_transform(canvas.voxel_size, canvas.origin));
  grid->insertMeta("rvor_dimension", openvdb::Int32Metadata(canvas.dimension));
  return grid;
}

// Sets value(slot) at every active voxel of the canvas. Canvas bricks are OpenVDB leaves (same
// origins), so leaves are filled in parallel and handed to the tree whole.
template <typename GridType, typename Value>
void fill_active(GridType& grid, const Canvas& canvas, Value value) {
  using Leaf = typename GridType::TreeType::LeafNodeType;
  std::vector<std::unique_ptr<Leaf>> leaves(canvas.brick_count());
  const auto background = grid.background();
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, leaves.size()), [&](const auto& range) {
    for (std::size_t brick = range.begin(); brick != range.end(); ++brick) {
      auto leaf = std::make_unique<Leaf>(to_coord(canvas.brick_origins[brick]), background, false);
      for (int local = 0; local < canvas.brick_volume(); ++local) {
        const std::size_t slot = brick * canvas.brick_volume() + local;
        if (canvas.active[slot])
          leaf->setValueOn(Leaf::coordToOffset(to_coord(canvas.voxel_of(slot))), value(slot));
      }
      leaves[brick] = std::move(leaf);
    }
  });
  for (auto& leaf : leaves)
    if (!leaf->isEmpty()) grid.tree().addLeaf(leaf.release());
}

// io::File::write does not check its stream: a full disk or a file size limit left a truncated
// file, published without an error. The same writer (the archive's, seekable, as io::File calls
// it) goes into a stream that write_file_atomically checks instead.
class CheckedArchiveWriter : public openvdb::io::Archive {
 public:
  void write_seekable(std::ostream& out, const openvdb::GridPtrVec& grids) const {
    Archive::write(out, grids, /*seekable=*/true);
  }
};

void write_grids_atomically(const std::string& path, const openvdb::GridPtrVec& grids) {
  openvdb::initialize();
  try {
    write_file_atomically(
        path, [&](std::ostream& out) { CheckedArchiveWriter().write_seekable(out, grids); },
        /*binary=*/true);
  } catch (const openvdb::Exception& error) {
    throw Error("cannot write VDB file " + path + ": " + error.what());
  }
}

void require_same_placement(const openvdb::GridBase& grid, const Canvas& canvas,
                            const std::string& path) {
  if (grid.transform() != *canvas_transform(canvas.voxel_size, canvas.origin))
    throw Error("grid '" + grid.getName() + "' in VDB file " + path +
                " does not have the canvas's voxel size and origin");
}

}  // namespace

// OpenVDB reads a string as its length, then that many bytes into a string it allocates first. In
// a file cut short that length was read past the end, garbage, and the message held gigabytes of
// blanks (VdbIo.ATruncatedFileIsNamedAsSuchInOneShortMessage); a length damaged inside the file
// cost the same allocation. So check_vdb_archive walks the lengths first, the file is read through
// a stream that throws at the first read past its end, and the message quotes at most the start
// of OpenVDB's.
namespace {

std::string cannot_read(const std::string& path) {
  return "cannot read VDB file " + path + ": ";
}

// Every grid of the archive at `path` (opened as `in`, at its start), every value read; the
// failures as rvor::Error naming the file.
openvdb::GridPtrVec read_stream(const std::string& path, std::istream& in) {
  const std::string too_large =
      cannot_read(path) + "it is damaged (it gives a size too large to allocate)";
  in.exceptions(std::ios::failbit | std::ios::badbit);
  try {
    openvdb::io::Stream stream(in, /*delayLoad=*/false);
    return *stream.getGrids();
  } catch (const std::ios_base::failure&) {
    throw Error(cannot_read(path) + "it ends early or is damaged");
  } catch (const openvdb::Exception& error) {
    throw Error(cannot_read(path) + quoted_text(error.what(), 200));
  } catch (const std::bad_alloc&) {
    throw Error(too_large);
  } catch (const std::length_error&) {
    throw Error(too_large);
  }
}

// OpenVDB's reader trusts the counts and sizes inside a grid's voxel data, which the archive
// check cannot follow: one flipped bit there corrupted its heap and the process died (6 of 378
// random single-bit flips of a metric file aborted rvor, VdbIo.AFileThatKillsOpenVdbsReader...;
// docs/measurements/vdb_guard.sh counts them).
// So the archive is read first in a child process (child_check.h): its death or its error becomes
// this one, and the caller reads only an archive the child read whole. The child reports while
// its grids still exist: destroying them runs TBB, which can wait forever on a lock that another
// thread of the caller held at the fork. Where no child can tell (none made, or none done within
// a minute plus a second per 10 MB), the read goes ahead unguarded.
void read_in_a_child_first(const std::string& path) {
  std::error_code error;
  const std::uintmax_t bytes = std::filesystem::file_size(path, error);
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(60) +
                        std::chrono::milliseconds(error ? 0 : bytes / 10000);
  const ChildEnd end = end_of_child(
      [&](const ChildReport& report) {
        try {
          std::ifstream in(path, std::ios::binary);
          const openvdb::GridPtrVec grids = read_stream(path, in);
          report("");
        } catch (const Error& e) {
          report(e.what());
        }
      },
      deadline);
  if (end.how == ChildEnd::How::died)
    throw Error(cannot_read(path) +
                "it is damaged (OpenVDB's reader died on its voxel data: " + end.text + ")");
  if (end.how == ChildEnd::How::reported && !end.text.empty()) throw Error(end.text);
}

}  // namespace

openvdb::GridPtrVec read_grids(const std::string& path,
                               const std::function<void(const VdbArchiveSummary&)>& before_values) {
  openvdb::initialize();
  // Read three times (its archive walked, read in a child, then here): a pipe failed at the first
  // seek with "basic_ios::clear: iostream error".
  InputFile in = open_regular_input_file(path, "VDB file", "rvor reads a VDB file more than once");
  const VdbArchiveSummary summary = check_vdb_archive(in, path);
  if (before_values) before_values(summary);
  read_in_a_child_first(path);
  in.clear();
  in.seekg(0);
  return read_stream(path, in);
}

void write_voronoi_vdb(const std::string& path, const Canvas& canvas, const VoronoiField& field) {
  require_placed(canvas, "cannot write VDB file " + path);
  require_field_for(canvas, field, "cannot write VDB file " + path);
  auto distance = make_canvas_grid<openvdb::FloatGrid>(canvas, "distance", kDistanceBackground);
  auto label = make_canvas_grid<openvdb::Int32Grid>(canvas, "label", kLabelBackground);
  fill_active(*distance, canvas, [&](std::size_t slot) { return field.distance[slot]; });
  fill_active(*label, canvas, [&](std::size_t slot) { return field.label[slot]; });
  write_grids_atomically(path, {distance, label});
}

// read_voronoi_vdb itself; the public entry point names a failed allocation.
static VoronoiField read_voronoi_vdb_itself(const std::string& path, const Canvas& canvas) {
  require_placed(canvas, "cannot read VDB file " + path + " onto the canvas");
  const auto grids = read_grids(path);
  const auto distance = find_grid<openvdb::FloatGrid>(grids, path, "distance", "float");
  const auto label = find_grid<openvdb::Int32Grid>(grids, path, "label", "int32");
  require_same_placement(*distance, canvas, path);
  require_same_placement(*label, canvas, path);
  VoronoiField field;
  field.distance.assign(canvas.slot_count(), std::numeric_limits<float>::infinity());
  field.label.assign(canvas.slot_count(), -1);
  const auto distances = distance->getConstAccessor();
  const auto labels = label->getConstAccessor();
  // The file must hold the canvas's active voxels, no more and no fewer: another canvas's field
  // of the same voxel size and origin filled the gaps with +inf and dropped the rest, silently.
  const auto file_voxels = static_cast<std::size_t>(distance->activeVoxelCount());
  if (file_voxels != canvas.active_voxel_count)
    throw Error("VDB file " + path + " holds a field of " + std::to_string(file_voxels) +
                " voxels, the canvas has " + std::to_string(canvas.active_voxel_count) +
                " active ones: it was written for another canvas");
  for (std::size_t slot = 0; slot < canvas.slot_count(); ++slot) {
    if (!canvas.active[slot]) continue;
    const openvdb::Coord c = to_coord(canvas.voxel_of(slot));
    // One look-up per grid gives the value and whether it is stored.
    if (!distances.probeValue(c, field.distance[slot]) || !labels.probeValue(c, field.label[slot]))
      throw Error("VDB file " + path + " has no value at the canvas's active voxel " +
                  voxel_text(c) + ": it was written for another canvas");
  }
  return field;
}

VoronoiField read_voronoi_vdb(const std::string& path, const Canvas& canvas) {
  return naming_out_of_memory("reading a Voronoi field from a VDB file",
                              [&] { return read_voronoi_vdb_itself(path, canvas); });
}

void write_metric_vdb(const std::string& path, const Canvas& canvas) {
  require_placed(canvas, "cannot write VDB file " + path);
  openvdb::GridPtrVec grids;
  for (int component = 0; component < 6; ++component) {
    auto grid = make_canvas_grid<openvdb::FloatGrid>(canvas, kMetricGridNames[component], 0.0f);
    fill_active(*grid, canvas, [&](std::size_t slot) { return canvas.metric_of(slot)[component]; });
    grids.push_back(grid);
  }
  write_grids_atomically(path, grids);
}

}  // namespace rvor
