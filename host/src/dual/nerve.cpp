// Nerve extraction: per brick, gather the labels of the brick and of its +x/+y/+z neighbours into
// a small dense block, skip uniform blocks, and visit the Kuhn simplices of every multi-label grid
// cell. Bricks are scanned in parallel, each thread into its own map; maps are merged at the end.
#include "rvor/nerve.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <thread>

#include "dual/simplex_map.h"
#include "rvor/error.h"

namespace rvor {

namespace {

constexpr int kBlockEdge = Canvas::kBrickEdge + 1;  // cells of a brick reach one voxel beyond it

// Insertion sort of a few labels (std::sort on tiny arrays trips GCC 12's -Warray-bounds).
void sort_few(int32_t* first, int count) {
  for (int i = 1; i < count; ++i)
    for (int j = i; j > 0 && first[j - 1] > first[j]; --j) std::swap(first[j - 1], first[j]);
}

// Labels, distances and slots of a brick's voxels and of the voxels one step beyond it.
struct Block {
  int edge_z = kBlockEdge;
  std::array<int32_t, kBlockEdge * kBlockEdge * kBlockEdge> label{};
  std::array<float, kBlockEdge * kBlockEdge * kBlockEdge> distance{};
  std::array<int64_t, kBlockEdge * kBlockEdge * kBlockEdge> slot{};
  static int index(int a, int b, int c) { return a + kBlockEdge * (b + kBlockEdge * c); }
};

// Fills the block of brick `brick`; returns false when it holds fewer than two labels.
bool gather_block(const Canvas& canvas, const VoronoiField& field, std::size_t brick,
                  Block& block) {
  const VoxelIndex o = canvas.brick_origins[brick];
  block.edge_z = canvas.dimension == 3 ? kBlockEdge : 1;
  int32_t first = -1;
  bool several = false;
  for (int c = 0; c < block.edge_z; ++c)
    for (int b = 0; b < kBlockEdge; ++b)
      for (int a = 0; a < kBlockEdge; ++a) {
        const int n = Block::index(a, b, c);
        const int64_t slot = canvas.slot_of(o.i + a, o.j + b, o.k + c);
        const int32_t label = slot < 0 ? -1 : field.label[slot];
        block.slot[n] = slot;
        block.label[n] = label;
        block.distance[n] = slot < 0 ? 0.0f : field.distance[slot];
        if (label < 0) continue;
        if (first < 0) first = label;
        several = several || label != first;
      }
  return several;
}

// The Kuhn simplices of one cell: vertex offsets along the monotone paths 000 -> 111.
struct KuhnPaths {
  std::vector<std::array<std::array<int, 3>, 4>> simplices;
  int vertex_count = 4;
  explicit KuhnPaths(int dimension) {
    std::array<int, 3> axes{0, 1, 2};
    vertex_count = dimension + 1;
    const int axis_count = dimension;
    do {
      std::array<std::array<int, 3>, 4> s{};
      for (int v = 1; v <= axis_count; ++v) {
        s[v] = s[v - 1];
        s[v][axes[v - 1]] += 1;
      }
      simplices.push_back(s);
    } while (std::next_permutation(axes.begin(), axes.begin() + axis_count));
  }
};

class BrickScanner {
 public:
  BrickScanner(const Canvas& canvas, const VoronoiField& field, std::size_t seed_count)
      : canvas_(canvas), field_(field), seed_count_(seed_count), kuhn_(canvas.dimension) {}

  void scan(std::size_t brick, dual::SimplexMap& out) {
    if (!gather_block(canvas_, field_, brick, block_)) return;
    const VoxelIndex o = canvas_.brick_origins[brick];
    const int cells_z = canvas_.dimension == 3 ? Canvas::kBrickEdge : 1;
    for (int c = 0; c < cells_z; ++c)
      for (int b = 0; b < Canvas::kBrickEdge; ++b)
        for (int a = 0; a < Canvas::kBrickEdge; ++a) scan_cell(o, a, b, c, out);
  }

 private:
  void scan_cell(const VoxelIndex& o, int a, int b, int c, dual::SimplexMap& out) {
    std::array<int32_t, 8> labels{};
    int n = 0;
    const int corner_z = canvas_.dimension == 3 ? 2 : 1;
    for (int dz = 0; dz < corner_z; ++dz)
      for (int dy = 0; dy < 2; ++dy)
        for (int dx = 0; dx < 2; ++dx) {
          const int32_t l = block_.label[Block::index(a + dx, b + dy, c + dz)];
          if (l >= 0 && std::find(labels.begin(), labels.begin() + n, l) == labels.begin() + n)
            labels[n++] = l;
        }
    if (n < 2) return;
    for (int i = 0; i < n; ++i)
      if (static_cast<std::size_t>(labels[i]) >= seed_count_)
        throw Error("nerve: voxel label " + std::to_string(labels[i]) + " is not a seed index (" +
                    std::to_string(seed_count_) + " seeds)");
    if (n > kuhn_.vertex_count) {
      sort_few(labels.data(), n);
      out.add_degenerate({VoxelIndex{o.i + a, o.j + b, o.k + c},
                          std::vector<int32_t>(labels.begin(), labels.begin() + n)});
    }
    for (const auto& simplex : kuhn_.simplices) scan_simplex(simplex, a, b, c, out);
  }

  struct Vertex {
    int32_t label;
    float distance;
    int64_t slot;
  };

  void scan_simplex(const std::array<std::array<int, 3>, 4>& simplex, int a, int b, int c,
                    dual::SimplexMap& out) {
    std::array<Vertex, 4> vertices{};
    int count = 0;
    for (int v = 0; v < kuhn_.vertex_count; ++v) {
      const int n = Block::index(a + simplex[v][0], b + simplex[v][1], c + simplex[v][2]);
      if (block_.label[n] >= 0)
        vertices[count++] = {block_.label[n], block_.distance[n], block_.slot[n]};
    }
    std::array<int32_t, 4> distinct{};
    int labels = 0;
    for (int v = 0; v < count; ++v)
      if (std::find(distinct.begin(), distinct.begin() + labels, vertices[v].label) ==
          distinct.begin() + labels)
        distinct[labels++] = vertices[v].label;
    if (labels < 2) return;
    sort_few(distinct.data(), labels);
    // Every subset of the distinct labels is carried by a face of this simplex; its witness is
    // the largest face carrying exactly that subset.
    for (unsigned mask = 1; mask < (1u << labels); ++mask) {
      if (__builtin_popcount(mask) < 2) continue;
      std::array<int32_t, 4> key{-1, -1, -1, -1};
      int size = 0;
      for (int l = 0; l < labels; ++l)
        if (mask & (1u << l)) key[size++] = distinct[l];
      out.add(key, size, witness_of(vertices, count, key, size));
    }
  }

  Witness witness_of(const std::array<Vertex, 4>& vertices, int count,
                     const std::array<int32_t, 4>& key, int size) const {
    Witness w;
    w.distance = -1.0f;
    int members = 0;
    for (int v = 0; v < count; ++v) {
      if (std::find(key.begin(), key.begin() + size, vertices[v].label) == key.begin() + size)
        continue;
      w.position += canvas_.world_of(static_cast<std::size_t>(vertices[v].slot));
      ++members;
      if (vertices[v].distance > w.distance) {
        w.distance = vertices[v].distance;
        w.slot = vertices[v].slot;
      }
    }
    w.position /= members;
    return w;
  }

  const Canvas& canvas_;
  const VoronoiField& field_;
  std::size_t seed_count_;
  KuhnPaths kuhn_;
  Block block_;
};

std::vector<NerveSimplex> sorted_simplices(const dual::SimplexMap& map, int vertex_count) {
  std::vector<NerveSimplex> out;
  for (const auto& [key, simplex] : map.simplices())
    if (simplex.vertex_count == vertex_count) out.push_back(simplex);
  std::sort(out.begin(), out.end(),
            [](const NerveSimplex& x, const NerveSimplex& y) { return x.seeds < y.seeds; });
  return out;
}

}  // namespace

const NerveSimplex* Nerve::find(std::vector<int32_t> seeds) const {
  if (seeds.size() < 2 || seeds.size() > 4) return nullptr;
  std::sort(seeds.begin(), seeds.end());
  NerveSimplex probe;
  std::copy(seeds.begin(), seeds.end(), probe.seeds.begin());
  const auto& list = seeds.size() == 2 ? edges : (seeds.size() == 3 ? triangles : tetrahedra);
  auto it = std::lower_bound(
      list.begin(), list.end(), probe,
      [](const NerveSimplex& x, const NerveSimplex& y) { return x.seeds < y.seeds; });
  return it != list.end() && it->seeds == probe.seeds ? &*it : nullptr;
}

Nerve extract_nerve(const Canvas& canvas, const VoronoiField& field, std::size_t seed_count) {
  const auto start = std::chrono::steady_clock::now();
  if (field.label.size() != canvas.slot_count() || field.distance.size() != canvas.slot_count())
    throw Error("nerve: the field does not match the canvas (slot counts differ)");
  const unsigned threads = std::max(1u, std::min(16u, std::thread::hardware_concurrency()));
  std::vector<dual::SimplexMap> maps(threads);
  std::atomic<std::size_t> next_brick{0};
  std::vector<std::exception_ptr> errors(threads);
  auto work = [&](unsigned t) {
    try {
      BrickScanner scanner(canvas, field, seed_count);
      for (std::size_t b; (b = next_brick.fetch_add(1)) < canvas.brick_count();)
        scanner.scan(b, maps[t]);
    } catch (...) {
      errors[t] = std::current_exception();
    }
  };
  std::vector<std::thread> pool;
  for (unsigned t = 1; t < threads; ++t) pool.emplace_back(work, t);
  work(0);
  for (auto& thread : pool) thread.join();
  for (const auto& e : errors)
    if (e) std::rethrow_exception(e);
  for (unsigned t = 1; t < threads; ++t) maps[0].merge(maps[t]);

  Nerve nerve;
  nerve.dimension = canvas.dimension;
  nerve.seed_count = seed_count;
  nerve.edges = sorted_simplices(maps[0], 2);
  nerve.triangles = sorted_simplices(maps[0], 3);
  nerve.tetrahedra = sorted_simplices(maps[0], 4);
  nerve.degenerate_witness_count = maps[0].degenerate_count();
  nerve.degenerate_witnesses = maps[0].take_degenerate(Nerve::kMaxDegenerateListed);
  nerve.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return nerve;
}

}  // namespace rvor
