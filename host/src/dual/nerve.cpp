// Nerve extraction: per brick, gather the labels of the brick and of its +x/+y/+z neighbours into
// a small dense block, skip uniform blocks, and visit the Kuhn simplices of every multi-label grid
// cell. Bricks are scanned in parallel, each thread into its own map; maps are merged at the end.
#include "rvor/nerve.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <thread>

#include "dual/simplex_map.h"
#include "dual/witness_cache.h"
#include "joining_threads.h"
#include "rvor/error.h"
#include "slot_ranges.h"

namespace rvor {

namespace {

constexpr int kBlockEdge = Canvas::kBrickEdge + 1;  // cells of a brick reach one voxel beyond it

// Insertion sort of a few labels (std::sort on tiny arrays trips GCC 12's -Warray-bounds).
void sort_few(int32_t* first, int count) {
  for (int i = 1; i < count; ++i)
    for (int j = i; j > 0 && first[j - 1] > first[j]; --j) std::swap(first[j - 1], first[j]);
}

// Labels, distances and slots of a brick's voxels and of the voxels one step beyond it, and the
// world coordinates of the block's voxel planes along each axis.
struct Block {
  int edge_z = kBlockEdge;
  std::array<int32_t, kBlockEdge * kBlockEdge * kBlockEdge> label{};
  std::array<float, kBlockEdge * kBlockEdge * kBlockEdge> distance{};
  std::array<int64_t, kBlockEdge * kBlockEdge * kBlockEdge> slot{};
  std::array<std::array<double, kBlockEdge>, 3> world{};  // world[axis][offset]
  static int index(int a, int b, int c) { return a + kBlockEdge * (b + kBlockEdge * c); }
};

// Ids of the brick at `o` and of its +x/+y/+z neighbours (-1 where empty or outside), indexed
// dx + 2 (dy + 2 dz): the bricks a block reaches into.
std::array<int32_t, 8> neighbour_bricks(const Canvas& canvas, const VoxelIndex& o) {
  std::array<int32_t, 8> bricks{};
  const int bi = o.i / Canvas::kBrickEdge, bj = o.j / Canvas::kBrickEdge,
            bk = o.k / canvas.brick_edge_z();
  for (int d = 0; d < 8; ++d) {
    const int i = bi + (d & 1), j = bj + ((d >> 1) & 1), k = bk + (d >> 2);
    bricks[d] = canvas.brick_at(i, j, k);
  }
  return bricks;
}

// Canvas::slot_of for block voxel (a, b, c), with the brick look-ups done once per block.
int64_t block_slot(const Canvas& canvas, const VoxelIndex& o, const std::array<int32_t, 8>& bricks,
                   int a, int b, int c) {
  if (o.i + a >= canvas.dims[0] || o.j + b >= canvas.dims[1] || o.k + c >= canvas.dims[2])
    return -1;
  constexpr int e = Canvas::kBrickEdge;
  const int32_t brick = bricks[a / e + 2 * (b / e) + 4 * (c / e)];
  if (brick < 0) return -1;
  const int64_t slot =
      static_cast<int64_t>(brick) * canvas.brick_volume() + a % e + e * (b % e + e * (c % e));
  return canvas.active[static_cast<std::size_t>(slot)] ? slot : -1;
}

// Fills the block of brick `brick`; returns false when it holds fewer than two labels.
bool gather_block(const Canvas& canvas, const VoronoiField& field, std::size_t brick,
                  Block& block) {
  const VoxelIndex o = canvas.brick_origins[brick];
  const std::array<int32_t, 8> bricks = neighbour_bricks(canvas, o);
  block.edge_z = canvas.dimension == 3 ? kBlockEdge : 1;
  int32_t first = -1;
  bool several = false;
  for (int c = 0; c < block.edge_z; ++c)
    for (int b = 0; b < kBlockEdge; ++b)
      for (int a = 0; a < kBlockEdge; ++a) {
        const int n = Block::index(a, b, c);
        const int64_t slot = block_slot(canvas, o, bricks, a, b, c);
        const int32_t label = slot < 0 ? -1 : field.label[slot];
        block.slot[n] = slot;
        block.label[n] = label;
        block.distance[n] = slot < 0 ? 0.0f : field.distance[slot];
        if (label < 0) continue;
        if (first < 0) first = label;
        several = several || label != first;
      }
  // Canvas::world_of is component-wise: the voxels on the block's diagonal give every plane.
  for (int a = 0; a < kBlockEdge; ++a) {
    const Vec3 p = canvas.world_of(VoxelIndex{o.i + a, o.j + a, o.k + a});
    for (int axis = 0; axis < 3; ++axis) block.world[axis][a] = p[axis];
  }
  return several;
}

// The Kuhn simplices of one cell: vertex offsets along the monotone paths 000 -> 111.
struct KuhnPaths {
  std::vector<std::array<std::array<int, 3>, 4>> simplices;
  // The same vertices as cell corner numbers dx + 2 dy + 4 dz.
  std::vector<std::array<int, 4>> corners;
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
      std::array<int, 4> c{};
      for (int v = 0; v < 4; ++v) c[v] = s[v][0] + 2 * s[v][1] + 4 * s[v][2];
      corners.push_back(c);
    } while (std::next_permutation(axes.begin(), axes.begin() + axis_count));
  }
};

// Bits set in 0..15 (GCC calls libgcc for __builtin_popcount without -mpopcnt).
constexpr std::array<int, 16> kBitCount{0, 1, 1, 2, 1, 2, 2, 3, 1, 2, 2, 3, 2, 3, 3, 4};

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

  // Merges what the cache still holds (call after the last brick).
  void finish(dual::SimplexMap& out) { cache_.flush(out); }

 private:
  // Most cells lie inside one Voronoi cell: a single comparison of the corners skips them.
  bool uniform_cell(int a, int b, int c) const {
    const int corner_z = canvas_.dimension == 3 ? 2 : 1;
    const int32_t first = block_.label[Block::index(a, b, c)];
    for (int dz = 0; dz < corner_z; ++dz)
      for (int dy = 0; dy < 2; ++dy)
        for (int dx = 0; dx < 2; ++dx)
          if (block_.label[Block::index(a + dx, b + dy, c + dz)] != first) return false;
    return true;
  }

  void scan_cell(const VoxelIndex& o, int a, int b, int c, dual::SimplexMap& out) {
    if (uniform_cell(a, b, c)) return;
    std::array<int32_t, 8> labels{};
    int n = 0;
    const int corner_z = canvas_.dimension == 3 ? 2 : 1;
    for (int dz = 0; dz < corner_z; ++dz)
      for (int dy = 0; dy < 2; ++dy)
        for (int dx = 0; dx < 2; ++dx) {
          const int32_t l = block_.label[Block::index(a + dx, b + dy, c + dz)];
          // -1: unreached; any other label, negative ones too, is checked below
          if (l != -1 && std::find(labels.begin(), labels.begin() + n, l) == labels.begin() + n)
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
    if (n == 2) {
      scan_two_label_cell(std::min(labels[0], labels[1]), std::max(labels[0], labels[1]), a, b, c,
                          out);
      return;
    }
    cell_simplices_.clear();
    for (const auto& simplex : kuhn_.simplices) scan_simplex(simplex, a, b, c);
    for (const NerveSimplex& s : cell_simplices_) cache_.merge(s, out);
  }

  // Most multi-label cells carry two labels: each of their simplices carrying both witnesses the
  // one edge, with all its active vertices as members (as scan_simplex would find). The cell's
  // witnesses are combined here and merged into the cache once.
  void scan_two_label_cell(int32_t first, int32_t second, int a, int b, int c,
                           dual::SimplexMap& out) {
    std::array<int, 8> corner_index{};
    std::array<Vec3, 8> position;
    const int corner_count = canvas_.dimension == 3 ? 8 : 4;
    for (int k = 0; k < corner_count; ++k) {
      const int x = a + (k & 1), y = b + ((k >> 1) & 1), z = c + (k >> 2);
      corner_index[k] = Block::index(x, y, z);
      position[k] = Vec3(block_.world[0][x], block_.world[1][y], block_.world[2][z]);
    }
    NerveSimplex edge;
    edge.seeds = {first, second, -1, -1};
    edge.vertex_count = 2;
    for (const auto& simplex : kuhn_.corners) {
      Witness w;
      w.distance = -1.0f;
      int members = 0;
      bool has_first = false, has_second = false;
      for (int v = 0; v < kuhn_.vertex_count; ++v) {
        const int n = corner_index[simplex[v]];
        const int32_t label = block_.label[n];
        if (label < 0) continue;
        (label == first ? has_first : has_second) = true;
        w.position += position[simplex[v]];
        ++members;
        if (block_.distance[n] > w.distance) {
          w.distance = block_.distance[n];
          w.slot = block_.slot[n];
        }
      }
      if (!has_first || !has_second) continue;
      w.position /= members;
      if (edge.witness_count++ == 0) {
        edge.farthest = edge.nearest = w;
        continue;
      }
      if (dual::witness_less(edge.farthest, w)) edge.farthest = w;
      if (dual::witness_less(w, edge.nearest)) edge.nearest = w;
    }
    if (edge.witness_count > 0) cache_.merge(edge, out);
  }

  struct Vertex {
    int32_t label;
    float distance;
    int64_t slot;
    Vec3 position;
    unsigned bit;  // 1 << (index of its label among the simplex's sorted distinct labels)
  };

  void scan_simplex(const std::array<std::array<int, 3>, 4>& simplex, int a, int b, int c) {
    std::array<Vertex, 4> vertices{};
    int count = 0;
    for (int v = 0; v < kuhn_.vertex_count; ++v) {
      const int x = a + simplex[v][0], y = b + simplex[v][1], z = c + simplex[v][2];
      const int n = Block::index(x, y, z);
      if (block_.label[n] >= 0)
        vertices[count++] = {block_.label[n], block_.distance[n], block_.slot[n],
                             Vec3(block_.world[0][x], block_.world[1][y], block_.world[2][z]), 0};
    }
    std::array<int32_t, 4> distinct{};
    int labels = 0;
    for (int v = 0; v < count; ++v)
      if (std::find(distinct.begin(), distinct.begin() + labels, vertices[v].label) ==
          distinct.begin() + labels)
        distinct[labels++] = vertices[v].label;
    if (labels < 2) return;
    sort_few(distinct.data(), labels);
    for (int v = 0; v < count; ++v)
      vertices[v].bit =
          1u << (std::find(distinct.begin(), distinct.begin() + labels, vertices[v].label) -
                 distinct.begin());
    // Every subset of the distinct labels is carried by a face of this simplex; its witness is
    // the largest face carrying exactly that subset.
    for (unsigned mask = 1; mask < (1u << labels); ++mask) {
      if (kBitCount[mask] < 2) continue;
      std::array<int32_t, 4> key{-1, -1, -1, -1};
      int size = 0;
      for (int l = 0; l < labels; ++l)
        if (mask & (1u << l)) key[size++] = distinct[l];
      note(key, size, witness_of(vertices, count, mask));
    }
  }

  // The witness of the face made of the vertices whose label is in `mask`.
  static Witness witness_of(const std::array<Vertex, 4>& vertices, int count, unsigned mask) {
    Witness w;
    w.distance = -1.0f;
    int members = 0;
    for (int v = 0; v < count; ++v) {
      if (!(vertices[v].bit & mask)) continue;
      w.position += vertices[v].position;
      ++members;
      if (vertices[v].distance > w.distance) {
        w.distance = vertices[v].distance;
        w.slot = vertices[v].slot;
      }
    }
    w.position /= members;
    return w;
  }

  // Collects the current cell's witnesses per Delaunay simplex (a handful of them), so that the
  // cache sees each simplex once per cell.
  void note(const std::array<int32_t, 4>& key, int size, const Witness& w) {
    for (NerveSimplex& s : cell_simplices_)
      if (dual::same_seeds(s.seeds, key)) {
        if (dual::witness_less(s.farthest, w)) s.farthest = w;
        if (dual::witness_less(w, s.nearest)) s.nearest = w;
        ++s.witness_count;
        return;
      }
    NerveSimplex& s = cell_simplices_.emplace_back();
    s.seeds = key;
    s.vertex_count = size;
    s.farthest = s.nearest = w;
    s.witness_count = 1;
  }

  const Canvas& canvas_;
  const VoronoiField& field_;
  std::size_t seed_count_;
  KuhnPaths kuhn_;
  Block block_;
  dual::WitnessCache cache_;
  std::vector<NerveSimplex> cell_simplices_;
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
  return extract_nerve(canvas, field, seed_count,
                       std::vector<std::uint8_t>(canvas.brick_count(), std::uint8_t{1}));
}

// extract_nerve itself; the public entry point names a failed allocation.
static Nerve extract_nerve_itself(const Canvas& canvas, const VoronoiField& field,
                                  std::size_t seed_count,
                                  const std::vector<std::uint8_t>& bricks_to_scan) {
  const auto start = std::chrono::steady_clock::now();
  // Every slot as a solve leaves it (NaN distances, or 0 without a label, gave a nerve): the
  // vectorised check an insertion runs on a caller's field, one pass over the slots beside the
  // scan's.
  require_insertable_field(canvas, field, seed_count, "nerve");
  if (bricks_to_scan.size() != canvas.brick_count())
    throw Error("nerve: " + std::to_string(bricks_to_scan.size()) + " brick flags for " +
                std::to_string(canvas.brick_count()) + " bricks");
  std::vector<std::uint32_t> bricks;
  for (std::size_t b = 0; b < bricks_to_scan.size(); ++b)
    if (bricks_to_scan[b]) bricks.push_back(static_cast<std::uint32_t>(b));
  const unsigned threads = slot_threads();
  std::vector<dual::SimplexMap> maps(threads);
  std::atomic<std::size_t> next{0};
  std::vector<std::exception_ptr> errors(threads);
  auto work = [&](unsigned t) {
    try {
      BrickScanner scanner(canvas, field, seed_count);
      for (std::size_t n; (n = next.fetch_add(1)) < bricks.size();)
        scanner.scan(bricks[n], maps[t]);
      scanner.finish(maps[t]);
    } catch (...) {
      errors[t] = std::current_exception();
    }
  };
  {
    JoiningThreads pool;  // a thread that cannot start leaves its share to the others
    for (unsigned t = 1; t < threads && pool.start(work, t); ++t) {
    }
    work(0);
  }
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

Nerve extract_nerve(const Canvas& canvas, const VoronoiField& field, std::size_t seed_count,
                    const std::vector<std::uint8_t>& bricks_to_scan) {
  return naming_out_of_memory("extracting the nerve", [&] {
    return extract_nerve_itself(canvas, field, seed_count, bricks_to_scan);
  });
}

}  // namespace rvor
