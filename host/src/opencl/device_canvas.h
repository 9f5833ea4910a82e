#pragma once
// The canvas packed for an OpenCL device (internal). Per slot: the state word (distance bits,
// label), two 32-bit evaluation stamps, the Selling stencil precomputed on the host (6 float
// weights rho_i / h^2 and the index of its int8 offsets in a table of the canvas's distinct
// offset sets; one stencil for the whole canvas when the metric is uniform) and an activity bit.
// A scratch copy of each brick being relaxed, states and change stamps: one colour class of bricks
// at a time. Per brick: origin, flags, activation, list, a touched mark.
#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>

#include "host_pages.h"
#include "opencl_runtime.h"
#include "rvor/canvas.h"

namespace rvor::opencl {

constexpr int kStencilTerms = 6;
// Words of a slot's stencil record: the weights, then its shape index (load_stencil,
// kernels/eikonal_scheme.clh).
constexpr int kStencilRecord = kStencilTerms + 1;

// The Selling stencils of every slot, in the device layout, or a single one when every active
// voxel has the same metric (bit for bit; the kernels are then built with UNIFORM_METRIC and read
// stencil 0). Inactive slots: all-zero weights, shape 0.
struct PackedStencils {
  // kStencilRecord words per slot: kStencilTerms float weights, then the uint32 index of the
  // slot's offsets in `shapes`. Large ones are packed on huge pages, which the device buffer of a
  // CPU device then takes over (upload_canvas): no second copy.
  HugePageVector<float> records;
  std::vector<std::int8_t> shapes;  // 3 * kStencilTerms per distinct offset set
  std::array<int, 3> reach{};       // largest |offset| per axis, in voxels
  bool uniform = false;

  std::size_t shape_count() const { return shapes.size() / (3 * kStencilTerms); }
  std::uint32_t shape_of(std::size_t slot) const;
  // Offset a (0, 1, 2 for x, y, z) of stencil term i at `slot`.
  int offset(std::size_t slot, int i, int a) const;
};

// Throws rvor::Error when an offset does not fit in int8 (anisotropy too large for the canvas).
// The weights are rho_i (length_unit / h)^2: distances in units of length_unit.
PackedStencils pack_stencils(const Canvas& canvas, double length_unit);

// The unit of the device's distances: a power of two near the metric length of one voxel step,
// h sqrt(tr G / d) averaged in log over the canvas. The float solve then works with numbers near
// the voxel counts whatever the metric's and the domain's units (world units overflowed float at
// a domain of 1e13 or a metric scale of 1e12, and underflowed at 1e-9), and its results are those
// in world units scaled by a power of two, which is exact: the same bits.
double device_length_unit(const Canvas& canvas);

struct DeviceCanvas {
  std::size_t slots = 0, bricks = 0;
  double length_unit = 1.0;               // device distances are world distances / length_unit
  cl_int4 dims{}, grid{}, brick_reach{};  // brick_reach: bricks within stencil reach per axis
  cl::Buffer state, scratch, stencils, shapes, table, origins;  // stencils, shapes: PackedStencils
  std::size_t scratch_bricks = 0;                               // the bricks the scratch holds
  cl::Buffer scratch_stamps;  // the change stamps of the scratch's bricks (commit_bricks)
  cl::Buffer activity;        // a bit per slot (bit s % 32 of word s / 32): active
  // One stencil for the whole canvas (every active voxel has the same metric): the kernels must
  // be built with UNIFORM_METRIC.
  bool uniform_stencil = false;
  // That stencil's offsets (x, y, z per term, up to its last term of non-zero weight).
  std::vector<int> uniform_offsets;
  // The uniform metric has no off-diagonal entries (brick_lanes' axis form relies on it).
  bool uniform_diagonal = false;
  cl::Buffer flags, list, update_counter, seeds;
  // Per brick: waiting for its colour's round (kernels/propagation.cl). round_counts: two ints,
  // how many bricks the round's list found and whether any brick waits (one fill and one read
  // per round: on a GPU each command is a few microseconds of a round).
  cl::Buffer pending, round_counts;
  // brick_sweep work avoidance: per slot, stamps of the last evaluation and the last change.
  cl::Buffer evaluated, changed;
  // Per brick: written since the solve or insertion began (only those are read back after an
  // insertion).
  cl::Buffer touched;
  // Per brick: how far the stencils reading its voxels reach (reader_reach.h), and the bricks
  // around that read a value its last relaxation changed (kernels/brick_layout.clh, brick_news),
  // so that only those become pending.
  cl::Buffer reader_reach, news;
  // Every stencil reading any voxel has axis offsets only (a diagonal metric, uniform or not).
  bool axis_readers = false;
  // Front stepping (brick_lanes): per brick, the least tentative distance its last relaxation
  // left (+inf: none); the least over all bricks as float bits (least_tentative_of).
  cl::Buffer least_tentative, least_bits;
  std::size_t seed_capacity = 0;
  std::uint64_t bytes = 0;  // device memory allocated for this canvas
};

// How many brick colours are relaxed in turn: 2^dimension with colouring (OpenCLOptions), else 1.
int brick_colours(const Canvas& canvas, bool colouring);

// colours: the brick colours relaxed in turn (1, 4 or 8); the scratch holds the largest class.
DeviceCanvas upload_canvas(const cl::Context& context, const Canvas& canvas, int colours);

}  // namespace rvor::opencl
