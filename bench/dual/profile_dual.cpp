// Profiling driver for nerve extraction + straight dual (not a test): propagates once per
// (resolution, seeds), caching the labeled field in a file so that later runs skip the
// propagation, then times extract_nerve and build_straight_dual and prints a fingerprint of
// their results (counts and a hash of every simplex, witness, flag and quality value), so that
// optimisations can be checked for identical output:
//   profile_dual RESOLUTION SEEDS [FIELD_CACHE] [REPETITIONS]
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <ctime>
#include <fstream>
#include <string>

#include "rvor/dual.h"
#include "rvor/propagation.h"
#include "rvor/seeds.h"
#include "support/box_canvas.h"

namespace {

// FNV-1a over raw bytes.
struct Hash {
  uint64_t h = 1469598103934665603ull;
  void bytes(const void* p, std::size_t n) {
    const auto* c = static_cast<const unsigned char*>(p);
    for (std::size_t i = 0; i < n; ++i) h = (h ^ c[i]) * 1099511628211ull;
  }
  template <typename T>
  void add(const T& v) {
    bytes(&v, sizeof v);
  }
};

// CPU time of the process, all threads (less noisy than wall time on a shared machine).
double cpu_seconds() {
  timespec t{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

bool load(const std::string& path, rvor::VoronoiField& field, std::size_t slots) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return false;
  field.label.resize(slots);
  field.distance.resize(slots);
  in.read(reinterpret_cast<char*>(field.label.data()), slots * sizeof(int32_t));
  in.read(reinterpret_cast<char*>(field.distance.data()), slots * sizeof(float));
  return static_cast<bool>(in);
}

void save(const std::string& path, const rvor::VoronoiField& field) {
  std::ofstream out(path, std::ios::binary);
  out.write(reinterpret_cast<const char*>(field.label.data()), field.label.size() * 4);
  out.write(reinterpret_cast<const char*>(field.distance.data()), field.distance.size() * 4);
}

void hash_witness(Hash& h, const rvor::Witness& w) {
  h.bytes(w.position.data(), 3 * sizeof(double));
  h.add(w.distance);
  h.add(w.slot);
}

uint64_t nerve_hash(const rvor::Nerve& nerve) {
  Hash h;
  for (const auto* list : {&nerve.edges, &nerve.triangles, &nerve.tetrahedra})
    for (const rvor::NerveSimplex& s : *list) {
      h.add(s.seeds);
      h.add(s.vertex_count);
      h.add(s.witness_count);
      hash_witness(h, s.farthest);
      hash_witness(h, s.nearest);
    }
  h.add(nerve.degenerate_witness_count);
  for (const auto& d : nerve.degenerate_witnesses) {
    h.add(d.cell_base);
    h.bytes(d.labels.data(), d.labels.size() * 4);
  }
  return h.h;
}

uint64_t dual_hash(const rvor::StraightDual& dual) {
  Hash h;
  h.bytes(dual.edges.data(), dual.edges.size() * 8);
  h.bytes(dual.triangles.data(), dual.triangles.size() * 12);
  h.bytes(dual.tetrahedra.data(), dual.tetrahedra.size() * 16);
  h.bytes(dual.flags.data(), dual.flags.size());
  for (const auto& q : dual.quality) h.add(q);
  h.bytes(dual.vertex_metrics.data(), dual.vertex_metrics.size() * sizeof(rvor::Mat3));
  const rvor::DualChecks& c = dual.checks;
  h.bytes(c.inverted_elements.data(), c.inverted_elements.size() * sizeof(std::size_t));
  h.bytes(c.intersecting_elements.data(), c.intersecting_elements.size() * sizeof(std::size_t));
  h.bytes(c.intersecting_element_pairs.data(), c.intersecting_element_pairs.size() * 16);
  h.bytes(c.non_manifold_facets.data(), c.non_manifold_facets.size() * 12);
  h.add(dual.quality_summary);
  return h.h;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 3) {
    std::fprintf(stderr, "usage: profile_dual RESOLUTION SEEDS [FIELD_CACHE] [REPETITIONS]\n");
    return 1;
  }
  const int resolution = std::atoi(argv[1]);
  const std::size_t seed_count = static_cast<std::size_t>(std::atol(argv[2]));
  const std::string cache = argc > 3 ? argv[3] : "";
  const int repetitions = argc > 4 ? std::atoi(argv[4]) : 3;
  rvor::Mat3 G;
  G << 4.0, 1.0, 0.0, 1.0, 2.0, 0.5, 0.0, 0.5, 1.0;
  const rvor::Canvas canvas = rvor::test::make_uniform_box_canvas(
      3, rvor::Vec3(0, 0, 0), rvor::Vec3(1, 1, 1), resolution, G);
  const std::vector<rvor::Vec3> seeds = rvor::random_seeds(canvas, seed_count, 1);
  rvor::VoronoiField field;
  if (cache.empty() || !load(cache, field, canvas.slot_count())) {
    const char* device = std::getenv("RVOR_BENCH_DEVICE");
    const auto start = std::chrono::steady_clock::now();
    rvor::make_propagator(device ? device : "auto")->solve(canvas, seeds, field);
    std::printf("propagation_s %.3f\n",
                std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
    if (!cache.empty()) save(cache, field);
  }
  for (int r = 0; r < repetitions; ++r) {
    const double cpu0 = cpu_seconds();
    const rvor::Nerve nerve = rvor::extract_nerve(canvas, field, seeds.size());
    const double cpu1 = cpu_seconds();
    const rvor::StraightDual dual = rvor::build_straight_dual(canvas, nerve, seeds);
    const double cpu2 = cpu_seconds();
    const rvor::DualChecks& c = dual.checks;
    std::printf("nerve_s %.3f dual_s %.3f (cpu: nerve %.3f dual %.3f)\n", nerve.seconds,
                dual.seconds, cpu1 - cpu0, cpu2 - cpu1);
    if (r + 1 < repetitions) continue;
    std::printf(
        "nerve: edges %zu triangles %zu tetrahedra %zu degenerate %zu hash %016llx\n"
        "dual: vertices %zu edges %zu triangles %zu tetrahedra %zu inverted %zu intersecting %zu "
        "pairs %zu non_manifold %zu near_degenerate %zu removed %zu added %zu dangling %zu "
        "unused %zu euler %d boundary_euler %d triangulation %d hash %016llx\n",
        nerve.edges.size(), nerve.triangles.size(), nerve.tetrahedra.size(),
        nerve.degenerate_witness_count, static_cast<unsigned long long>(nerve_hash(nerve)),
        dual.vertices.size(), dual.edges.size(), dual.triangles.size(), dual.tetrahedra.size(),
        c.inverted, c.intersecting, c.intersecting_pairs, c.non_manifold, c.near_degenerate,
        c.near_degenerate_removed, c.near_degenerate_added, c.dangling, c.unused_vertices,
        c.euler_characteristic, c.boundary_euler_characteristic, c.is_triangulation ? 1 : 0,
        static_cast<unsigned long long>(dual_hash(dual)));
  }
  return 0;
}
