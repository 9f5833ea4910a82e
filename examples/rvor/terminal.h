#pragma once
// Terminal conveniences of the rvor tool: stage progress lines, summaries, option parsing helpers.
#include <chrono>
#include <cstdint>
#include <ostream>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "rvor/field_summary.h"
#include "rvor/metric_reach.h"
#include "rvor/opencl_propagator.h"

namespace rvor::cli {

// Prints "building canvas ... done in 1.23 s (detail)" lines on stderr so stdout stays clean. A
// stage still open when the Progress goes away (an exception on its way to the error line) ends
// with "failed", so the error starts a line of its own.
class Progress {
 public:
  explicit Progress(bool quiet);
  Progress(const Progress&) = delete;
  Progress& operator=(const Progress&) = delete;
  ~Progress();
  void begin(const std::string& stage);
  // Shows how far the open stage is, after its name: on a terminal only (a log keeps one line per
  // stage), at most twice a second unless `now`.
  void update(const std::string& status, bool now = false);
  double end(const std::string& detail);  // returns the stage's seconds
  // Prints `line` on a line of its own, quiet or not, and the open stage's name again after it.
  void note(const std::string& line);

 private:
  // Starts the stage's line again where an update wrote over it.
  void restart_line();

  bool quiet_;
  bool terminal_;  // stderr is a terminal
  bool open_ = false;
  bool updated_ = false;
  std::string stage_;
  std::chrono::steady_clock::time_point start_, last_update_;
};

// The line that says rvor waits on a FIFO input that nothing has written to yet (a named pipe
// without a writer would otherwise hang the run silently): given quiet or not, as it explains a
// wait. rvor::set_fifo_wait_notice takes it.
std::string fifo_wait_text(const std::string& what, const std::string& path);
// fifo_wait_text on a line of stderr: the notice outside a progress stage.
void print_fifo_wait(const std::string& what, const std::string& path);

// "512M", "2G", "1.5T" or plain bytes. Throws rvor::Error on anything else.
std::uint64_t parse_byte_size(const std::string& text);
// --memory-budget's transform (parse_byte_size, handing on plain bytes): a bad size is reported
// at parse time, before anything else (it came after "out/voronoi.vdb already exists").
extern const CLI::Validator byte_size;
// What --memory-budget defaults to, in every command's help.
inline constexpr const char* kDefaultMemoryBudgetHelp =
    "default 75% of physical memory, or of the process's memory limit where lower (a container's, "
    "ulimit -v); for the CPU reference's arrays, the memory available";
std::string join(const std::vector<std::string>& items, const std::string& separator = ", ");
// An error's text as one line, the CLI's rule: its lines (an OpenCL build log's) joined by " | ",
// blank ones dropped, at most 4000 characters.
std::string one_line(const std::string& text);
// A command-line parse error as one line: CLI11's message, or "unknown sub-command" (or option)
// for a word it took for one, an unknown option of a sub-command with the one it was likely meant
// to be, and where to read the options.
std::string parse_error_text(const CLI::App& app, const CLI::ParseError& error, int argc,
                             char** argv);
// Option validators: a whole number in [least, most] (CLI11 takes "-1" for the largest unsigned),
// a finite number (its ranges let NaN through).
CLI::Validator whole_number_in(double least, double most);
// Whole-number validators rewrite their text and go in transform(), not check(): CLI11 converts
// with base 0 ("010" is 8). A canvas resolution:
extern const CLI::Validator resolution_value;
// Seed counts up to the OpenCL engine's most.
inline CLI::Validator seed_count(double least) {
  return whole_number_in(least, static_cast<double>(kMostOpenCLSeeds));
}
// --rng-seed: a whole number that fits in 64 bits, checked on its digits (2^64 - 1 is no double:
// a comparison in double let 2^64 and above through, saturated to 2^64 - 1).
extern const CLI::Validator rng_seed_value;
// A file or directory name that is not empty ("--seeds $UNSET" would otherwise mean "none").
extern const CLI::Validator non_empty_path;

// The help of --domain and --metric, the same for `voronoi` and `bench`.
std::string domain_help();
std::string metric_help();

// --device, whose default is $RVOR_DEVICE or auto. `what_cpu_is` says what "cpu" means there.
CLI::Option* add_device_option(CLI::App* command, std::string& device,
                               const std::string& what_cpu_is);
// Checks the chosen device before any work (rvor::require_device); a device that came from
// $RVOR_DEVICE rather than from --device says so.
void require_chosen_device(const CLI::Option* option, const std::string& device);

// What a run noticed about its inputs and its solve, for the summary's warnings.
struct RunNotes {
  // The OpenCL engine's voxel updates per active voxel (0 on the CPU reference): many more than a
  // few dozen come from strongly anisotropic stencils with few seeds, where the reference, which
  // orders its updates by value, can be far faster (docs: README, "How accurate, how fast").
  double opencl_updates_per_voxel = 0;
  std::size_t far_probes = 0;  // probes more than a voxel from the voxel that answers them
  // Active voxels beyond the --metric-mesh's bounding box by more than half a voxel: they take the
  // metric of its nearest element.
  std::size_t voxels_outside_metric_mesh = 0;
};

void print_voronoi_summary(std::ostream& out, const std::string& out_dir,
                           const std::vector<std::string>& outputs, std::size_t active_voxels,
                           std::size_t seeds, const FieldSummary& summary, const MetricReach& reach,
                           const RunNotes& notes, double propagation_seconds, double total_seconds);

}  // namespace rvor::cli
