#pragma once
// The output files of `rvor voronoi` as one set: they are written into a staging directory inside
// the output directory and moved into place together once the run has succeeded, so a run that
// fails (a bad input found late, a writer that throws) leaves the earlier outputs as they were.
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "interrupt_cleanup.h"

namespace rvor::cli {

// The folders of `path` that do not exist yet, outermost first: those prepare_output_directory
// creates, as create_directories makes them, so prefixes of the path as written ("new/../out"
// makes new and new/../out).
std::vector<std::string> missing_folders(const std::string& path);
// Removes `folders` innermost first, each only when empty.
void remove_empty_folders(const std::vector<std::string>& folders);

class OutputSet {
 public:
  // `names`: the files this run writes into `dir` (which must exist: prepare_output_directory).
  // `replace`: earlier files of those names may be replaced; otherwise their presence is an
  // error. `created_folders`: the folders this run created for `dir` (prepare_output_directory),
  // outermost first, `dir` last; a run that fails or is interrupted removes them again, each when
  // it is empty. Throws rvor::Error before anything is written when a name is taken by
  // something that is not a regular file, or exists without `replace`.
  OutputSet(std::string dir, std::vector<std::string> names, bool replace,
            std::vector<std::string> created_folders);
  OutputSet(const OutputSet&) = delete;
  OutputSet& operator=(const OutputSet&) = delete;
  ~OutputSet();  // removes what is still staged: before commit(), `dir` is as it was (also when
                 // the run is interrupted by SIGINT, SIGTERM or SIGHUP: InterruptCleanup)

  // Where the writer of `name` (one of the names) writes it until commit().
  std::string path(const std::string& name) const;
  // `message` with the staging directory written as the output directory: errors of the writers
  // name the file the user will look for, not a directory that is gone when they read it.
  std::string shown(std::string message) const;
  // Moves every staged file into `dir`; then, when replacing, removes the files of
  // earlier_names() that this run did not write (the rest of an earlier run's set). Throws
  // rvor::Error when a name was not written. Runs into the same `dir` commit one at a time (a
  // lock on the directory), and earlier_names is asked under that lock: a run that published
  // while this one computed is the earlier run (it was read when the run began, and two
  // --overwrite runs left a mixed set).
  void commit(const std::function<std::vector<std::string>()>& earlier_names);

 private:
  void publish_all_new();

  std::string dir_, staging_;
  std::vector<std::string> names_, created_folders_;
  bool replace_, committed_ = false;
  std::optional<InterruptCleanup> interrupt_cleanup_;
};

}  // namespace rvor::cli
