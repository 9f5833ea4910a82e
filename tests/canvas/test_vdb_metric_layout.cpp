// VDB metric files whose six grids do not hold values at the same voxels (written with OpenVDB
// directly: rvor's own writer always gives them one layout).
#include <gtest/gtest.h>
#include <openvdb/io/Stream.h>
#include <openvdb/openvdb.h>

#include <cstdint>
#include <cstring>
#include <fstream>
#include <string>

#include "canvas_test_support.h"
#include "rvor/metric_field.h"
#include "support/temp_dir.h"
#include "vdb_support.h"

namespace rvor {
namespace {

// The identity on the z layers [z0, z1] of [-4, 4]^2 in every grid, each grid marked with
// rvor_dimension = `dimension` (0: no metadata).
openvdb::GridPtrVec identity_grids(int z0, int z1, int dimension) {
  openvdb::initialize();
  openvdb::GridPtrVec grids;
  for (int n = 0; n < 6; ++n) {
    auto grid = openvdb::FloatGrid::create(0.0f);
    grid->setName(kMetricGridNames[n]);
    if (dimension != 0) grid->insertMeta("rvor_dimension", openvdb::Int32Metadata(dimension));
    const float value = n == 0 || n == 2 || n == 5 ? 1.0f : 0.0f;
    for (int k = z0; k <= z1; ++k)
      for (int j = -4; j <= 4; ++j)
        for (int i = -4; i <= 4; ++i) grid->tree().setValueOn(openvdb::Coord(i, j, k), value);
    grids.push_back(grid);
  }
  return grids;
}

std::string write_grids(const test::TempDir& dir, const openvdb::GridPtrVec& grids) {
  const std::string path = dir.file("metric.vdb");
  openvdb::io::File(path).write(grids);
  return path;
}

// The identity over the index box [-4, 4]^3 in every grid, then `edit` applied to grid `which`.
template <typename Edit>
std::string write_metric(const test::TempDir& dir, int which, Edit edit) {
  const openvdb::GridPtrVec grids = identity_grids(-4, 4, 0);
  if (which >= 0) edit(static_cast<openvdb::FloatGrid&>(*grids[which]));
  return write_grids(dir, grids);
}

TEST(VdbMetricLayout, ComponentsStoredWhereM11IsNotAreNamed) {
  test::TempDir dir;
  const std::string extra = write_metric(dir, 1, [](openvdb::FloatGrid& m12) {
    m12.tree().setValueOn(openvdb::Coord(5, -4, -4), 50.0f);  // beyond m11: never validated
  });
  const std::string message = test::error_of([&] { load_vdb_metric(extra); });
  EXPECT_NE(message.find("grid 'm12' has a value at voxel (5, -4, -4), where 'm11' has none"),
            std::string::npos)
      << message;

  const std::string hole = write_metric(
      dir, 4, [](openvdb::FloatGrid& m23) { m23.tree().setValueOff(openvdb::Coord(0, 1, 2)); });
  const std::string missing = test::error_of([&] { load_vdb_metric(hole); });
  EXPECT_NE(missing.find("grid 'm23' has no value at voxel (0, 1, 2), where 'm11' has one"),
            std::string::npos)
      << missing;

  const std::string fine = write_metric(dir, -1, [](openvdb::FloatGrid&) {});
  EXPECT_EQ(load_vdb_metric(fine)->at(Vec3(0.2, 0.1, -0.3)), Mat3::Identity());
}

std::string write_layers(const test::TempDir& dir, int z0, int z1, int dimension) {
  return write_grids(dir, identity_grids(z0, z1, dimension));
}

// The archive check (check_vdb_archive) walks every grid of a seekable archive, but only the first
// of a streamed one (no grid offsets): both read back as written, with file metadata, a grid
// stored as half floats and one that shares another's tree (an instance).
TEST(VdbMetricLayout, StreamedAndSeekableArchivesAreRead) {
  test::TempDir dir;
  openvdb::GridPtrVec grids = identity_grids(-4, 4, 3);
  grids[1]->setSaveFloatAsHalf(true);
  auto instance = grids[0]->copyGrid();  // the same tree under another name
  instance->setName("m11_instance");
  grids.push_back(instance);
  openvdb::MetaMap file_metadata;
  file_metadata.insertMeta("creator", openvdb::StringMetadata("test"));
  const std::string seekable = dir.file("seekable.vdb"), streamed = dir.file("streamed.vdb");
  openvdb::io::File(seekable).write(grids, file_metadata);
  {
    std::ofstream out(streamed, std::ios::binary);
    openvdb::io::Stream(out).write(grids, file_metadata);
  }
  for (const std::string& path : {seekable, streamed})
    EXPECT_EQ(load_vdb_metric(path)->at(Vec3(0.2, 0.1, -0.3)), Mat3::Identity()) << path;
}

// A damaged string length: OpenVDB allocated it (up to 4 GiB, for seconds) before its read
// failed; the archive check refuses it first and says where.
TEST(VdbMetricLayout, ADamagedLengthIsRefusedBeforeOpenVdbAllocatesIt) {
  test::TempDir dir;
  const std::string path = write_layers(dir, -4, 4, 3);
  std::string bytes = test::read_text(path);
  const auto damage = [&](const std::string& field, const std::string& expected) {
    std::string damaged = bytes;
    const std::size_t at = damaged.find(field);
    ASSERT_NE(at, std::string::npos) << field;
    const std::uint32_t huge = 0xFFFFFF00u;
    std::memcpy(&damaged[at - sizeof huge], &huge, sizeof huge);  // the length before the text
    test::write_text(dir.file("damaged.vdb"), damaged);
    const std::string message = test::error_of([&] { load_vdb_metric(dir.file("damaged.vdb")); });
    EXPECT_NE(message.find("it is damaged or cut short: " + expected), std::string::npos)
        << message;
  };
  damage("m11", "a grid's name at byte");
  damage("rvor_dimension", "a metadata name at byte");
  damage("UniformScaleMap", "a grid's transform at byte");
}

// Tiles stand for many voxels: grids whose voxels would not fit in the memory budget are refused
// before they are voxelized, against --memory-budget when one is given (the default budget was
// used whatever the user gave).
TEST(VdbMetricLayout, GridsBeyondTheMemoryBudgetAreRefused) {
  test::TempDir dir;
  const std::string small = write_grids(dir, identity_grids(-4, 4, 3));  // 6 x 729 voxels
  EXPECT_GE(load_vdb_metric(small)->resident_bytes(), 6u * 729 * sizeof(float));
  const std::string refused = test::error_of([&] { load_vdb_metric(small, 10000); });
  EXPECT_NE(refused.find("over the memory budget of"), std::string::npos) << refused;
  EXPECT_NE(refused.find("(--memory-budget)"), std::string::npos) << refused;
  openvdb::GridPtrVec huge = identity_grids(0, 0, 3);
  for (const openvdb::GridBase::Ptr& grid : huge)  // 2^36 voxels a grid, as tiles
    static_cast<openvdb::FloatGrid&>(*grid).fill(
        openvdb::CoordBBox(openvdb::Coord(0), openvdb::Coord(4095)), 1.0f, true);
  const std::string tiles = test::error_of([&] { load_vdb_metric(write_grids(dir, huge)); });
  EXPECT_NE(tiles.find("active voxels in all (many as tiles)"), std::string::npos) << tiles;
}

// A file marked 2D with several z layers used to be read on its lowest layer, silently.
TEST(VdbMetricLayout, FilesMarkedTwoDimensionalHoldOneLayer) {
  test::TempDir dir;
  const std::string message = test::error_of([&] { load_vdb_metric(write_layers(dir, -1, 2, 2)); });
  EXPECT_NE(message.find("marked 2D (metadata rvor_dimension = 2) but grid 'm11' holds values on "
                         "z layers -1 to 2"),
            std::string::npos)
      << message;
  EXPECT_NE(test::error_of([&] {
              load_vdb_metric(write_layers(dir, 0, 0, 5));
            }).find("metadata rvor_dimension is 5, not 2 or 3"),
            std::string::npos);
  EXPECT_EQ(load_vdb_metric(write_layers(dir, 3, 3, 2))->dimension(), 2);
  // Metadata of another type was ignored.
  openvdb::GridPtrVec text_marked = identity_grids(0, 0, 0);
  for (const auto& grid : text_marked)
    grid->insertMeta("rvor_dimension", openvdb::StringMetadata("3"));
  EXPECT_NE(test::error_of([&] {
              load_vdb_metric(write_grids(dir, text_marked));
            }).find("metadata rvor_dimension is of type string ('3'), not an integer 2 or 3"),
            std::string::npos);
  // pyopenvdb stores a Python int as an int64.
  openvdb::GridPtrVec int64_marked = identity_grids(0, 0, 0);
  for (const auto& grid : int64_marked)
    grid->insertMeta("rvor_dimension", openvdb::Int64Metadata(3));
  EXPECT_EQ(load_vdb_metric(write_grids(dir, int64_marked))->dimension(), 3);
  // Marked 3D, one layer is a 3D field (a slab); without metadata it is taken as 2D and says so.
  EXPECT_EQ(load_vdb_metric(write_layers(dir, 3, 3, 3))->dimension(), 3);
  const auto guessed = load_vdb_metric(write_layers(dir, 3, 3, 0));
  EXPECT_EQ(guessed->dimension(), 2);
  EXPECT_NE(guessed->description().find("(2D: its values lie on one z layer)"), std::string::npos);
  EXPECT_EQ(load_vdb_metric(write_layers(dir, 0, 1, 0))->dimension(), 3);
}

}  // namespace
}  // namespace rvor
