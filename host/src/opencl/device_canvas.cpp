#include "device_canvas.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <string>
#include <unordered_map>
#include <vector>

#include <Eigen/LU>

#include "../slot_ranges.h"
#include "device_memory.h"
#include "host_pages.h"
#include "reader_reach.h"
#include "rvor/error.h"
#include "rvor/nearest_seeds.h"
#include "rvor/seeds.h"
#include "rvor/selling.h"

namespace rvor::opencl {

namespace {

// FNV-1a: the shape table's hash.
constexpr std::uint64_t kFnvBasis = 1469598103934665603ull;
void fnv_mix(std::uint64_t& hash, std::uint64_t value) {
  hash = (hash ^ value) * 1099511628211ull;
}

using Shape = std::array<std::int8_t, 3 * kStencilTerms>;

struct ShapeHash {
  std::size_t operator()(const Shape& shape) const {
    std::uint64_t hash = kFnvBasis;
    for (std::int8_t e : shape) fnv_mix(hash, static_cast<std::uint8_t>(e));
    return static_cast<std::size_t>(hash);
  }
};

// The distinct offset sets met so far, each with its index in the shape table.
using ShapeTable = std::unordered_map<Shape, std::uint32_t, ShapeHash>;

void store_shape_index(HugePageVector<float>& records, std::size_t into, std::uint32_t index) {
  std::memcpy(&records[kStencilRecord * into + kStencilTerms], &index, sizeof index);
}

// Packs the stencils of a range of slots: weights into the records, offsets into a table of this
// packer's own (merged into the canvas's by merge_shapes). `last_*` caches the last metric, so
// uniform regions reuse its stencil and shape.
struct StencilPacker {
  StencilPacker(const Canvas& c, PackedStencils& o, double length_unit)
      : canvas(c), out(o), step2(c.voxel_size * c.voxel_size / (length_unit * length_unit)) {}
  const Canvas& canvas;
  PackedStencils& out;
  double step2;  // (h / length_unit)^2: the weights are rho_i / step2
  std::array<int, 3> reach{};
  ShapeTable shapes;
  std::vector<Shape> shape_list;  // by local index
  std::array<float, 6> last_metric{};
  SellingStencil last_stencil;
  std::uint32_t last_shape = 0;
  bool has_last = false;

  // Packs the stencil of `slot` at position `into` of the records; its shape index is local.
  void pack(std::size_t slot, std::size_t into) {
    if (!canvas.active[slot]) return;
    std::array<float, 6> m;
    std::memcpy(m.data(), canvas.metric_of(slot), sizeof m);
    if (!has_last || m != last_metric) {
      last_stencil = canvas_selling_decomposition(canvas, slot, canvas.metric_at(slot).inverse());
      last_metric = m;
      last_shape = shape_index();
      has_last = true;
    }
    for (int i = 0; i < last_stencil.size; ++i)
      out.records[kStencilRecord * into + i] = static_cast<float>(last_stencil.weight[i] / step2);
    store_shape_index(out.records, into, last_shape);
  }

  // The local index of last_stencil's offsets, added to this packer's table when new.
  std::uint32_t shape_index() {
    Shape shape{};
    for (int i = 0; i < last_stencil.size; ++i)
      for (int a = 0; a < 3; ++a) {
        // Within int8: canvas_selling_decomposition refuses longer offsets.
        const int e = last_stencil.offset[i][a];
        shape[3 * i + a] = static_cast<std::int8_t>(e);
        reach[a] = std::max(reach[a], std::abs(e));
      }
    // Neighbouring voxels mostly share their offsets: skip the hash lookup then.
    if (!shape_list.empty() && shape_list[last_shape] == shape) return last_shape;
    const auto [found, added] =
        shapes.emplace(shape, static_cast<std::uint32_t>(shape_list.size()));
    if (added) shape_list.push_back(shape);
    return found->second;
  }
};

// Appends each packer's shapes to the canvas's table (once each) and returns, per packer, the
// canvas index of each of its local indices.
std::vector<std::vector<std::uint32_t>> merge_shapes(const std::vector<StencilPacker>& packers,
                                                     PackedStencils& out) {
  ShapeTable merged;
  std::vector<std::vector<std::uint32_t>> global_index(packers.size());
  for (std::size_t t = 0; t < packers.size(); ++t)
    for (const Shape& shape : packers[t].shape_list) {
      const auto [found, added] =
          merged.emplace(shape, static_cast<std::uint32_t>(out.shape_count()));
      if (added) out.shapes.insert(out.shapes.end(), shape.begin(), shape.end());
      global_index[t].push_back(found->second);
    }
  if (out.shapes.empty()) out.shapes.assign(3 * kStencilTerms, 0);  // shape 0 always exists
  return global_index;
}

// One stencil for the whole canvas, that of its first active voxel.
PackedStencils pack_uniform_stencil(const Canvas& canvas, double length_unit) {
  PackedStencils out;
  out.uniform = true;
  out.records.assign(kStencilRecord, 0.0f);
  const auto first = std::find(canvas.active.begin(), canvas.active.end(), std::uint8_t{1});
  std::vector<StencilPacker> packer(1, StencilPacker(canvas, out, length_unit));
  if (first != canvas.active.end())
    packer[0].pack(static_cast<std::size_t>(first - canvas.active.begin()), 0);
  merge_shapes(packer, out);  // its only shape has index 0 in both tables
  out.reach = packer[0].reach;
  return out;
}

}  // namespace

std::uint32_t PackedStencils::shape_of(std::size_t slot) const {
  std::uint32_t index;
  std::memcpy(&index, &records[kStencilRecord * slot + kStencilTerms], sizeof index);
  return index;
}

int PackedStencils::offset(std::size_t slot, int i, int a) const {
  return shapes[3 * (kStencilTerms * shape_of(slot) + static_cast<std::size_t>(i)) +
                static_cast<std::size_t>(a)];
}

PackedStencils pack_stencils(const Canvas& canvas, double length_unit) {
  if (has_uniform_metric(canvas)) return pack_uniform_stencil(canvas, length_unit);
  PackedStencils out;
  const std::size_t slots = canvas.slot_count();
  // Zeros with no pass over the pages (HugePageAllocator): the packing threads touch them first.
  out.records.resize(kStencilRecord * slots);
  const unsigned threads = slot_threads();
  std::vector<StencilPacker> packers(threads, StencilPacker(canvas, out, length_unit));
  for_slot_ranges(slots, threads, [&](unsigned t, std::size_t begin, std::size_t end) {
    for (std::size_t slot = begin; slot < end; ++slot) packers[t].pack(slot, slot);
  });
  const std::vector<std::vector<std::uint32_t>> global_index = merge_shapes(packers, out);
  for_slot_ranges(slots, threads, [&](unsigned t, std::size_t begin, std::size_t end) {
    for (std::size_t slot = begin; slot < end; ++slot)
      if (canvas.active[slot])
        store_shape_index(out.records, slot, global_index[t][out.shape_of(slot)]);
  });
  for (const StencilPacker& p : packers)
    for (int a = 0; a < 3; ++a) out.reach[a] = std::max(out.reach[a], p.reach[a]);
  return out;
}

namespace {

// For tests (RVOR_POISON_DEVICE_BUFFERS=1): new working buffers hold a byte pattern rather than
// the zeros PoCL's fresh host pages give, as a GPU's new buffers hold what was there before, so
// that a kernel reading what no command wrote shows up on PoCL too.
bool poison_new_buffers() {
  const char* value = std::getenv("RVOR_POISON_DEVICE_BUFFERS");
  return value != nullptr && std::string(value) == "1";
}

// Makes a canvas's buffers, each checked against the device's memory and counted in `bytes`.
class BufferMaker {
 public:
  BufferMaker(const cl::Context& context, std::uint64_t& bytes)
      : context_(context),
        memory_(device_memory(context)),
        host_memory_(device_uses_host_memory(context)),
        bytes_(bytes) {}

  // A read-only copy of `data`.
  template <typename Vector>
  cl::Buffer input(const Vector& data) {
    using T = typename Vector::value_type;
    const std::size_t size = data.size() * sizeof(T);
    count(size);
    if (size >= kHugePageBufferBytes && host_memory_)
      return huge_page_buffer(context_, CL_MEM_READ_ONLY, size, data.data());
    return cl::Buffer(context_, CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR, size,
                      const_cast<T*>(data.data()));
  }

  // A read-only buffer holding `data`: on its very memory where the device uses host memory.
  template <typename T>
  cl::Buffer adopt(HugePageVector<T>&& data) {
    const std::size_t size = data.size() * sizeof(T);
    if (size < kHugePageBufferBytes || !host_memory_) return input(data);
    count(size);
    return adopting_buffer(context_, CL_MEM_READ_ONLY, std::move(data));
  }

  // A working buffer of `size` bytes.
  cl::Buffer scratch(std::size_t size) {
    count(size);
    size = std::max<std::size_t>(size, 8);
    std::vector<unsigned char> poison;
    if (poison_new_buffers()) poison.assign(size, 0xA5);
    const void* initial = poison.empty() ? nullptr : poison.data();
    if (size >= kHugePageBufferBytes && host_memory_)
      return huge_page_buffer(context_, CL_MEM_READ_WRITE, size, initial);
    if (initial)
      return cl::Buffer(context_, CL_MEM_READ_WRITE | CL_MEM_COPY_HOST_PTR, size,
                        const_cast<void*>(initial));
    return cl::Buffer(context_, CL_MEM_READ_WRITE, size);
  }

 private:
  void count(std::size_t size) {
    require_room_for_buffer(memory_, bytes_, size);
    bytes_ += size;
  }

  const cl::Context& context_;
  const DeviceMemory memory_;
  const bool host_memory_;
  std::uint64_t& bytes_;
};

}  // namespace

namespace {

// A bit per slot, set where the slot is active (DeviceCanvas::activity).
std::vector<cl_uint> activity_bits(const Canvas& canvas) {
  std::vector<cl_uint> bits((canvas.slot_count() + 31) / 32, 0u);
  for (std::size_t slot = 0; slot < canvas.slot_count(); ++slot)
    if (canvas.active[slot]) bits[slot / 32] |= 1u << (slot % 32);
  return bits;
}

// The most bricks one round can list: the largest colour class (colour = parities of the brick
// coordinates, as brick_colour in kernels/propagation.cl), or every brick without colouring.
std::size_t largest_colour_class(const Canvas& canvas, int colours) {
  if (colours <= 1) return canvas.brick_count();
  std::vector<std::size_t> members(static_cast<std::size_t>(colours), 0);
  for (const VoxelIndex& o : canvas.brick_origins) {
    const int i = o.i / Canvas::kBrickEdge, j = o.j / Canvas::kBrickEdge;
    const int k = canvas.dimension == 3 ? o.k / canvas.brick_edge_z() : 0;
    ++members[static_cast<std::size_t>(((i & 1) | (j & 1) << 1 | (k & 1) << 2) % colours)];
  }
  return *std::max_element(members.begin(), members.end());
}

}  // namespace

double device_length_unit(const Canvas& canvas) {
  double log2_sum = 0.0;
  std::size_t count = 0;
  const std::size_t stride = std::max<std::size_t>(1, canvas.active_voxel_count / 4096);
  for (std::size_t slot = 0, active = 0; slot < canvas.slot_count(); ++slot) {
    if (!canvas.active[slot] || active++ % stride != 0) continue;
    const Mat3 G = canvas.metric_at(slot);
    const double trace = G(0, 0) + G(1, 1) + (canvas.dimension == 3 ? G(2, 2) : 0.0);
    log2_sum += std::log2(canvas.voxel_size * canvas.voxel_size * trace / canvas.dimension);
    ++count;
  }
  // sqrt of a power of four: the exponent of (h^2 tr G / d) halved and rounded.
  return count == 0 ? 1.0 : std::ldexp(1.0, static_cast<int>(std::lround(0.5 * log2_sum / count)));
}

int brick_colours(const Canvas& canvas, bool colouring) {
  return colouring ? (canvas.dimension == 3 ? 8 : 4) : 1;
}

DeviceCanvas upload_canvas(const cl::Context& context, const Canvas& canvas, int colours) {
  DeviceCanvas d;
  d.slots = canvas.slot_count();
  d.bricks = canvas.brick_count();
  if (d.bricks == 0) throw Error(kEmptyCanvasMessage);
  d.length_unit = device_length_unit(canvas);
  PackedStencils stencils = pack_stencils(canvas, d.length_unit);
  BufferMaker make(context, d.bytes);
  const int edges[3] = {Canvas::kBrickEdge, Canvas::kBrickEdge, canvas.brick_edge_z()};
  for (int a = 0; a < 3; ++a) {
    d.dims.s[a] = canvas.dims[a];
    d.grid.s[a] = canvas.brick_grid_dims[a];
    d.brick_reach.s[a] =
        canvas.dimension == 2 && a == 2 ? 0 : (stencils.reach[a] + edges[a] - 1) / edges[a];
  }
  std::vector<cl_int4> origins(d.bricks);
  for (std::size_t b = 0; b < d.bricks; ++b) {
    const VoxelIndex& o = canvas.brick_origins[b];
    origins[b] = {{o.i, o.j, o.k, 0}};
  }
  d.uniform_stencil = stencils.uniform;
  if (stencils.uniform) {
    for (std::size_t i = 0; i < kStencilTerms; ++i)
      if (stencils.records[i] > 0.0f)
        d.uniform_offsets.assign(stencils.shapes.begin(), stencils.shapes.begin() + 3 * (i + 1));
    d.uniform_diagonal = first_metric_is_diagonal(canvas);
  }
  d.activity = make.input(activity_bits(canvas));
  const std::vector<std::uint32_t> reaches = reader_reach(canvas, stencils);
  d.stencils = make.adopt(std::move(stencils.records));  // their last use is reader_reach's
  d.shapes = make.input(stencils.shapes);
  d.table = make.input(canvas.brick_table);
  d.origins = make.input(origins);
  d.state = make.scratch(d.slots * sizeof(cl_ulong));
  // A round relaxes one colour class, so the scratch holds 1/8 of the bricks (1/4 in 2D): this
  // pays for 32-bit stamps, which never need restarting within a solve, under 64 B per voxel.
  d.scratch_bricks = largest_colour_class(canvas, colours);
  d.scratch = make.scratch(d.scratch_bricks * canvas.brick_volume() * sizeof(cl_ulong));
  d.scratch_stamps = make.scratch(d.scratch_bricks * canvas.brick_volume() * sizeof(cl_uint));
  d.evaluated = make.scratch(d.slots * sizeof(cl_uint));
  d.changed = make.scratch(d.slots * sizeof(cl_uint));
  d.flags = make.scratch(d.bricks);
  d.touched = make.scratch(d.bricks);
  d.axis_readers = std::all_of(reaches.begin(), reaches.end(),
                               [](std::uint32_t r) { return (r & kAxisReaders) != 0; });
  d.reader_reach = make.input(reaches);
  d.news = make.scratch(d.bricks * sizeof(cl_uint));
  d.least_tentative = make.scratch(d.bricks * sizeof(cl_float));
  d.least_bits = make.scratch(sizeof(cl_uint));
  d.pending = make.scratch(d.bricks);
  d.round_counts = make.scratch(2 * sizeof(cl_int));
  d.list = make.scratch(d.bricks * sizeof(cl_int));
  d.update_counter = make.scratch(sizeof(cl_ulong));
  return d;
}

}  // namespace rvor::opencl
