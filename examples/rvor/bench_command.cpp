// rvor bench: propagation throughput with OpenVDB FastSweeping and the CPU reference measured in
// the same run on the same canvas and seeds (rvor/benchmark.h); a table, or JSON with --json.
#include <algorithm>
#include <cstdio>
#include <iostream>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "commands.h"
#include "rvor/benchmark.h"
#include "rvor/devices.h"
#include "rvor/domain.h"
#include "rvor/error.h"
#include "rvor/metric_field.h"
#include "rvor/opencl_propagator.h"
#include "rvor/spec_text.h"
#include "terminal.h"

namespace rvor::cli {

namespace {

// Sweeps or phase iterations per relaxation (kMostVisitsPerRelaxation bounds both).
const CLI::Validator visit_count = whole_number_in(1, kMostVisitsPerRelaxation);

struct BenchOptions {
  std::optional<std::string> domain, metric;
  std::optional<int> resolution;
  std::optional<std::size_t> seeds;
  std::uint64_t rng_seed = 1;
  std::string device = default_device_name();  // $RVOR_DEVICE, else auto
  RelaxationVariant variant = RelaxationVariant::automatic;
  std::optional<double> front_step;
  std::optional<int> phase_iterations, insertion_phase_iterations, max_sweeps;
  int repetitions = 2;  // the first solve may include compiling the kernels
  std::size_t inserted_seeds = 0;
  std::size_t insert_batch = 1;
  bool checked_insert = false;
  std::uint64_t memory_budget = 0;  // bytes (byte_size); 0: the default
  bool no_exact_start = false;
  bool no_reference = false;
  bool no_fastsweeping = false;
  bool json = false;
  bool quiet = false;
};

// --front-step: 0 (off) or a step the engine takes (OpenCLOptions::front_step, at least
// kSmallestFrontStep). NaN and infinities fail the comparisons too.
const CLI::Validator front_step_range(
    [](const std::string& text) -> std::string {
      const std::optional<double> value = parse_decimal(text);
      if (value && (*value == 0.0 || (*value >= kSmallestFrontStep && *value <= 1000.0))) return "";
      char smallest[32];
      std::snprintf(smallest, sizeof smallest, "%g", kSmallestFrontStep);
      return "'" + text.substr(0, 40) + "' is not 0 (off) or a step from " + smallest + " to 1000";
    },
    "K");

// The field for the default domain: in 3D where it has a 3D form, else in 2D.
std::unique_ptr<MetricField> field_for_default_domain(const std::string& metric) {
  try {
    return make_analytic_metric(metric, 3);
  } catch (const Error& error_in_3d) {
    try {
      return make_analytic_metric(metric, 2);
    } catch (const Error&) {
      throw error_in_3d;
    }
  }
}

// Without --domain the metric's own domain (radial_shock_3d: [1,11]^3, swirl: [-1,1]^2), else
// [-1,1]^3, or [-1,1]^2 for a field with a 2D form only.
std::string domain_for(const std::string& metric) {
  const std::unique_ptr<MetricField> field = field_for_default_domain(metric);
  const Box box = field->natural_domain().value_or(Box{Vec3(-1, -1, -1), Vec3(1, 1, 1)});
  DomainSpec domain;  // its description() writes the numbers as parse_domain reads them back
  domain.kind = field->dimension() == 2 ? DomainSpec::Kind::Rectangle : DomainSpec::Kind::Box;
  domain.bounds = box;
  return domain.description();
}

// --variant's names, which the errors below use too.
const std::map<std::string, RelaxationVariant> kVariantNames = {
    {"auto", RelaxationVariant::automatic},
    {"brick_sweep", RelaxationVariant::brick_sweep},
    {"brick_lanes", RelaxationVariant::brick_lanes},
    {"voxel_phases", RelaxationVariant::voxel_phases}};

std::string variant_name(RelaxationVariant variant) {
  for (const auto& [name, named] : kVariantNames)
    if (named == variant) return name;
  return "auto";
}

// --variant: one of kVariantNames, handed on as the enum's number (CLI11's CheckedTransformer
// would take the numbers too, and print its mapping in --help).
const CLI::Validator variant_from_name(
    [](std::string& text) -> std::string {
      const auto named = kVariantNames.find(text);
      if (named == kVariantNames.end()) {
        std::vector<std::string> names;
        for (const auto& [name, variant] : kVariantNames) names.push_back(name);
        return "'" + text + "' is not a variant (" + join(names) + ")";
      }
      text = std::to_string(static_cast<int>(named->second));
      return {};
    },
    "");

// Front stepping is a brick_lanes schedule, sweeps the brick variants', phase iterations
// voxel_phases': an explicit other variant would ignore them, and the reference (--device cpu)
// ignores all five.
void check_variant_options(const BenchOptions& o) {
  if (o.device == "cpu")
    for (const auto& [option, given] :
         {std::pair{"--variant", o.variant != RelaxationVariant::automatic},
          std::pair{"--front-step", o.front_step.has_value()},
          std::pair{"--max-sweeps", o.max_sweeps.has_value()},
          std::pair{"--phase-iterations", o.phase_iterations.has_value()},
          std::pair{"--insertion-phase-iterations", o.insertion_phase_iterations.has_value()}})
      if (given)
        throw Error(std::string(option) +
                    " applies to the OpenCL engine only, not to --device cpu (the reference)");
  const bool sweeps = o.variant == RelaxationVariant::brick_sweep;
  const bool phases = o.variant == RelaxationVariant::voxel_phases;
  auto refuse = [&](const std::string& option, const std::string& applies_to) {
    throw Error(option + " applies to " + applies_to + " only, not to --variant " +
                variant_name(o.variant));
  };
  if (o.front_step && *o.front_step > 0 && (sweeps || phases))
    refuse("--front-step", "brick_lanes solves");
  if (o.max_sweeps && phases) refuse("--max-sweeps", "brick_sweep and brick_lanes");
  const bool other = sweeps || o.variant == RelaxationVariant::brick_lanes;
  if (o.phase_iterations && other) refuse("--phase-iterations", "voxel_phases");
  if (o.insertion_phase_iterations && other) refuse("--insertion-phase-iterations", "voxel_phases");
}

std::vector<BenchCase> chosen_cases(const BenchOptions& o) {
  check_variant_options(o);
  if ((o.domain && o.domain->empty()) || (o.metric && o.metric->empty()))
    throw Error(std::string(o.domain && o.domain->empty() ? "--domain" : "--metric") + " is empty");
  std::vector<BenchCase> cases;
  if (!o.domain && !o.metric) {
    cases = standard_bench_cases();
  } else {
    BenchCase custom;
    custom.metric = o.metric.value_or(custom.metric);
    custom.domain = o.domain ? *o.domain : domain_for(custom.metric);
    cases.push_back(custom);
  }
  for (BenchCase& c : cases) {
    if (o.resolution) c.resolution = *o.resolution;
    if (o.seeds) c.seeds = *o.seeds;
    c.rng_seed = o.rng_seed;
    c.device = o.device;
    c.variant = o.variant;
    if (o.front_step) c.front_step = *o.front_step;
    if (o.max_sweeps) c.max_sweeps = *o.max_sweeps;
    if (o.phase_iterations) c.phase_iterations = *o.phase_iterations;
    if (o.insertion_phase_iterations) c.insertion_phase_iterations = *o.insertion_phase_iterations;
    c.repetitions = o.repetitions;
    c.inserted_seeds = o.inserted_seeds;
    c.insert_batch = o.insert_batch;
    c.checked_insert = o.checked_insert;
    c.exact_start = !o.no_exact_start;
    c.reference = !o.no_reference;
    c.fastsweeping = !o.no_fastsweeping;
    c.memory_budget = o.memory_budget;
  }
  return cases;
}

// 12345678 -> "12.3M": rates and counts stay readable in a narrow column.
std::string short_number(double value) {
  const char* suffixes[] = {"", "k", "M", "G", "T"};
  int power = 0;
  while (value >= 1000.0 && power < 4) {
    value /= 1000.0;
    ++power;
  }
  char text[32];
  std::snprintf(text, sizeof text, value < 100 ? "%.3g%s" : "%.0f%s", value, suffixes[power]);
  return text;
}

std::string fixed(double value, int digits) {
  char text[32];
  std::snprintf(text, sizeof text, "%.*f", digits, value);
  return text;
}

std::string optional_rate(const std::optional<double>& rate) {
  return rate ? short_number(*rate) : "-";
}

std::string optional_ratio(const std::optional<double>& ratio) {
  return ratio ? fixed(*ratio, 2) + "x" : "-";
}

std::string optional_percent(const std::optional<double>& fraction) {
  return fraction ? fixed(100.0 * *fraction, 2) + "%" : "-";
}

std::string case_name(const BenchResult& r) {
  return r.bench_case.metric + "@" + std::to_string(r.bench_case.resolution);
}

void print_table(std::ostream& out, const std::vector<BenchResult>& results) {
  const std::vector<std::string> header = {"case",     "voxels",    "seeds",   "seconds",
                                           "voxels/s", "upd/voxel", "B/voxel", "FS vox/s",
                                           "vs FS",    "ref vox/s", "vs ref",  "insert"};
  std::vector<std::size_t> widths = {24, 9, 6, 8, 9, 9, 8, 9, 7, 9, 7, 7};
  for (const BenchResult& r : results) widths[0] = std::max(widths[0], case_name(r).size());
  auto row = [&](const std::vector<std::string>& cells) {
    for (std::size_t n = 0; n < cells.size(); ++n) {
      const std::string& cell = cells[n];
      const std::size_t width = widths[n];
      const std::string pad(cell.size() < width ? width - cell.size() : 0, ' ');
      out << (n == 0 ? cell + pad : "  " + pad + cell);
    }
    out << "\n";
  };
  row(header);
  for (const BenchResult& r : results)
    row({case_name(r), short_number(double(r.active_voxels)), std::to_string(r.bench_case.seeds),
         fixed(r.seconds, 3), short_number(r.voxels_per_second), fixed(r.updates_per_voxel, 2),
         fixed(r.bytes_per_voxel, 1), optional_rate(r.fastsweeping_voxels_per_second),
         optional_ratio(r.fastsweeping_ratio), optional_rate(r.cpu_reference_voxels_per_second),
         optional_ratio(r.reference_ratio), optional_percent(r.insert_fraction)});
  for (const BenchResult& r : results)
    out << case_name(r) << ": " << r.device_description << "; " << r.metric_description << " on "
        << r.domain_description << ", max anisotropy " << fixed(r.max_anisotropy, 1) << "\n";
}

template <typename T>
nlohmann::json or_null(const std::optional<T>& value) {
  return value ? nlohmann::json(*value) : nlohmann::json(nullptr);
}

// Texts as printable_text writes them: JSON strings are UTF-8, and nlohmann throws on other bytes
// (a mesh named in Latin-1, mesh:tw\xFFo.off, failed --json after the benchmark had run).
nlohmann::json case_json(const BenchResult& r) {
  return {{"domain", printable_text(r.bench_case.domain)},
          {"metric", printable_text(r.bench_case.metric)},
          {"metric_description", printable_text(r.metric_description)},
          {"resolution", r.bench_case.resolution},
          {"seeds", r.bench_case.seeds},
          {"rng_seed", r.bench_case.rng_seed},
          {"device", printable_text(r.bench_case.device)},
          {"device_description", printable_text(r.device_description)},
          {"active_voxels", r.active_voxels},
          {"max_anisotropy", r.max_anisotropy},
          {"seconds", r.seconds},
          {"iterations", r.iterations},
          {"voxel_updates", r.voxel_updates},
          {"voxels_per_second", r.voxels_per_second},
          {"updates_per_voxel", r.updates_per_voxel},
          {"relaxations_per_brick", r.relaxations_per_brick},
          {"visits_per_relaxation", r.visits_per_relaxation},
          {"exact_start", r.exact_start},
          {"device_bytes", r.device_bytes},
          {"bytes_per_voxel", r.bytes_per_voxel},
          {"inserted_seeds", r.bench_case.inserted_seeds},
          {"insert_batch", r.bench_case.insert_batch},
          {"insertions", r.insertions},
          {"checked_insert", r.bench_case.checked_insert},
          {"variant", variant_name(r.bench_case.variant)},  // as asked; device_description: ran
          {"front_step", r.bench_case.front_step < 0 ? nlohmann::json(nullptr)  // automatic
                                                     : nlohmann::json(r.bench_case.front_step)},
          {"repeat", r.bench_case.repetitions},
          {"max_sweeps", r.bench_case.max_sweeps == 0 ? nlohmann::json(nullptr)  // automatic
                                                      : nlohmann::json(r.bench_case.max_sweeps)},
          {"phase_iterations", r.bench_case.phase_iterations},
          {"insertion_phase_iterations", r.bench_case.insertion_phase_iterations},
          {"insert_mean_seconds", or_null(r.insert_mean_seconds)},
          {"insert_max_seconds", or_null(r.insert_max_seconds)},
          {"insert_mean_round_seconds", or_null(r.insert_mean_round_seconds)},
          {"insert_mean_rounds", or_null(r.insert_mean_rounds)},
          {"insert_exact_start", or_null(r.insert_exact_start)},
          {"insert_fraction", or_null(r.insert_fraction)},
          {"fastsweeping_seconds", or_null(r.fastsweeping_seconds)},
          {"fastsweeping_init_seconds", or_null(r.fastsweeping_init_seconds)},
          {"fastsweeping_voxels_per_second", or_null(r.fastsweeping_voxels_per_second)},
          {"fastsweeping_ratio", or_null(r.fastsweeping_ratio)},
          {"fastsweeping_label_agreement", or_null(r.fastsweeping_label_agreement)},
          {"cpu_reference_seconds", or_null(r.reference_seconds)},
          {"cpu_reference_voxels_per_second", or_null(r.cpu_reference_voxels_per_second)},
          {"cpu_reference_ratio", or_null(r.reference_ratio)},
          {"cpu_reference_max_relative_difference", or_null(r.reference_max_relative_difference)},
          {"cpu_reference_label_mismatches", or_null(r.reference_label_mismatches)}};
}

void run_bench(const BenchOptions& o) {
  std::vector<BenchResult> results;
  for (const BenchCase& c : chosen_cases(o)) {
    if (!o.quiet) std::cerr << "bench " << c.metric << " on " << c.domain << " ...\n";
    results.push_back(run_benchmark_case(c, [&](const std::string& line) {
      if (!o.quiet) std::cerr << "  " << line << "\n";
    }));
  }
  if (!o.json) return print_table(std::cout, results);
  nlohmann::json report = {{"generator", "rvor bench"}, {"cases", nlohmann::json::array()}};
  for (const BenchResult& r : results) report["cases"].push_back(case_json(r));
  std::cout << report.dump(2) << "\n";
}

}  // namespace

void add_bench_command(CLI::App& app) {
  auto options = std::make_shared<BenchOptions>();
  CLI::App* cmd = app.add_subcommand(
      "bench",
      "Measure propagation throughput (converged voxels per second) next to OpenVDB FastSweeping "
      "and the CPU reference on the same canvas and seeds");
  cmd->footer(
      "Without --domain/--metric the standard cases run: euclidean on box:-1,-1,-1,1,1,1 and\n"
      "radial_shock_3d on box:1,1,1,11,11,11, 256^3, 1000 seeds (rng seed 1).\n"
      "Examples:\n"
      "  rvor bench --resolution 128 --no-reference --insert 3\n"
      "  rvor bench --metric swirl --domain rect:-1,-1,1,1 --resolution 96 --json");
  cmd->add_option("--domain", options->domain,
                  domain_help() +
                      " (default: the metric's domain, else box:-1,-1,-1,1,1,1, or "
                      "rect:-1,-1,1,1 for a 2D field)");
  cmd->add_option("--metric", options->metric,
                  metric_help() + " (default: euclidean when --domain is given)");
  cmd->add_option("--resolution", options->resolution,
                  "Voxels along the longest side of the domain (2 to 65536; default 256)")
      ->transform(resolution_value);
  cmd->add_option("--seeds", options->seeds, "Number of random seeds (default 1000)")
      ->transform(seed_count(1));
  cmd->add_option("--rng-seed", options->rng_seed, "Random generator seed")
      ->transform(rng_seed_value)
      ->capture_default_str();
  const CLI::Option* device = add_device_option(cmd, options->device, "the reference itself");
  cmd->add_option("--variant", options->variant,
                  "OpenCL relaxation: auto (brick_lanes on CPUs, voxel_phases on GPUs) | "
                  "brick_lanes (brick_sweep on 8 bricks per work-item, in SIMD lanes) | "
                  "brick_sweep | voxel_phases")
      ->transform(variant_from_name)
      ->type_name("NAME");
  cmd->add_option("--front-step", options->front_step,
                  "brick_lanes solves: front stepping, in voxel lengths K (values above a "
                  "threshold stay tentative; once per colour cycle it moves K past the least "
                  "tentative value), 0.25 to 1000; 0: off; default automatic: 3 for non-axis "
                  "stencils and Voronoi cells at least 50 voxels across, else off")
      ->check(front_step_range);
  cmd->add_option("--max-sweeps", options->max_sweeps,
                  "brick_lanes and brick_sweep: most sweeps per brick relaxation, 1 to 64 (default "
                  "automatic: 4 for a uniform metric with axis offsets, 2 for any other stencil; "
                  "visits_per_relaxation in --json gives what ran)")
      ->transform(visit_count);
  cmd->add_option("--phase-iterations", options->phase_iterations,
                  "voxel_phases (an explicit --variant, or auto on a GPU): most iterations per "
                  "round of a solve, 1 to 64 (default " +
                      std::to_string(OpenCLOptions{}.phase_iterations) + ")")
      ->transform(visit_count);
  cmd->add_option("--insertion-phase-iterations", options->insertion_phase_iterations,
                  "voxel_phases: most iterations per round of an insertion, 1 to 64 (default " +
                      std::to_string(OpenCLOptions{}.insertion_phase_iterations) + ")")
      ->transform(visit_count);
  cmd->add_option("--repeat", options->repetitions,
                  "Solves per case with the same engine, and runs of FastSweeping, 1 to 100; the "
                  "fastest of each counts (the engine's first solve also "
                  "uploads the canvas, and compiles the kernels where PoCL's cache lacks them: "
                  "seconds at small sizes; with --insert and 2 or more, an untimed insertion "
                  "follows it, so that the timed ones find their kernels built)")
      ->transform(whole_number_in(1, 100))
      ->capture_default_str();
  CLI::Option* insert =
      cmd->add_option(
             "--insert", options->inserted_seeds,
             "Then insert N more seeds into the solved canvas, one at a time (or "
             "--insert-batch at a time), as a chain of insertions does (a VoronoiSession, "
             "which keeps the field with the engine); the table's `insert` column is the mean "
             "insert time as a percentage of the solve")
          ->transform(seed_count(0))
          ->capture_default_str();
  cmd->add_option("--insert-batch", options->insert_batch,
                  "Seeds per insertion of --insert (the last may take fewer); the `insert` "
                  "column is then the mean time of one such insertion")
      ->transform(seed_count(1))
      ->capture_default_str()
      ->needs(insert);
  cmd->add_flag("--checked-insert", options->checked_insert,
                "Time --insert through Propagator::insert into a copy of the solved field instead: "
                "a caller's field, which every insertion reads whole to check (beside its rounds)")
      ->needs(insert);
  cmd->add_flag("--no-exact-start", options->no_exact_start,
                "Solve a uniform diagonal metric (the isotropic one among them) from +inf, as "
                "any other metric, instead of from each voxel's nearest seed's exact distance "
                "(every voxel of a convex domain in one face-connected piece; elsewhere those "
                "whose 4^3 block, 4^2 in 2D, sees the seed through active voxels; both "
                "engines), and insert without lowering voxels to a new seed's exact distance "
                "first (the OpenCL engine)");
  cmd->add_flag("--no-reference", options->no_reference, "Skip the CPU reference (slow at 256^3)");
  cmd->add_flag("--no-fastsweeping", options->no_fastsweeping,
                "Skip OpenVDB FastSweeping (it runs on 3D canvases only)");
  cmd->add_option("--memory-budget", options->memory_budget,
                  "Refuse canvases needing more memory than this, and a CPU reference solve whose "
                  "arrays would not fit (bytes, or with K/M/G/T, powers of 1024); " +
                      std::string(kDefaultMemoryBudgetHelp))
      ->transform(byte_size);
  cmd->add_flag("--json", options->json, "Print one JSON object with a `cases` array");
  cmd->add_flag("--quiet", options->quiet, "No progress lines on stderr");
  cmd->callback([options, device] {
    require_chosen_device(device, options->device);
    run_bench(*options);
  });
}

}  // namespace rvor::cli
