#pragma once
// Output files are never half-written: they are written under a temporary name in the same
// directory and renamed over the target only once complete. Every library writer (write_xyz,
// write_voronoi_vdb, the VTU, Medit and PNG writers) goes through here, so it replaces a file
// already at its path without asking (the CLI asks first: --overwrite), takes a symlink's place
// (its target is left alone) and gives the file the process's default mode. A device, FIFO or
// socket at the path is an error: it is never replaced.
#include <functional>
#include <optional>
#include <ostream>
#include <string>

namespace rvor {

// Writes `path` through `writer`; throws rvor::Error naming the path when the directory is not
// writable or the stream fails. On failure the previous file (if any) is untouched.
void write_file_atomically(const std::string& path,
                           const std::function<void(std::ostream&)>& writer, bool binary = false);

// For writers that need a file name (OpenVDB): a unique temporary name next to `path`, and the
// rename that publishes it (throws rvor::Error naming both paths on failure).
std::string temporary_path_for(const std::string& path);
// The process id in `name` (a file name, no directory) when temporary_path_for gave it for a file
// named `file_name`; nullopt for any other name. Lets a cleanup tell a killed run's temporaries
// from those of a run still writing.
std::optional<long> temporary_owner(const std::string& name, const std::string& file_name);
void publish_temporary(const std::string& temporary, const std::string& path);
// Gives `source` the name `target` too (a hard link; `source` stays), never replacing a file at
// `target`: one there (that appeared since the caller checked) is an error and stays as it is.
// On a file system without hard links, `source` is renamed to `target` instead.
void link_new(const std::string& source, const std::string& target);

// Throws rvor::Error "cannot write to output directory DIR: reason" unless DIR exists (it is
// created with its parents if missing) and a file can be created in it.
void prepare_output_directory(const std::string& dir);

}  // namespace rvor
