#include "rvor/atomic_file.h"

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <random>

#include <unistd.h>

#include "rvor/error.h"

namespace fs = std::filesystem;

namespace rvor {

namespace {

// ".NAME.tmp-": a temporary name is this, the process id, "-" and a random number below 10^9.
std::string temporary_prefix(const std::string& file_name) {
  return "." + file_name + ".tmp-";
}

// Throws unless what is at `path` may be replaced: nothing, a file, a symlink (its target is left
// alone) or a directory (the rename then says so). A device, FIFO or socket at the path would be
// replaced by a regular file: as root, writing to /dev/full replaced the device node for the
// whole machine.
void require_replaceable(const std::string& path) {
  std::error_code error;
  const fs::file_status status = fs::symlink_status(path, error);
  const fs::file_type type = error ? fs::file_type::not_found : status.type();
  const char* kind = type == fs::file_type::character ? "a character device"
                     : type == fs::file_type::block   ? "a block device"
                     : type == fs::file_type::fifo    ? "a FIFO"
                     : type == fs::file_type::socket  ? "a socket"
                     : type == fs::file_type::unknown ? "a file of an unknown kind"
                                                      : nullptr;
  if (kind)
    throw Error("cannot write " + path + ": it is " + kind +
                ", which rvor would replace by a regular file (it writes regular files only)");
}

}  // namespace

std::string temporary_path_for(const std::string& path) {
  static thread_local std::mt19937_64 random{std::random_device{}()};
  const fs::path target(path);
  const std::string name = temporary_prefix(target.filename().string()) + std::to_string(getpid()) +
                           "-" + std::to_string(random() % 1000000000ULL);
  return (target.parent_path() / name).string();
}

std::optional<long> temporary_owner(const std::string& name, const std::string& file_name) {
  const std::string prefix = temporary_prefix(file_name);
  if (name.rfind(prefix, 0) != 0) return std::nullopt;
  const std::string rest = name.substr(prefix.size());
  const std::size_t dash = rest.find('-');
  const bool digits_around_dash =
      dash != 0 && dash != std::string::npos && dash <= 9 &&
      rest.find_first_not_of("0123456789") == dash && dash + 1 < rest.size() &&
      rest.find_first_not_of("0123456789", dash + 1) == std::string::npos;
  if (!digits_around_dash) return std::nullopt;
  return std::stol(rest.substr(0, dash));
}

void publish_temporary(const std::string& temporary, const std::string& path) {
  std::error_code error;
  try {
    require_replaceable(path);
  } catch (const Error&) {
    fs::remove(temporary, error);
    throw;
  }
  fs::rename(temporary, path, error);
  if (error) {
    // Why, where it is plain: an empty path, or a directory in the file's place.
    const std::string reason = path.empty() ? "an empty path"
                               : fs::is_directory(path)
                                   ? "it is a directory"
                                   : "rename from temporary file failed (" + error.message() + ")";
    std::error_code ignored;
    fs::remove(temporary, ignored);
    throw Error("cannot write " + (path.empty() ? std::string("''") : path) + ": " + reason);
  }
}

void link_new(const std::string& source, const std::string& target) {
  // link() never replaces its target: a file that appeared at `target` since the caller checked
  // (another run writing to the same directory) stays.
  if (link(source.c_str(), target.c_str()) == 0) return;
  std::error_code ignored;
  if (errno == EEXIST || fs::exists(fs::symlink_status(target, ignored)))
    throw Error("cannot write " + target +
                ": it appeared while rvor was writing (another run with the same output "
                "directory?); it was left as it is");
  // A file system without hard links: the check above, then a rename (apart, not atomic).
  publish_temporary(source, target);
}

void write_file_atomically(const std::string& path,
                           const std::function<void(std::ostream&)>& writer, bool binary) {
  require_replaceable(path);  // before the work, and again at the rename
  const std::string temporary = temporary_path_for(path);
  try {
    std::ofstream out(temporary, binary ? std::ios::binary | std::ios::trunc : std::ios::trunc);
    if (!out) throw Error("cannot write " + path + ": " + std::strerror(errno));
    writer(out);
    out.flush();
    if (!out) throw Error("cannot write " + path + ": write failed (disk full?)");
  } catch (...) {
    std::error_code ignored;
    fs::remove(temporary, ignored);
    throw;
  }
  publish_temporary(temporary, path);
}

void prepare_output_directory(const std::string& dir) {
  std::error_code error;
  if (fs::exists(dir, error) && !fs::is_directory(dir, error))
    throw Error("cannot write to output directory " + dir + ": it exists and is not a directory");
  fs::create_directories(dir, error);
  if (error) throw Error("cannot write to output directory " + dir + ": " + error.message());
  const std::string probe = temporary_path_for((fs::path(dir) / "probe").string());
  std::ofstream out(probe);
  if (!out) throw Error("cannot write to output directory " + dir + ": " + std::strerror(errno));
  out.close();
  fs::remove(probe, error);
}

}  // namespace rvor
