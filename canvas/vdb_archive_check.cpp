#include "vdb_archive_check.h"

#include <algorithm>
#include <cstdint>
#include <istream>
#include <optional>
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

  // A string of at most `most` bytes; a longer one is skipped and reads as empty.
  std::string read_string(const char* what, std::uint32_t most) {
    const auto length = read<std::uint32_t>(what);
    if (length > most) {
      skip(length, what);
      return {};
    }
    require(length, what);
    std::string text(length, '\0');
    in_.read(text.data(), length);
    position_ += length;
    return text;
  }

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
// Returns the value of file_voxel_count where the map holds it (an int64).
std::optional<std::int64_t> read_metadata(ArchiveWalker& walker) {
  constexpr std::uint32_t kLongestMetadataName = 64;
  std::optional<std::int64_t> recorded_voxels;
  const auto count = walker.read<std::uint32_t>("a metadata count");
  for (std::uint32_t entry = 0; entry < count; ++entry) {
    const std::string name = walker.read_string("a metadata name", kLongestMetadataName);
    const std::string type = walker.read_string("a metadata type name", kLongestMetadataName);
    const auto size = walker.read<std::uint32_t>("a metadata value's size");
    if (name == "file_voxel_count" && type == "int64" && size == sizeof(std::int64_t))
      recorded_voxels = walker.read<std::int64_t>("a metadata value");
    else
      walker.skip(size, "a metadata value");
  }
  return recorded_voxels;
}

// What OpenVDB reads of a grid before its voxels: compression flags, metadata, the map's name.
// Records the grid's file_voxel_count under its name.
void read_grid_header(ArchiveWalker& walker, const std::string& name, VdbArchiveSummary& summary) {
  walker.read<std::uint32_t>("a grid's compression flags");
  const std::optional<std::int64_t> voxels = read_metadata(walker);
  walker.skip_string("a grid's transform");
  if (!voxels) return;
  const auto [entry, added] = summary.recorded_voxels.emplace(name, *voxels);
  if (!added) entry->second = std::max(entry->second, *voxels);  // names repeat: the largest
}

// A grid descriptor's name without the suffix OpenVDB adds to repeated names (after '\x1e').
std::string grid_name(const std::string& unique_name) {
  return unique_name.substr(0, unique_name.find('\x1e'));
}

}  // namespace

VdbArchiveSummary check_vdb_archive(std::istream& in, const std::string& path) {
  VdbArchiveSummary summary;
  in.seekg(0, std::ios::end);
  const auto end = in.tellg();
  if (end < 0) return summary;
  in.seekg(0);
  ArchiveWalker walker(path, in, static_cast<std::uint64_t>(end));
  constexpr std::uint64_t kMagicAndVersion = 12;
  if (static_cast<std::uint64_t>(end) < kMagicAndVersion) return summary;
  if (walker.read<std::int64_t>("the magic number") != openvdb::OPENVDB_MAGIC) return summary;
  const auto version = walker.read<std::uint32_t>("the format version");
  if (version < openvdb::OPENVDB_FILE_VERSION_NODE_MASK_COMPRESSION ||
      version > openvdb::OPENVDB_FILE_VERSION)
    return summary;  // another header layout
  walker.skip(2 * sizeof(std::uint32_t), "the library version");
  const bool grid_offsets = walker.read<char>("the grid offsets flag") != 0;
  walker.skip(36, "the file's UUID");
  read_metadata(walker);  // the file's: no grid's count
  const auto grids = walker.read<std::int32_t>("the grid count");
  for (std::int32_t grid = 0; grid < grids; ++grid) {
    constexpr std::uint32_t kLongestGridName = 256;
    const std::string name = grid_name(walker.read_string("a grid's name", kLongestGridName));
    walker.skip_string("a grid's type");
    walker.skip_string("a grid's instance parent");
    const auto start = walker.read<std::int64_t>("a grid's offsets");
    const auto block = walker.read<std::int64_t>("a grid's offsets");
    const auto stop = walker.read<std::int64_t>("a grid's offsets");
    if (!grid_offsets) {  // written as a stream: the grid follows, and the next one after it
      read_grid_header(walker, name, summary);
      return summary;
    }
    // An instance (a grid sharing another's tree) has no voxel block: its block offset stays 0.
    const bool block_inside = block == 0 || (start <= block && block <= stop);
    if (start < static_cast<std::int64_t>(walker.position()) || stop < start || !block_inside)
      walker.damaged("a grid's offsets");
    walker.seek(static_cast<std::uint64_t>(stop), "a grid's data");
    walker.seek(static_cast<std::uint64_t>(start), "a grid's data");
    read_grid_header(walker, name, summary);
    walker.seek(static_cast<std::uint64_t>(stop), "a grid's data");
  }
  return summary;
}

}  // namespace rvor
