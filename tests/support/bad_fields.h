#pragma once
// Fields that no solve returns, for checking that insert() refuses them with a clear error; and a
// metric no engine can solve.
#include <cstddef>
#include <vector>

#include "rvor/propagation.h"

namespace rvor::test {

// Expects engine.insert(canvas, seeds, first_new, f) to throw an rvor::Error naming the slot, for
// copies f of `solved` (solved for seeds[0..first_new), first_new >= 1) with one labelled slot
// corrupted in turn: a label of a new seed, a label far past the seeds, label -2, a NaN distance,
// a negative distance, no label under a finite distance, a label under +inf.
void expect_corrupted_fields_refused(Propagator& engine, const Canvas& canvas,
                                     const std::vector<Vec3>& seeds, std::size_t first_new,
                                     const VoronoiField& solved);

// Expects engine.solve to refuse a uniform 2D metric of anisotropy 1e4 whose Selling stencil has an
// offset of 167 voxels (past the int8 both engines store), naming the voxel and why; the engines'
// own checks gave neither, and library callers reach them without the CLI's earlier ones.
void expect_offsets_past_int8_refused(Propagator& engine);

}  // namespace rvor::test
