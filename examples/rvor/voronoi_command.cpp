// rvor voronoi: domain + metric + seeds -> distance and label per voxel, written as .vdb (and
// .vtu, probes) with a report.json.
#include <algorithm>
#include <array>
#include <cctype>
#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "commands.h"
#include "output_set.h"
#include "rvor/atomic_file.h"
#include "rvor/canvas_builder.h"
#include "rvor/canvas_output.h"
#include "rvor/canvas_png.h"
#include "rvor/curved_dual.h"
#include "rvor/devices.h"
#include "rvor/dual.h"
#include "rvor/error.h"
#include "rvor/field_summary.h"
#include "rvor/input_file.h"
#include "rvor/local_fields.h"
#include "rvor/metric_field.h"
#include "rvor/metric_reach.h"
#include "rvor/nerve.h"
#include "rvor/propagation.h"
#include "rvor/seeds.h"
#include "rvor/spec_text.h"
#include "rvor/vdb_io.h"
#include "terminal.h"

namespace rvor::cli {

namespace {

struct VoronoiOptions {
  std::string domain;
  int resolution = 128;
  std::string metric = "euclidean";
  std::string metric_sol, metric_mesh, metric_vdb;
  std::string seeds_file;
  std::size_t random_seed_count = 0;
  std::uint64_t rng_seed = 1;
  std::string device = default_device_name();  // $RVOR_DEVICE, else auto
  std::string probe_file;
  std::string out_dir = "rvor-out";
  bool vtu = false;
  bool overwrite = false;
  std::uint64_t memory_budget = 0;  // bytes (byte_size); 0: the default
  std::string dual;                 // "", "straight", "curved" or "both"
  bool png = false;
  bool quiet = false;
};

std::string lowercase_extension(const std::string& path) {
  std::string extension = std::filesystem::path(path).extension().string();
  for (char& c : extension) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return extension;
}

// The Medit pair with a .sol given to --metric-mesh or a .mesh to --metric-file (swapped, say):
// the reader's error speaks of the file's sections ("no Tetrahedra"), not of the options.
std::unique_ptr<MetricField> load_medit_metric(const VoronoiOptions& o) {
  try {
    return load_mesh_metric(o.metric_mesh, o.metric_sol);
  } catch (const Error& error) {
    if (lowercase_extension(o.metric_mesh) != ".sol" &&
        lowercase_extension(o.metric_sol) != ".mesh")
      throw;
    throw Error(std::string(error.what()) +
                " (--metric-mesh takes the .mesh file, --metric-file the .sol file)");
  }
}

std::unique_ptr<MetricField> load_metric(const VoronoiOptions& o, int dimension,
                                         std::uint64_t memory_budget) {
  if (!o.metric_vdb.empty()) return load_vdb_metric(o.metric_vdb, memory_budget);
  if (!o.metric_sol.empty() || !o.metric_mesh.empty()) {
    if (o.metric_sol.empty() || o.metric_mesh.empty())
      throw Error("--metric-file and --metric-mesh must be given together");
    return load_medit_metric(o);
  }
  return make_analytic_metric(o.metric, dimension);
}

// Every file rvor voronoi may write, and whether this run's options write it.
std::vector<std::pair<std::string, bool>> output_table(const VoronoiOptions& o) {
  const bool straight = o.dual == "straight" || o.dual == "both";
  const bool curved = o.dual == "curved" || o.dual == "both";
  return {{"voronoi.vdb", true},
          {"report.json", true},
          {"seeds.xyz", true},
          {"canvas.vtu", o.vtu},
          {"probe.csv", !o.probe_file.empty()},
          {"dual.vtu", straight},
          {"dual.mesh", straight},
          {"dual_flagged.vtu", straight},
          {"curved_dual.vtu", curved},
          {"curved_faces.vtu", curved},
          {"voronoi.png", o.png}};
}

// This run's outputs; with `every`, all that any run may leave.
std::vector<std::string> output_names(const VoronoiOptions& o, bool every = false) {
  std::vector<std::string> names;
  for (const auto& [name, written] : output_table(o))
    if (written || every) names.push_back(name);
  return names;
}

// The files the run reads, each with the option that names it ("" where not given).
std::vector<std::pair<std::string, std::string>> input_files(const VoronoiOptions& o) {
  std::vector<std::pair<std::string, std::string>> inputs = {{"--seeds", o.seeds_file},
                                                             {"--probe", o.probe_file},
                                                             {"--metric-file", o.metric_sol},
                                                             {"--metric-mesh", o.metric_mesh},
                                                             {"--metric-vdb", o.metric_vdb}};
  if (o.domain.rfind("mesh:", 0) == 0) inputs.push_back({"--domain mesh:", o.domain.substr(5)});
  return inputs;
}

// The outputs an earlier rvor voronoi run left in `dir`, as its report.json lists them (names
// rvor voronoi writes only): what --overwrite removes when this run does not write them again.
// None without such a report: files that merely share an output's name are the user's.
std::vector<std::string> earlier_outputs(const std::string& dir, const VoronoiOptions& o) {
  const std::filesystem::path path = std::filesystem::path(dir) / "report.json";
  std::error_code error;
  if (!std::filesystem::is_regular_file(std::filesystem::symlink_status(path, error))) return {};
  std::ifstream in(path);
  const nlohmann::json report = nlohmann::json::parse(in, nullptr, /*allow_exceptions=*/false);
  if (!report.is_object()) return {};
  const auto generator = report.find("generator"), listed = report.find("outputs");
  if (generator == report.end() || *generator != "rvor voronoi" || listed == report.end() ||
      !listed->is_array())
    return {};
  const std::vector<std::string> known = output_names(o, /*every=*/true);
  std::vector<std::string> names;
  for (const nlohmann::json& name : *listed)
    if (name.is_string() && std::find(known.begin(), known.end(), name) != known.end())
      names.push_back(name.get<std::string>());
  return names;
}

// An input file that this run would replace or remove (an earlier run's seeds.xyz given to
// --seeds, say) is refused, --overwrite or not: it is the user's data, not only an old output.
void refuse_replacing_inputs(const VoronoiOptions& o, const std::vector<std::string>& earlier) {
  std::vector<std::string> touched = output_names(o);
  touched.insert(touched.end(), earlier.begin(), earlier.end());
  for (const auto& [option, file] : input_files(o)) {
    if (file.empty()) continue;
    for (const std::string& name : touched) {
      const std::filesystem::path output = std::filesystem::path(o.out_dir) / name;
      std::error_code error;
      if (std::filesystem::equivalent(output, file, error) && !error)
        throw Error(option + " " + file + " is " + output.string() +
                    ", which this run would replace: copy it elsewhere, or choose another --out");
    }
  }
}

// Before anything is written: the outputs' checks would otherwise come first.
void require_one_seed_source(const VoronoiOptions& o) {
  if (!o.seeds_file.empty() && o.random_seed_count > 0)
    throw Error("give either --seeds or --random-seeds, not both");
  if (o.seeds_file.empty() && o.random_seed_count == 0)
    throw Error("no seeds: give --seeds FILE.xyz or --random-seeds N");
}

// The seeds of a --seeds file, read before the canvas is built (a bad file is reported at once,
// not after a long build); none with --random-seeds, which are drawn on the canvas.
XyzPoints seeds_from_file(const VoronoiOptions& o, int dimension) {
  if (o.seeds_file.empty()) return {};
  // "--seeds 100" (rvor bench's --seeds is a count) names no file: say which option takes a count.
  const std::optional<long long> count = parse_integer(o.seeds_file);
  std::error_code error;
  if (count && *count > 0 && !std::filesystem::exists(o.seeds_file, error))
    throw Error("--seeds " + o.seeds_file +
                ": no such file; --seeds takes a file of points, --random-seeds a count (for " +
                o.seeds_file + " random seeds: --random-seeds " + o.seeds_file + ")");
  return read_xyz_with_lines(o.seeds_file, dimension);
}

// The active voxels whose centres lie beyond `box` by more than half a voxel.
std::size_t voxels_outside(const Canvas& canvas, const Box& box) {
  const Vec3 slack = Vec3::Constant(canvas.voxel_size / 2);
  std::size_t outside = 0;
  for (std::size_t slot = 0; slot < canvas.slot_count(); ++slot) {
    if (!canvas.active[slot]) continue;
    const Vec3 p = canvas.world_of(slot);
    outside += (p.array() < (box.lo - slack).array()).any() ||
               (p.array() > (box.hi + slack).array()).any();
  }
  return outside;
}

// A picture too large for cairo failed as voronoi.png was written, after the solve and the
// duals, and took the run's other outputs with it: refuse it with the inputs' checks instead.
void require_png_fits(const Canvas& canvas) {
  try {
    require_drawable_png(canvas, 0, "--png");
  } catch (const Error& error) {
    throw Error(std::string(error.what()) +
                ": lower --resolution, or leave out --png (--vtu for ParaView)");
  }
}

nlohmann::json summary_json(const FieldSummary& s) {
  return {{"reached_voxels", s.reached_voxels},
          {"unreached_voxels", s.unreached_voxels},
          {"unreached_beside_reached_voxels", s.unreached_beside_reached},
          {"non_empty_cells", s.non_empty_cells},
          {"empty_cells", s.empty_cells},
          {"smallest_cell_voxels", s.smallest_cell},
          {"largest_cell_voxels", s.largest_cell},
          {"max_distance", s.max_distance},
          {"mean_distance", s.mean_distance}};
}

// The straight dual in the progress line: whether it is a triangulation, its element count, and
// the seeds it leaves out (a domain a few voxels thin: "a triangulation, 1 elements" of 60 seeds
// said nothing of the 56 in none); too few seeds for a simplex, or seeds all on one point, line or
// plane (which make flat simplices at best), make none, which is not a failed triangulation
// either: say why.
std::string straight_dual_detail(const StraightDual& dual, const std::vector<Vec3>& seeds,
                                 int dimension) {
  const std::string simplex = dimension == 2 ? "triangle" : "tetrahedron";
  const std::string count = std::to_string(seeds.size());
  if (seeds.size() <= static_cast<std::size_t>(dimension))
    return "no elements: " + count + (seeds.size() == 1 ? " seed" : " seeds") + ", and a " +
           simplex + " needs " + std::to_string(dimension + 1);
  std::string detail =
      std::string(dual.checks.is_triangulation ? "a triangulation" : "NOT a triangulation") + ", " +
      std::to_string(dual.top_count()) + (dual.top_count() == 1 ? " element" : " elements");
  const std::size_t unused = dual.checks.unused_vertices;
  if (unused > 0 && dual.top_count() > 0)
    detail += ", " + std::to_string(unused) + " of the " + count + " seeds in none";
  const int spanned = seeds_affine_dimension(seeds, dimension);
  if (spanned >= dimension) return detail;
  const std::string why = "the " + count + " seeds " +
                          (spanned == 0   ? "are all at one point"
                           : spanned == 1 ? "are collinear"
                                          : "are coplanar") +
                          ", and a " + simplex + " needs " + std::to_string(dimension + 1) +
                          " seeds off one " + (dimension == 2 ? "line" : "plane");
  return dual.top_count() == 0 ? "no elements: " + why : detail + ", all flat: " + why;
}

// The curved dual with its faces, on the nerve decided as the straight dual decides it (both duals
// then have the same simplices): per-seed local fields first (one small solve per seed, on the
// CPU), then the geodesics; writes curved_dual.vtu and curved_faces.vtu and fills `report`.
template <typename PathOf>
CurvedDual build_curved(const Canvas& canvas, const VoronoiField& field, const Nerve& witnessed,
                        const std::vector<Vec3>& seeds, std::uint64_t memory_budget,
                        Progress& progress, const PathOf& path, nlohmann::json& report) {
  const Nerve nerve = decided_nerve(canvas, witnessed, seeds);
  LocalFieldOptions local_options;
  local_options.memory_budget = memory_budget;
  local_options.progress = [&progress](std::size_t solved, std::size_t total) {
    if (solved == total)
      progress.update("tracing geodesics", /*now=*/true);
    else
      progress.update("local fields of " + std::to_string(solved) + " / " + std::to_string(total) +
                      " seeds");
  };
  const LocalFields locals = compute_local_fields(canvas, nerve, seeds, local_options);
  CurvedDual curved = build_curved_dual(canvas, field, nerve, seeds, &locals);
  write_curved_dual_vtu(path("curved_dual.vtu"), curved);
  write_curved_faces_vtu(path("curved_faces.vtu"), curved);
  report = {{"edges", curved.edges.size()},
            {"unreached_edges", curved.unreached_edges},
            {"faces", curved.faces.size()},
            {"unreached_faces", curved.unreached_faces},
            {"staircase_edges", curved.staircase_edges},
            {"staircase_faces", curved.staircase_faces},
            {"straightened_edges", curved.straightened_edges},
            {"local_fields",
             {{"voxels", locals.voxels},
              {"solved_voxels", locals.solved_voxels},
              {"seconds", locals.seconds}}},
            {"seconds", curved.seconds}};
  return curved;
}

// `created`: the folders of --out that do not exist before the run (missing_folders).
void write_voronoi(const VoronoiOptions& o, const std::vector<std::string>& created) {
  const auto start = std::chrono::steady_clock::now();
  Progress progress(o.quiet);
  // The note of a FIFO input that nothing has written to yet goes on a line of its own, not after
  // the open stage's name.
  set_fifo_wait_notice([&progress](const std::string& what, const std::string& path) {
    progress.note(fifo_wait_text(what, path));
  });
  struct PlainNotice {  // destroyed before `progress`, which the notice above refers to
    ~PlainNotice() { set_fifo_wait_notice(print_fifo_wait); }
  } plain_notice_after;

  // Every input is read and checked, down to the seeds on the built canvas, before the output
  // directory is looked at: a bad input came after "... already exists; pass --overwrite", which
  // steered the user towards replacing their results to learn what was wrong. The canvas is built
  // once, here; nothing is written before the outputs' checks.
  progress.begin("building canvas");
  const DomainSpec domain = parse_domain(o.domain);
  if (o.png && domain.dimension() != 2)
    throw Error(
        "--png draws 2D results only: use a 2D domain (rect: or implicit:disk) "
        "(3D results: --vtu for ParaView)");
  const std::vector<Vec3> probes =
      o.probe_file.empty() ? std::vector<Vec3>{} : read_xyz(o.probe_file, domain.dimension());
  const XyzPoints given_seeds = seeds_from_file(o, domain.dimension());
  CanvasOptions canvas_options;
  canvas_options.resolution = o.resolution;
  canvas_options.memory_budget = o.memory_budget;
  const std::unique_ptr<MetricField> metric =
      load_metric(o, domain.dimension(), canvas_options.memory_budget);
  const Canvas canvas = build_canvas(domain, *metric, canvas_options);
  if (o.png) require_png_fits(canvas);
  const MetricReach reach = sampled_metric_reach(canvas);
  const double canvas_seconds =
      progress.end(std::to_string(canvas.active_voxel_count) + " active voxels");

  const std::vector<Vec3> seeds = o.random_seed_count > 0
                                      ? random_seeds(canvas, o.random_seed_count, o.rng_seed)
                                      : given_seeds.points;
  // A given seed is named by its file and line as well as its label (which counts from 0).
  validate_seeds(canvas, seeds, 0, [&](std::size_t n) {
    const std::string label = "seed " + std::to_string(n);
    return given_seeds.lines.empty()
               ? label
               : o.seeds_file + ":" + std::to_string(given_seeds.lines[n]) + ": " + label;
  });

  const std::string out = o.out_dir;
  prepare_output_directory(out);
  const std::vector<std::string> earlier =
      o.overwrite ? earlier_outputs(out, o) : std::vector<std::string>{};
  refuse_replacing_inputs(o, earlier);
  // In place once everything succeeded.
  OutputSet outputs(out, output_names(o), o.overwrite, created);
  auto path = [&](const std::string& name) { return outputs.path(name); };
  try {
    progress.begin("propagating from " + std::to_string(seeds.size()) + " seeds");
    std::unique_ptr<Propagator> propagator = make_propagator(o.device);
    propagator->set_memory_budget(canvas_options.memory_budget);  // 0: the memory available
    VoronoiField field;
    const PropagationStats stats = propagator->solve(canvas, seeds, field);
    const std::string device = propagator->device_description();
    const double propagation_seconds = progress.end(device);
    const double updates_per_voxel =
        canvas.active_voxel_count ? double(stats.voxel_updates) / canvas.active_voxel_count : 0.0;
    // The dual's bricks come from the device's state. With them taken, the device's buffers (host
    // memory on PoCL) are freed before the outputs and the duals take theirs.
    const auto bricks_start = std::chrono::steady_clock::now();
    const std::vector<std::uint8_t> nerve_bricks =
        o.dual.empty() ? std::vector<std::uint8_t>{}
                       : propagator->multi_label_bricks(canvas, field);
    const double bricks_seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - bricks_start).count();
    propagator.reset();

    progress.begin("writing outputs");
    write_voronoi_vdb(path("voronoi.vdb"), canvas, field);
    write_xyz(path("seeds.xyz"), seeds, canvas.dimension);
    if (o.vtu) write_canvas_vtu(path("canvas.vtu"), canvas, field);
    RunNotes notes;
    if (o.device != "cpu") notes.opencl_updates_per_voxel = updates_per_voxel;
    if (!o.metric_mesh.empty() && metric->natural_domain())
      notes.voxels_outside_metric_mesh = voxels_outside(canvas, *metric->natural_domain());
    if (!o.probe_file.empty()) {
      const std::vector<ProbeSample> samples = probe_field(canvas, field, probes);
      for (const ProbeSample& sample : samples)
        notes.far_probes += (sample.query - sample.voxel_centre).norm() > canvas.voxel_size;
      write_probe_csv(path("probe.csv"), samples);
    }
    const FieldSummary summary = summarize_field(canvas, field, seeds.size());
    const double output_seconds = progress.end("");

    nlohmann::json dual_report, curved_report;
    double dual_seconds = 0;
    std::optional<StraightDual> dual;
    std::optional<CurvedDual> curved;
    if (!o.dual.empty()) {
      progress.begin(o.dual == "both" ? "building the straight and curved duals"
                                      : "building the " + o.dual + " dual");
      const Nerve nerve = extract_nerve(canvas, field, seeds.size(), nerve_bricks);
      std::string detail;
      if (o.dual != "curved") {
        dual = build_straight_dual(canvas, nerve, seeds);
        write_dual_vtu(path("dual.vtu"), *dual);
        write_dual_medit(path("dual.mesh"), *dual);
        write_dual_vtu(path("dual_flagged.vtu"), *dual, /*only_flagged=*/true);
        dual_report = nlohmann::json::parse(dual_report_json(*dual));
        detail = straight_dual_detail(*dual, seeds, canvas.dimension);
      }
      if (o.dual != "straight") {
        curved = build_curved(canvas, field, nerve, seeds, canvas_options.memory_budget, progress,
                              path, curved_report);
        // Edges and faces unreached apart: "217 geodesic edges, 138 faces, 1 unreached" left
        // which one to report.json.
        detail += (detail.empty() ? "" : "; ") + std::to_string(curved->edges.size()) +
                  " geodesic edges (" + std::to_string(curved->unreached_edges) + " unreached), " +
                  std::to_string(curved->faces.size()) + " faces (" +
                  std::to_string(curved->unreached_faces) + " unreached)";
      }
      dual_seconds = bricks_seconds + progress.end(detail);
    }
    if (o.png)
      write_canvas_png(path("voronoi.png"), canvas, field, seeds, dual ? &*dual : nullptr,
                       curved ? &*curved : nullptr);

    const double total =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    // JSON strings are UTF-8, and nlohmann refuses to write anything else: a file name in
    // Latin-1 (mesh:tw\xFFo.off, --metric-file m\xE9.sol) failed the run after everything was
    // computed. Such bytes are written as \xNN, as errors write them.
    nlohmann::json report = {{"generator", "rvor voronoi"},
                             {"domain", printable_text(domain.description())},
                             {"metric", printable_text(metric->description())},
                             {"dimension", canvas.dimension},
                             {"resolution", o.resolution},
                             {"voxel_size", canvas.voxel_size},
                             {"index_box", canvas.dims},
                             {"active_voxels", canvas.active_voxel_count},
                             {"seeds", seeds.size()},
                             {"device", printable_text(device)},
                             {"iterations", stats.iterations},
                             {"voxel_updates", stats.voxel_updates},
                             {"brick_relaxations", stats.brick_relaxations},
                             {"exact_start", stats.exact_start},
                             {"max_anisotropy", reach.max_anisotropy},
                             {"longest_stencil_offset", reach.longest_offset},
                             {"updates_per_voxel", updates_per_voxel},
                             {"timings",
                              {{"canvas", canvas_seconds},
                               {"propagation", propagation_seconds},
                               {"outputs", output_seconds},
                               {"dual", dual_seconds},
                               {"total", total}}},
                             {"field", summary_json(summary)},
                             {"outputs", output_names(o)}};
    if (!o.probe_file.empty()) report["probes_beyond_a_voxel"] = notes.far_probes;
    if (!o.metric_mesh.empty())
      report["voxels_outside_metric_mesh"] = notes.voxels_outside_metric_mesh;
    if (!dual_report.is_null()) report["dual"] = dual_report;
    if (!curved_report.is_null()) report["curved_dual"] = curved_report;
    write_file_atomically(path("report.json"),
                          [&](std::ostream& s) { s << report.dump(2) << "\n"; });
    outputs.commit([&] {  // the earlier run is the last to publish, maybe while this one ran
      std::vector<std::string> last =
          o.overwrite ? earlier_outputs(out, o) : std::vector<std::string>{};
      refuse_replacing_inputs(o, last);
      return last;
    });
    if (!o.quiet)
      print_voronoi_summary(std::cout, out, output_names(o), canvas.active_voxel_count,
                            seeds.size(), summary, reach, notes, propagation_seconds, total);
  } catch (const Error& error) {
    throw Error(outputs.shown(error.what()));  // the output's name, not its staging path
  }
}

// write_voronoi; the --out directory and the folders above it that it had to create are removed
// again when the run fails and leaves them empty (a refused option would otherwise leave empty
// folders behind).
void run_voronoi(const VoronoiOptions& o) {
  require_one_seed_source(o);
  const std::vector<std::string> created = missing_folders(o.out_dir);
  try {
    write_voronoi(o, created);
  } catch (...) {
    remove_empty_folders(created);  // where the output set did not (it was not made yet)
    throw;
  }
}

}  // namespace

void add_voronoi_command(CLI::App& app) {
  auto options = std::make_shared<VoronoiOptions>();
  CLI::App* cmd = app.add_subcommand(
      "voronoi",
      "Compute a Riemannian Voronoi diagram: geodesic distance to the nearest seed and its label "
      "at every voxel of a canvas.");
  cmd->footer(
      "Examples:\n"
      "  rvor voronoi --domain box:-1,-1,-1,1,1,1 --metric hyperbolic_shock --resolution 128 \\\n"
      "               --random-seeds 200 --out out/shock\n"
      "  rvor voronoi --domain rect:-1,-1,1,1 --metric uniform:100,0,1 --seeds seeds.xyz --vtu \\\n"
      "               --dual straight\n"
      "  rvor voronoi --domain mesh:part.off --metric-file m.sol --metric-mesh m.mesh --seeds "
      "s.xyz\n"
      "Outputs in --out: voronoi.vdb (float grid 'distance', int grid 'label'), report.json,\n"
      "seeds.xyz, and with --vtu canvas.vtu, with --probe probe.csv (x,y,z,distance,label),\n"
      "with --dual the files listed there, with --png voronoi.png.");
  cmd->add_option("--domain", options->domain, domain_help())->required();
  cmd->add_option("--resolution", options->resolution,
                  "Voxels along the longest side of the domain (2 to 65536)")
      ->transform(resolution_value)
      ->capture_default_str();
  CLI::Option* metric_option =
      cmd->add_option("--metric", options->metric, metric_help())->capture_default_str();
  CLI::Option* sol_option =
      cmd->add_option("--metric-file", options->metric_sol,
                      "Metric tensors at mesh vertices (Medit .sol), interpolated; points "
                      "outside the mesh take its nearest element's metric")
          ->check(non_empty_path);
  CLI::Option* mesh_option = cmd->add_option("--metric-mesh", options->metric_mesh,
                                             "The Medit .mesh the --metric-file lives on")
                                 ->check(non_empty_path);
  CLI::Option* vdb_option =
      cmd->add_option("--metric-vdb", options->metric_vdb,
                      "Metric as six float grids m11 m12 m22 m13 m23 m33 in a .vdb (a 3D file or "
                      "mesh on a rect: domain: its tensors restricted to the plane z = 0)")
          ->check(non_empty_path);
  // One source of the metric: a second one would be ignored.
  metric_option->excludes(sol_option)->excludes(mesh_option)->excludes(vdb_option);
  vdb_option->excludes(sol_option)->excludes(mesh_option);
  cmd->add_option("--seeds", options->seeds_file,
                  "Seeds, one point per line (2 or 3 coordinates, separated by blanks, commas or "
                  "semicolons; lines starting with # are skipped). A run needs this or "
                  "--random-seeds")
      ->check(non_empty_path);
  CLI::Option* random_option =
      cmd->add_option("--random-seeds", options->random_seed_count,
                      "Draw N seeds uniformly in distinct voxels of the canvas (the domain to half "
                      "a voxel); two of them closer than the canvas resolves can still share a "
                      "cell (report.json: field.empty_cells). A run needs this or --seeds")
          ->transform(seed_count(1));
  cmd->add_option("--rng-seed", options->rng_seed, "Random generator seed for --random-seeds")
      ->transform(rng_seed_value)
      ->capture_default_str()
      ->needs(random_option);
  const CLI::Option* device =
      add_device_option(cmd, options->device, "sequential reference, double precision");
  cmd->add_option(
         "--probe", options->probe_file,
         "Points (.xyz) at which to write probe.csv: nearest active voxel, distance, label")
      ->check(non_empty_path);
  cmd->add_option("--out", options->out_dir, "Output directory (created if missing)")
      ->check(non_empty_path)
      ->capture_default_str();
  cmd->add_option(
         "--dual", options->dual,
         "Also build the Riemannian Delaunay dual. straight: seeds joined by straight simplices, "
         "checked with exact predicates: dual.vtu, dual.mesh (Medit), dual_flagged.vtu "
         "(offending elements), a 'dual' object in report.json; curved: edges and faces traced as "
         "geodesics (one CPU solve per seed over its star first): curved_dual.vtu (polylines), "
         "curved_faces.vtu (triangulated patches), a 'curved_dual' object in report.json; both")
      ->check(CLI::IsMember({"straight", "curved", "both"}));
  cmd->add_flag(
      "--png", options->png,
      "2D only: also write voronoi.png, the cells shaded by distance bands, the seeds, and "
      "the dual when --dual is given (straight: dark segments, curved: red geodesics)");
  cmd->add_flag("--vtu", options->vtu, "Also write the labeled canvas as canvas.vtu (ParaView)");
  cmd->add_flag("--overwrite", options->overwrite,
                "Replace the outputs of an earlier run in --out; its files that this run does "
                "not write (as its report.json lists them) are removed, so that the directory "
                "holds one run's outputs. An input file of this run is never replaced");
  cmd->add_option("--memory-budget", options->memory_budget,
                  "Refuse canvases (and --metric-vdb grids) needing more memory than this, "
                  "a canvas counting the grids it is built from, a CPU reference solve "
                  "(--device cpu) whose arrays would not fit, and a curved dual whose local "
                  "fields do not fit beside its canvas (bytes, or with K/M/G/T, powers of 1024); " +
                      std::string(kDefaultMemoryBudgetHelp))
      ->transform(byte_size);
  cmd->add_flag("--quiet", options->quiet,
                "Print nothing but errors (and the note that an input is a FIFO nothing has "
                "written to yet, before waiting on it)");
  cmd->callback([options, device] {
    require_chosen_device(device, options->device);
    run_voronoi(*options);
  });
}

}  // namespace rvor::cli
