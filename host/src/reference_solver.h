#pragma once
// The sequential CPU reference of docs/scheme.md in double precision (private to rvor_solver; the
// solver tests use it directly to compare fields at full precision). The public entry point is
// make_reference_propagator() in rvor/propagation.h, which wraps this class.
#include <cstdint>
#include <vector>

#include "rvor/canvas.h"
#include "rvor/propagation.h"

namespace rvor::detail {

// Per canvas slot, like VoronoiField but in double: +inf / -1 where unreached or inactive.
struct ExactField {
  std::vector<double> distance;
  std::vector<int32_t> label;
};

// Stencil of one active voxel, with the offsets stored as the kernels store them (int8).
struct VoxelStencil {
  int8_t size = 0;
  int8_t offset[6][3] = {};
  double weight[6] = {};
};

class ReferenceSolver {
 public:
  // Precomputes, once per canvas, the Selling stencil of every active voxel, its stencil
  // neighbours and the reverse stencil graph (who has me in their stencil), as CSR.
  explicit ReferenceSolver(const Canvas& canvas);

  // `canvas` must be the one given to the constructor. Seed i gets label i.
  PropagationStats solve(const Canvas& canvas, const std::vector<Vec3>& seeds, ExactField& field);
  // Adds seeds[first_new..] to `field`, solved for seeds[0..first_new).
  PropagationStats insert(const Canvas& canvas, const std::vector<Vec3>& seeds,
                          std::size_t first_new, ExactField& field);

 private:
  struct Seed {
    Vec3 position;
    Mat3 G;  // metric of the voxel containing the seed
  };
  struct QueueEntry {
    double value;
    int32_t voxel;
    bool operator>(const QueueEntry& other) const { return value > other.value; }
  };

  void compute_stencils(const Canvas& canvas);
  void compute_neighbours(const Canvas& canvas);
  void compute_reverse_graph();

  void load_seeds(const Canvas& canvas, const std::vector<Vec3>& seeds);
  void load_field(const ExactField& field);
  void store_field(ExactField& field) const;
  void initialise_seed_blocks(const Canvas& canvas, std::size_t first_seed);
  void run_queue(PropagationStats& stats);

  bool offer(int32_t voxel, double value, int32_t label);
  double local_solve(int32_t voxel, int32_t label) const;
  Vec3 position_of(int32_t voxel) const {
    const VoxelIndex& x = index_of_voxel_[voxel];
    return origin_ + h_ * Vec3(x.i, x.j, x.k);
  }

  // Canvas geometry.
  int dimension_ = 3;
  double h_ = 0;
  Vec3 origin_ = Vec3::Zero();
  std::size_t slot_count_ = 0;

  // Active voxels are numbered 0..n-1 ("voxel ids"); everything below is indexed by them.
  std::vector<int32_t> voxel_of_slot_;  // -1 for inactive slots
  std::vector<int32_t> slot_of_voxel_;
  std::vector<VoxelIndex> index_of_voxel_;
  std::vector<VoxelStencil> stencils_;     // distinct stencils (uniform regions share one)
  std::vector<int32_t> stencil_of_voxel_;  // index into stencils_
  std::vector<int32_t> neighbour_;  // 12 per voxel: x + e_t at 2t, x - e_t at 2t + 1; -1 missing
  std::vector<int64_t> reverse_begin_;  // CSR: voxels having x in their stencil
  std::vector<int32_t> reverse_;

  // State of the current solve. Value and label side by side: the local solve reads both for up
  // to 12 scattered neighbours, and the run time is dominated by those memory accesses.
  struct VoxelState {
    double value;
    int32_t label;
  };
  std::vector<Seed> seeds_;
  std::vector<VoxelState> state_;
  std::vector<QueueEntry> queue_;  // binary min-heap (std::push_heap with greater)
};

}  // namespace rvor::detail
