// Farthest-point seeding on the library's incremental insertion: from one seed, insert one seed at
// a time at the voxel farthest, in geodesic distance, from all seeds so far. A VoronoiSession keeps
// the field with its propagator, so each insertion re-solves only the region its seed takes over;
// the chain is then checked against one solve of all its seeds (exit status 2 where they differ).
//
// Usage: farthest_point_seeds [METRIC [DOMAIN [RESOLUTION [SEEDS]]]]
//   (defaults: hyperbolic_shock box:-1,-1,-1,1,1,1 64 200; METRIC and DOMAIN as `rvor voronoi`
//   takes them; the device: $RVOR_DEVICE, else auto)
#include <rvor/canvas_builder.h>
#include <rvor/devices.h>
#include <rvor/domain.h>
#include <rvor/error.h>
#include <rvor/metric_field.h>
#include <rvor/propagation.h>
#include <rvor/spec_text.h>
#include <rvor/voronoi_session.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <exception>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace {

struct Arguments {
  std::string metric = "hyperbolic_shock";
  std::string domain = "box:-1,-1,-1,1,1,1";
  int resolution = 64;
  std::size_t seeds = 200;
};

// A positional argument that must be a decimal whole number in [least, most].
long long whole_number(const char* text, const char* name, long long least, long long most) {
  const std::optional<long long> value = rvor::parse_integer(text);
  if (!value || *value < least || *value > most)
    throw rvor::Error(std::string(name) + " '" + text + "' is not a whole number in [" +
                      std::to_string(least) + ", " + std::to_string(most) + "]");
  return *value;
}

constexpr const char* kUsage = "farthest_point_seeds [METRIC [DOMAIN [RESOLUTION [SEEDS]]]]";

// -h or --help: the usage with its defaults, on stdout (it was taken for a METRIC named "--help").
bool asked_for_help(int argc, char** argv) {
  if (argc != 2 || (std::string(argv[1]) != "-h" && std::string(argv[1]) != "--help")) return false;
  const Arguments defaults;
  std::printf(
      "Usage: %s\n"
      "Farthest-point seeding on incremental insertion, checked against one solve of all seeds\n"
      "(exit status 2 where they differ). METRIC and DOMAIN as `rvor voronoi` takes them; the\n"
      "device: $RVOR_DEVICE, else auto. Defaults: %s %s %d %zu\n",
      kUsage, defaults.metric.c_str(), defaults.domain.c_str(), defaults.resolution,
      defaults.seeds);
  return true;
}

Arguments parse_arguments(int argc, char** argv) {
  Arguments a;
  if (argc > 5) throw rvor::Error(std::string("usage: ") + kUsage);
  if (argc > 1) a.metric = argv[1];
  if (argc > 2) a.domain = argv[2];
  if (argc > 3)
    a.resolution = static_cast<int>(whole_number(
        argv[3], "RESOLUTION", rvor::kLeastCanvasResolution, rvor::kMostCanvasResolution));
  if (argc > 4) a.seeds = static_cast<std::size_t>(whole_number(argv[4], "SEEDS", 2, 100000));
  return a;
}

// The centre of the first active voxel (slot 0 lies outside a domain that does not fill its box).
rvor::Vec3 first_active_voxel(const rvor::Canvas& canvas) {
  std::size_t slot = 0;
  while (!canvas.active[slot]) ++slot;  // build_canvas refuses a canvas without active voxels
  return canvas.world_of(slot);
}

// The centre of the active voxel farthest from the seeds (ties: the first slot). A voxel no seed
// reached is the farthest of all (+inf): choosing among reached voxels only, the chain never
// seeded a piece of the domain apart from the first seed's (half of two disjoint boxes).
rvor::Vec3 farthest_voxel(const rvor::Canvas& canvas, const rvor::VoronoiField& field) {
  std::size_t farthest = 0;
  float distance = -1.0f;
  for (std::size_t slot = 0; slot < field.distance.size(); ++slot)
    if (canvas.active[slot] && field.distance[slot] > distance) {
      distance = field.distance[slot];
      farthest = slot;
    }
  return canvas.world_of(farthest);
}

double seconds_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

// Whether the chain's field is the solve's: labels and distances (to a relative 1e-4, the engines'
// agreement with each other) equal but at a few voxels, where a near-tie at a bisector can tip
// either way with the order of updates (docs/scheme.md, "Convergence").
bool same_field(const rvor::Canvas& canvas, const rvor::VoronoiField& chain,
                const rvor::VoronoiField& solve) {
  std::size_t labels = 0, distances = 0, reached = 0;
  for (std::size_t slot = 0; slot < solve.distance.size(); ++slot) {
    if (solve.label[slot] < 0) continue;
    ++reached;
    labels += chain.label[slot] != solve.label[slot];
    distances +=
        !(std::abs(chain.distance[slot] - solve.distance[slot]) <= 1e-4f * solve.distance[slot]);
  }
  std::printf(
      "chain against one solve of all seeds: %zu of %zu voxels labelled differently, "
      "%zu beyond a relative 1e-4\n",
      labels, reached, distances);
  // Fewer seeds than pieces of the domain, or voxels that no stencil leads to (README, "Voxels no
  // stencil reaches").
  if (reached < canvas.active_voxel_count)
    std::printf("%zu of %zu active voxels reached by no seed\n",
                canvas.active_voxel_count - reached, canvas.active_voxel_count);
  return 1000 * std::max(labels, distances) <= reached;
}

}  // namespace

int main(int argc, char** argv) try {
  if (asked_for_help(argc, argv)) return 0;
  const Arguments a = parse_arguments(argc, argv);
  const rvor::DomainSpec domain = rvor::parse_domain(a.domain);
  const auto metric = rvor::make_analytic_metric(a.metric, domain.dimension());
  rvor::CanvasOptions options;
  options.resolution = a.resolution;
  const rvor::Canvas canvas = rvor::build_canvas(domain, *metric, options);

  rvor::VoronoiSession session(rvor::make_default_propagator());
  session.solve(canvas, {first_active_voxel(canvas)});
  const auto start = std::chrono::steady_clock::now();
  while (session.seeds().size() < a.seeds)
    session.insert(canvas, {farthest_voxel(canvas, session.field())});
  const double insertion_seconds = seconds_since(start) / static_cast<double>(a.seeds - 1);

  // The same seeds solved at once; the second solve, as the first also uploads the canvas.
  const std::unique_ptr<rvor::Propagator> propagator = rvor::make_default_propagator();
  rvor::VoronoiField all;
  propagator->solve(canvas, session.seeds(), all);
  const double solve_seconds = propagator->solve(canvas, session.seeds(), all).seconds;
  std::printf("%s\non %s\n", canvas.description.c_str(), session.device_description().c_str());
  std::printf("%zu insertions, %.2f ms each: %.1f%% of a solve of all %zu seeds (%.3f s)\n",
              a.seeds - 1, 1e3 * insertion_seconds, 100.0 * insertion_seconds / solve_seconds,
              a.seeds, solve_seconds);
  return same_field(canvas, session.field(), all) ? 0 : 2;
} catch (const std::exception& error) {
  std::fprintf(stderr, "farthest_point_seeds: %s\n", error.what());
  return 1;
}
