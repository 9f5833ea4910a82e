#include "terminal.h"

#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdlib>
#include <iomanip>
#include <iostream>
#include <optional>
#include <sstream>

#include "interrupt_cleanup.h"
#include "rvor/canvas_builder.h"
#include "rvor/devices.h"
#include "rvor/error.h"
#include "rvor/metric_field.h"
#include "rvor/spec_text.h"

namespace rvor::cli {

Progress::Progress(bool quiet) : quiet_(quiet), terminal_(isatty(STDERR_FILENO) == 1) {}

Progress::~Progress() {
  set_progress_line_open(false);
  if (!open_ || quiet_) return;
  restart_line();
  std::cerr << " failed\n";
}

void Progress::begin(const std::string& stage) {
  start_ = last_update_ = std::chrono::steady_clock::now();
  open_ = true;
  updated_ = false;
  stage_ = stage;
  if (!quiet_) std::cerr << stage << " ..." << std::flush;
  set_progress_line_open(!quiet_);
}

void Progress::update(const std::string& status, bool now) {
  if (quiet_ || !open_ || !terminal_) return;
  const auto time = std::chrono::steady_clock::now();
  if (!now && time - last_update_ < std::chrono::milliseconds(500)) return;
  last_update_ = time;
  updated_ = true;
  std::cerr << "\r" << stage_ << " ... " << status << "\x1b[K" << std::flush;  // clear to the end
}

void Progress::restart_line() {
  if (updated_) std::cerr << "\r" << stage_ << " ...\x1b[K";
  updated_ = false;
}

double Progress::end(const std::string& detail) {
  open_ = false;
  set_progress_line_open(false);
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  if (!quiet_) {
    restart_line();
    std::cerr << " done in " << std::fixed << std::setprecision(2) << seconds << " s";
    if (!detail.empty()) std::cerr << " (" << detail << ")";
    std::cerr << std::defaultfloat << "\n";
  }
  return seconds;
}

void Progress::note(const std::string& line) {
  const bool reopen = open_ && !quiet_;
  if (reopen) {
    restart_line();
    std::cerr << "\n";
  }
  std::cerr << line << "\n";
  if (reopen) std::cerr << stage_ << " ..." << std::flush;
}

std::string fifo_wait_text(const std::string& what, const std::string& path) {
  return "rvor: waiting for " + what + " " + printable_text(path) +
         ", a FIFO that nothing has written to yet";
}

void print_fifo_wait(const std::string& what, const std::string& path) {
  std::cerr << fifo_wait_text(what, path) << "\n";
}

std::uint64_t parse_byte_size(const std::string& text) {
  // Binary multiples, in either case: 8G and 8g are 8 GiB.
  static const std::string suffixes = "KMGT";
  const std::size_t suffix =
      text.empty()
          ? std::string::npos
          : suffixes.find(static_cast<char>(std::toupper(static_cast<unsigned char>(text.back()))));
  const std::optional<double> value =
      parse_decimal(suffix == std::string::npos ? text : text.substr(0, text.size() - 1));
  const double factor =
      suffix == std::string::npos ? 1.0 : std::pow(1024.0, static_cast<double>(suffix + 1));
  // At least one byte: a budget that rounds to 0 would mean "the default".
  if (!value || !(*value * factor >= 1))
    throw Error("memory budget " + quoted_text(text) +
                " is not a positive size like 512M, 8G or 1000000");
  // Below 2^64 once rounded to a double, so that the conversion to bytes is defined.
  constexpr double kMostBytes = 1.8e19;
  if (!(*value * factor <= kMostBytes))
    throw Error("memory budget " + quoted_text(text) +
                " is beyond the largest size rvor can represent (1.8e19 bytes, about 15.6 EiB)");
  return static_cast<std::uint64_t>(*value * factor);
}

namespace {

// Edits (insertions, deletions, substitutions) that turn `a` into `b`.
std::size_t edit_distance(const std::string& a, const std::string& b) {
  std::vector<std::size_t> row(b.size() + 1);
  for (std::size_t j = 0; j <= b.size(); ++j) row[j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i) {
    std::size_t diagonal = row[0];
    row[0] = i;
    for (std::size_t j = 1; j <= b.size(); ++j) {
      const std::size_t above = row[j];
      row[j] = std::min({row[j] + 1, row[j - 1] + 1, diagonal + (a[i - 1] == b[j - 1] ? 0 : 1)});
      diagonal = above;
    }
  }
  return row[b.size()];
}

// The option of `command` that `word` (an unknown "--name" or "--name=value") was most likely
// meant to be: a typo (a letter or two off, "--rng-seeds") or a longer or shorter name that holds
// it ("--output" for --out, "--random-seeds" for bench's --seeds); "" where none is near.
std::string nearest_option(const CLI::App& command, const std::string& word) {
  const std::string typed = word.substr(0, word.find('='));
  const std::size_t start = typed.find_first_not_of('-');
  if (start == std::string::npos) return "";  // dashes only
  const std::string bare = typed.substr(start);
  std::string best;
  std::size_t best_distance = std::string::npos;
  for (const CLI::Option* option : command.get_options())
    for (const std::string& name : option->get_lnames()) {
      const std::size_t distance = edit_distance(bare, name);
      // Up to two edits, fewer for short names, whose every neighbour is a few edits away.
      const bool typo =
          distance <= std::min<std::size_t>(2, std::max<std::size_t>(1, bare.size() / 3));
      const bool holds =
          std::min(bare.size(), name.size()) >= 3 &&
          (bare.find(name) != std::string::npos || name.find(bare) != std::string::npos);
      if ((typo || holds) && distance < best_distance) {
        best = "--" + name;
        best_distance = distance;
      }
    }
  return best;
}

// A word on the command line that CLI11 did not take is an option where it starts with '-' and is
// no number ("-1" is a coordinate split off a spec by a blank).
bool looks_like_option(const std::string& word) {
  return word.size() > 1 && word[0] == '-' && !parse_decimal(word);
}

// Whether `word` stands on the command line before the sub-command's name. CLI11 gives the words
// after "--" to the main command as well, so that its remaining() does not tell.
bool typed_before(const std::string& word, const CLI::App& command, int argc, char** argv) {
  for (int n = 1; n < argc; ++n) {
    if (argv[n] == command.get_name()) return false;
    if (argv[n] == word) return true;
  }
  return false;
}

// An ExtrasError's text: an unknown option, named with the option it was likely meant to be, or
// the words no option took, in the order they were typed (CLI11's message lists them backwards).
std::string extras_text(const CLI::App& app, const CLI::App& command, int argc, char** argv) {
  std::vector<std::string> left = app.remaining();  // before the sub-command's name, or after --
  for (const std::string& word : command.remaining()) left.push_back(word);
  for (const std::string& word : left) {
    if (!looks_like_option(word)) continue;
    const std::string meant = nearest_option(command, word);
    if (meant == word.substr(0, word.find('='))) {
      if (typed_before(word, command, argc, argv))
        return "option '" + meant + "' comes before the sub-command: write it after `rvor " +
               command.get_name() + "`";
      continue;  // after "--", which makes every later word a value: nothing was mistyped
    }
    return "unknown option '" + word + "' for `rvor " + command.get_name() + "`" +
           (meant.empty() ? "" : " (did you mean " + meant + "?)");
  }
  return "unexpected argument" + std::string(left.size() > 1 ? "s" : "") + " '" + join(left, " ") +
         "': each option takes one value (quote a value that holds blanks)";
}

// CLI11's "--metric: At Most 1 required but received 2" for an option given twice, in plain
// words; any other text as it is.
std::string repeated_option_text(const std::string& text) {
  const std::string marker = ": At Most 1 required but received ";
  const std::size_t at = text.find(marker);
  if (at == std::string::npos) return text;
  return text.substr(0, at) + " is given " + text.substr(at + marker.size()) +
         " times: give it once";
}

}  // namespace

std::string parse_error_text(const CLI::App& app, const CLI::ParseError& error, int argc,
                             char** argv) {
  const std::vector<CLI::App*> chosen = app.get_subcommands();
  if (chosen.empty() && argc > 1) {
    std::vector<std::string> names;
    for (const CLI::App* sub : app.get_subcommands({})) names.push_back(sub->get_name());
    // CLI11 reports "A subcommand is required" before an option it does not know.
    if (argv[1][0] == '-')
      return "unknown option '" + std::string(argv[1]) + "': options follow a sub-command (" +
             join(names) + "; see `rvor --help`)";
    return "unknown sub-command '" + std::string(argv[1]) + "' (one of " + join(names) + ")";
  }
  // CLI11 names an ExtrasError after the command, not its kind: told apart by its type.
  std::string text = dynamic_cast<const CLI::ExtrasError*>(&error) && !chosen.empty()
                         ? extras_text(app, *chosen[0], argc, argv)
                         : repeated_option_text(one_line(error.what()));
  if (text.size() > 200) text = text.substr(0, 200) + "...";
  const std::string help =
      chosen.empty() ? "rvor --help" : "rvor " + chosen[0]->get_name() + " --help";
  return text + " (see `" + help + "`)";
}

CLI::Validator whole_number_in(double least, double most) {
  return CLI::Validator(
      [=](std::string& text) -> std::string {
        const std::optional<double> value = parse_decimal(text);
        if (!value || !(*value >= least) || *value > most || std::floor(*value) != *value)
          return "'" + text.substr(0, 40) + "' is not a whole number from " +
                 std::to_string(static_cast<long long>(least)) + " to " +
                 std::to_string(static_cast<long long>(most));
        // Handed on in plain decimal: CLI11 converts with base 0, so "010" would be octal 8.
        text = std::to_string(static_cast<long long>(*value));
        return "";
      },
      "COUNT");
}

const CLI::Validator resolution_value =
    whole_number_in(kLeastCanvasResolution, kMostCanvasResolution);

const CLI::Validator rng_seed_value(
    [](std::string& text) -> std::string {
      std::uint64_t value = 0;
      const char* end = text.data() + text.size();
      const auto [last, error] = std::from_chars(text.data(), end, value);
      if (text.empty() || error != std::errc() || last != end)
        return "'" + text.substr(0, 40) + "' is not a whole number from 0 to 2^64 - 1";
      text = std::to_string(value);  // plain decimal: CLI11 would read "010" as octal
      return "";
    },
    "SEED");

const CLI::Validator byte_size(
    [](std::string& text) -> std::string {
      try {
        text = std::to_string(parse_byte_size(text));  // plain bytes for the option's integer
        return "";
      } catch (const Error& error) {
        return error.what();
      }
    },
    "SIZE");

const CLI::Validator non_empty_path(
    [](const std::string& text) -> std::string {
      return text.empty() ? "an empty path (an unset variable?)" : "";
    },
    "PATH");

std::string one_line(const std::string& text) {
  constexpr std::size_t kMostCharacters = 4000;
  std::vector<std::string> lines;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) {
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (line.find_first_not_of(" \t") != std::string::npos) lines.push_back(line);
  }
  std::string joined = join(lines, " | ");
  if (joined.size() > kMostCharacters) joined = joined.substr(0, kMostCharacters) + " ...";
  return joined;
}

std::string join(const std::vector<std::string>& items, const std::string& separator) {
  std::string joined;
  for (const std::string& item : items) joined += (joined.empty() ? "" : separator) + item;
  return joined;
}

std::string domain_help() {
  return "box:X0,Y0,Z0,X1,Y1,Z1 | rect:X0,Y0,X1,Y1 | mesh:FILE (.off/.obj/.stl: closed surfaces "
         "that neither cross nor touch each other or themselves and have no zero-area "
         "triangles; one inside another bounds a cavity; a binary STL's size must be 84 + 50 "
         "bytes per facet of its count) | implicit:NAME[:k=v,...]: sphere "
         "(center=X,Y,Z, r=1), ellipsoid (center, a=1, b=0.75, c=0.5), torus (center, R=1, "
         "r=0.25; always about the z axis, which no parameter turns), disk (2D: center=X,Y, r=1); "
         "centres default to the origin";
}

std::string metric_help() {
  return "NAME[:key=value,...], NAME one of: " + join(analytic_metric_names()) +
         "; every field takes scale=S (every distance times S, the tensors times S²); "
         "uniform:m11,m12,m22 (2D) or "
         "uniform:m11,m12,m22,m13,m23,m33 (3D); swirl, starred and unidimensional_shock are 2D "
         "fields, radial_shock_3d is 3D, the others both";
}

CLI::Option* add_device_option(CLI::App* command, std::string& device,
                               const std::string& what_cpu_is) {
  return command
      ->add_option("--device", device,
                   "Where to propagate: auto (first OpenCL GPU, else OpenCL CPU device), pocl, "
                   "opencl, opencl:N (see `rvor devices`), or cpu (" +
                       what_cpu_is + "); default $RVOR_DEVICE or auto")
      ->capture_default_str();
}

void require_chosen_device(const CLI::Option* option, const std::string& device) {
  if (option->count() > 0)
    require_device(device);
  else
    with_default_device([](const std::string& name) { require_device(name); });
  keep_reporting_aborts();  // OpenCL, started by the look-up, has put LLVM's SIGABRT handler in
}

// Beyond this many updates per voxel the summary suggests the reference: the standard cases make
// 2 to 15, and 2D anisotropy 50 at 0.3 rad with 10 seeds made 138 at 512² in 3.0 s, where the
// reference took 0.1 s (2026-12-05).
constexpr double kManyUpdatesPerVoxel = 50;

void print_voronoi_summary(std::ostream& out, const std::string& out_dir,
                           const std::vector<std::string>& outputs, std::size_t active_voxels,
                           std::size_t seeds, const FieldSummary& summary, const MetricReach& reach,
                           const RunNotes& notes, double propagation_seconds,
                           double total_seconds) {
  out << "rvor voronoi: " << active_voxels << " voxels, " << seeds << " seeds, "
      << summary.non_empty_cells << " non-empty cells (" << summary.smallest_cell << " to "
      << summary.largest_cell << " voxels each)\n";
  out << "  farthest voxel from its seed: " << summary.max_distance
      << " (metric units); mean distance " << summary.mean_distance << "\n";
  if (summary.empty_cells > 0)
    out << "  warning: " << summary.empty_cells << " seed" << (summary.empty_cells > 1 ? "s" : "")
        << " (seed " << summary.first_empty_cell << " first) own no voxel: each shares its voxel "
        << "with another seed, or lies nearer to one than the resolution separates\n";
  if (beyond_validated_anisotropy(reach))
    out << "  warning: the metric's anisotropy reaches " << reach.max_anisotropy
        << " with stencils " << reach.longest_offset << " voxels long, beyond the anisotropy "
        << kValidatedAnisotropy
        << " up to which the tests validate the scheme at any angle: expect distances off by "
           "percents, more where the stencils reach across the canvas\n";
  if (notes.far_probes > 0)
    out << "  warning: " << notes.far_probes << " probe"
        << (notes.far_probes > 1 ? "s lie" : " lies")
        << " more than a voxel from the canvas: probe.csv gives the nearest active voxel's "
           "values (and its centre)\n";
  if (notes.opencl_updates_per_voxel > kManyUpdatesPerVoxel)
    out << "  note: the OpenCL solve made " << std::fixed << std::setprecision(0)
        << notes.opencl_updates_per_voxel << std::defaultfloat
        << " updates per voxel: with strongly anisotropic stencils and few seeds its brick "
           "schedule revisits voxels many times, and the sequential reference (--device cpu) can "
           "be many times faster\n";
  if (notes.voxels_outside_metric_mesh > 0)
    out << "  warning: " << notes.voxels_outside_metric_mesh << " of " << active_voxels
        << " voxels lie outside the bounding box of the --metric-mesh: they take the metric of "
           "its nearest element\n";
  const std::size_t seedless = summary.unreached_voxels - summary.unreached_beside_reached;
  if (seedless > 0)
    out << "  warning: " << seedless
        << " voxels were reached by no seed: they lie in pieces of the canvas without seeds\n";
  if (summary.unreached_beside_reached > 0)
    out << "  warning: " << summary.unreached_beside_reached
        << " voxels were reached by no seed although they adjoin reached ones: none of their "
           "stencils (up to "
        << reach.longest_offset
        << " voxels long) leads to a reached voxel, where the stencils are long against how fast "
           "the metric turns (raise --resolution) or at corners of the canvas that a rotated "
           "stencil reaches only from outside\n";
  const double rate = propagation_seconds > 0 ? active_voxels / propagation_seconds : 0.0;
  const bool millions = rate >= 1e6;  // small canvases: thousands, not "0.0 M"
  out << "  propagation " << std::fixed << std::setprecision(2) << propagation_seconds << " s ("
      << std::setprecision(1) << rate / (millions ? 1e6 : 1e3) << (millions ? " M" : " k")
      << " voxels/s), total " << std::setprecision(2) << total_seconds << " s\n"
      << std::defaultfloat;
  out << "  outputs in " << printable_text(out_dir) << "/: " << join(outputs) << "\n";
}

}  // namespace rvor::cli
