#include "vdb_archive_check.h"

#include <cstdint>
#include <istream>
#include <string>

#include <openvdb/version.h>

#include "rvor/error.h"

namespace rvor {

namespace {

// Reads and skips through the archive, refusing any length that runs past the end of the file.
class ArchiveWalker {
 public:
  ArchiveWalker(const std::string& path, std::istream& in, std::uint64_t size)
      : path_(path), in_(in), size_(size) {}

  std::uint64_t position() const { return position_; }

  template <typename Value>
  Value read(const char* what) {
    require(sizeof(Value), what);
    Value value{};
    in_.read(reinterpret_cast<char*>(&value), sizeof(Value));
    position_ += sizeof(Value);
    return value;
  }

  void skip(std::uint64_t bytes, const char* what) { seek(position_ + bytes, what); }

  // OpenVDB's strings: a 32-bit length, then the bytes.
  void skip_string(const char* what) { skip(read<std::uint32_t>(what), what); }

  void seek(std::uint64_t to, const char* what) {
    if (to > size_) damaged(what);
    in_.seekg(static_cast<std::streamoff>(to));
    position_ = to;
  }

  [[noreturn]] void damaged(const char* what) const {
    throw Error("cannot read VDB file " + path_ + ": it is damaged or cut short: " + what +
                " at byte " + std::to_string(position_) + " runs past its end (" +
                std::to_string(size_) + " bytes)");
  }

 private:
  void require(std::uint64_t bytes, const char* what) const {
    if (bytes > size_ - position_) damaged(what);
  }

  const std::string& path_;
  std::istream& in_;
  std::uint64_t size_;
  std::uint64_t position_ = 0;
};

// A MetaMap: a count, then per entry its name, its type name and its value's size and bytes.
void skip_metadata(ArchiveWalker& walker) {
  const auto count = walker.read<std::uint32_t>("a metadata count");
  for (std::uint32_t entry = 0; entry < count; ++entry) {
    walker.skip_string("a metadata name");
    walker.skip_string("a metadata type name");
    walker.skip(walker.read<std::uint32_t>("a metadata value's size"), "a metadata value");
  }
}

// What OpenVDB reads of a grid before its voxels: compression flags, metadata, the map's name.
void skip_grid_header(ArchiveWalker& walker) {
  walker.read<std::uint32_t>("a grid's compression flags");
  skip_metadata(walker);
  walker.skip_string("a grid's transform");
}

}  // namespace

void check_vdb_archive(std::istream& in, const std::string& path) {
  in.seekg(0, std::ios::end);
  const auto end = in.tellg();
  if (end < 0) return;
  in.seekg(0);
  ArchiveWalker walker(path, in, static_cast<std::uint64_t>(end));
  constexpr std::uint64_t kMagicAndVersion = 12;
  if (static_cast<std::uint64_t>(end) < kMagicAndVersion) return;
  if (walker.read<std::int64_t>("the magic number") != openvdb::OPENVDB_MAGIC) return;
  const auto version = walker.read<std::uint32_t>("the format version");
  if (version < openvdb::OPENVDB_FILE_VERSION_NODE_MASK_COMPRESSION ||
      version > openvdb::OPENVDB_FILE_VERSION)
    return;  // another header layout
  walker.skip(2 * sizeof(std::uint32_t), "the library version");
  const bool grid_offsets = walker.read<char>("the grid offsets flag") != 0;
  walker.skip(36, "the file's UUID");
  skip_metadata(walker);
  const auto grids = walker.read<std::int32_t>("the grid count");
  for (std::int32_t grid = 0; grid < grids; ++grid) {
    walker.skip_string("a grid's name");
    walker.skip_string("a grid's type");
    walker.skip_string("a grid's instance parent");
    const auto start = walker.read<std::int64_t>("a grid's offsets");
    const auto block = walker.read<std::int64_t>("a grid's offsets");
    const auto stop = walker.read<std::int64_t>("a grid's offsets");
    if (!grid_offsets) {  // written as a stream: the grid follows, and the next one after it
      skip_grid_header(walker);
      return;
    }
    // An instance (a grid sharing another's tree) has no voxel block: its block offset stays 0.
    const bool block_inside = block == 0 || (start <= block && block <= stop);
    if (start < static_cast<std::int64_t>(walker.position()) || stop < start || !block_inside)
      walker.damaged("a grid's offsets");
    walker.seek(static_cast<std::uint64_t>(stop), "a grid's data");
    walker.seek(static_cast<std::uint64_t>(start), "a grid's data");
    skip_grid_header(walker);
    walker.seek(static_cast<std::uint64_t>(stop), "a grid's data");
  }
}

}  // namespace rvor
