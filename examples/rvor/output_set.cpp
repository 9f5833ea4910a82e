#include "output_set.h"

#include <signal.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <filesystem>

#include "rvor/atomic_file.h"
#include "rvor/error.h"

namespace fs = std::filesystem;

namespace rvor::cli {

namespace {

// Staging directories (".outputs.tmp-PID-N") of runs that were killed before they could remove
// theirs: those whose process is gone. A live process's, or one whose name does not parse, stays.
void remove_abandoned_staging(const std::string& dir) {
  const std::string prefix = ".outputs.tmp-";
  std::error_code error;
  for (const fs::directory_entry& entry : fs::directory_iterator(dir, error)) {
    const std::string name = entry.path().filename().string();
    if (name.rfind(prefix, 0) != 0 || !entry.is_directory(error)) continue;
    const std::string rest = name.substr(prefix.size());
    const std::size_t dash = rest.find('-');
    if (dash == 0 || dash == std::string::npos || dash > 9 ||
        rest.find_first_not_of("0123456789") != dash)
      continue;
    const long pid = std::stol(rest.substr(0, dash));
    if (pid == getpid() || kill(static_cast<pid_t>(pid), 0) == 0 || errno != ESRCH) continue;
    fs::remove_all(entry.path(), error);
  }
}

}  // namespace

OutputSet::OutputSet(std::string dir, std::vector<std::string> names, bool replace)
    : dir_(std::move(dir)), names_(std::move(names)), replace_(replace) {
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
  staging_ = temporary_path_for((fs::path(dir_) / "outputs").string());
  std::error_code error;
  if (!fs::create_directory(staging_, error))
    throw Error("cannot write to output directory " + dir_ + ": " +
                (error ? error.message() : "cannot create a staging directory"));
}

OutputSet::~OutputSet() {
  std::error_code ignored;
  fs::remove_all(staging_, ignored);
}

std::string OutputSet::path(const std::string& name) const {
  return (fs::path(staging_) / name).string();
}

void OutputSet::commit(const std::vector<std::string>& earlier_names) {
  for (const std::string& name : names_)
    if (!fs::is_regular_file(path(name)))
      throw Error("internal error: output " + name + " was not written");
  for (const std::string& name : names_) {
    const std::string target = (fs::path(dir_) / name).string();
    // Without replace_, a file another run published meanwhile must stay (the constructor's check
    // was long ago).
    replace_ ? publish_temporary(path(name), target) : publish_new(path(name), target);
  }
  if (replace_)
    for (const std::string& name : earlier_names) {
      if (std::find(names_.begin(), names_.end(), name) != names_.end()) continue;
      const fs::path stale = fs::path(dir_) / name;
      std::error_code error;
      if (fs::is_regular_file(fs::symlink_status(stale, error))) fs::remove(stale, error);
    }
}

}  // namespace rvor::cli
