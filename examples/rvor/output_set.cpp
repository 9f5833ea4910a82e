#include "output_set.h"

#include <fcntl.h>
#include <signal.h>
#include <sys/file.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <filesystem>

#include "rvor/atomic_file.h"
#include "rvor/error.h"

namespace fs = std::filesystem;

namespace rvor::cli {

namespace {

// The staging directory's name before temporary_path_for's ".tmp-PID-N": it holds the host's name,
// so that a run only judges the processes of its own host (an --out on a shared file system).
std::string staging_stem() {
  char host[256] = {};
  gethostname(host, sizeof host - 1);
  return "outputs-" + std::string(host);
}

// Staging directories of this host's runs that were killed before they could remove theirs: those
// whose process is gone. A live process's, or one whose name does not parse, stays.
void remove_abandoned_staging(const std::string& dir) {
  std::error_code error;
  for (fs::directory_iterator entry(dir, error), end; !error && entry != end;
       entry.increment(error)) {
    const std::optional<long> pid =
        temporary_owner(entry->path().filename().string(), staging_stem());
    std::error_code status;
    if (!pid || !entry->is_directory(status)) continue;
    if (*pid == getpid() || kill(static_cast<pid_t>(*pid), 0) == 0 || errno != ESRCH) continue;
    std::error_code ignored;
    fs::remove_all(entry->path(), ignored);
  }
}

// An exclusive lock on a directory for the scope (flock on the directory itself: advisory, between
// rvor runs). A file system without locks leaves it unlocked, as before.
class DirectoryLock {
 public:
  explicit DirectoryLock(const std::string& dir) : fd_(open(dir.c_str(), O_RDONLY | O_DIRECTORY)) {
    if (fd_ >= 0) flock(fd_, LOCK_EX);
  }
  DirectoryLock(const DirectoryLock&) = delete;
  DirectoryLock& operator=(const DirectoryLock&) = delete;
  ~DirectoryLock() {
    if (fd_ >= 0) close(fd_);  // releases the lock
  }

 private:
  int fd_;
};

}  // namespace

std::vector<std::string> missing_folders(const std::string& path) {
  std::vector<std::string> missing;
  fs::path prefix;
  std::error_code error;
  for (const fs::path& part : fs::path(path)) {
    prefix /= part;
    if (part.empty() || part == "." || part == "..") continue;
    if (!fs::exists(prefix, error)) missing.push_back(prefix.string());
  }
  return missing;
}

void remove_empty_folders(const std::vector<std::string>& folders) {
  std::error_code error;
  for (auto folder = folders.rbegin(); folder != folders.rend(); ++folder)
    fs::remove(*folder, error);  // fails on a folder that holds something
}

OutputSet::OutputSet(std::string dir, std::vector<std::string> names, bool replace,
                     std::vector<std::string> created_folders)
    : dir_(std::move(dir)),
      names_(std::move(names)),
      created_folders_(std::move(created_folders)),
      replace_(replace) {
  remove_abandoned_staging(dir_);
  for (const std::string& name : names_) {
    const fs::path target = fs::path(dir_) / name;
    std::error_code error;
    const fs::file_status status = fs::symlink_status(target, error);
    if (!fs::exists(status)) continue;
    if (!fs::is_regular_file(status))
      throw Error(target.string() +
                  " exists and is not a regular file; remove it or choose "
                  "another --out");
    if (!replace_) throw Error(target.string() + " already exists; pass --overwrite to replace it");
  }
  staging_ = temporary_path_for((fs::path(dir_) / staging_stem()).string());
  std::error_code error;
  if (!fs::create_directory(staging_, error))
    throw Error("cannot write to output directory " + dir_ + ": " +
                (error ? error.message() : "cannot create a staging directory"));
  interrupt_cleanup_.emplace(staging_, created_folders_);
}

OutputSet::~OutputSet() {
  std::error_code ignored;
  fs::remove_all(staging_, ignored);
  if (!committed_) remove_empty_folders(created_folders_);
}

std::string OutputSet::path(const std::string& name) const {
  return (fs::path(staging_) / name).string();
}

// Without replace_, a file another run published meanwhile must stay (the constructor's check was
// long ago), and then none of this run's files is published: the set goes in whole or not at all.
void OutputSet::publish_all_new() {
  std::vector<std::string> published;
  try {
    for (const std::string& name : names_) {
      const std::string target = (fs::path(dir_) / name).string();
      link_new(path(name), target);
      published.push_back(target);
    }
  } catch (const Error&) {
    std::error_code ignored;
    for (const std::string& target : published) fs::remove(target, ignored);
    throw;
  }
}

std::string OutputSet::shown(std::string message) const {
  for (std::size_t at = message.find(staging_); at != std::string::npos;
       at = message.find(staging_, at + dir_.size()))
    message.replace(at, staging_.size(), dir_);
  return message;
}

void OutputSet::commit(const std::function<std::vector<std::string>()>& earlier_names) {
  for (const std::string& name : names_)
    if (!fs::is_regular_file(path(name)))
      throw Error("internal error: output " + name + " was not written");
  const DirectoryLock lock(dir_);
  const std::vector<std::string> earlier = earlier_names();
  interrupt_cleanup_->hold();  // the set goes in whole, then an interruption takes effect
  committed_ = true;
  if (!replace_) {
    publish_all_new();
    return;
  }
  for (const std::string& name : names_)
    publish_temporary(path(name), (fs::path(dir_) / name).string());
  for (const std::string& name : earlier) {
    if (std::find(names_.begin(), names_.end(), name) != names_.end()) continue;
    const fs::path stale = fs::path(dir_) / name;
    std::error_code error;
    if (fs::is_regular_file(fs::symlink_status(stale, error))) fs::remove(stale, error);
  }
}

}  // namespace rvor::cli
