#pragma once
// Moving a VoronoiField between the host and the device state words (internal), and the hash the
// engine uses to recognise the field it returned last.
#include <cstddef>
#include <cstdint>
#include <functional>
#include <vector>

#include "opencl_runtime.h"
#include "rvor/propagation.h"

namespace rvor::opencl {

constexpr cl_ulong kInfiniteState = 0x7F8000007FFFFFFFull;  // +inf, no label (state_word.clh)

// Sum over slots of a bijective mix of (slot, distance bits, label): two fields that differ in
// one slot always hash differently, and the hash follows a change of some slots in time
// proportional to them.
std::uint64_t field_hash(const VoronoiField& field);

// field_hash and, in the same pass, whether some slot fails insertable_slot (rvor/propagation.h)
// for `solved_seeds` seeds (require_insertable_field then names it).
struct FieldDigest {
  std::uint64_t hash = 0;
  bool faulty = false;
};
FieldDigest digest_field(const VoronoiField& field, std::size_t solved_seeds);

// The device holds distances in units of length_unit (DeviceCanvas), a power of two: the
// conversions are exact.
void upload_field(const cl::CommandQueue& queue, const cl::Buffer& state, const VoronoiField& field,
                  double length_unit);

// The whole device state into `field`; returns its field_hash.
std::uint64_t download_field(const cl::CommandQueue& queue, const cl::Buffer& state,
                             std::size_t slots, double length_unit, VoronoiField& field);

// Reads the device states of the listed bricks, brick_volume words each in list order, into
// `words` (sized for them).
using BrickReader = std::function<void(const std::vector<cl_int>& bricks, cl_ulong* words)>;

// Only the bricks whose `touched` byte is set (brick_volume slots each) into `field`, which held
// the rest of the device state already and hashed to `hash`; returns the new field_hash. Falls
// back to download_field when more than a quarter of the bricks were touched.
std::uint64_t download_touched_bricks(const cl::CommandQueue& queue, const cl::Buffer& state,
                                      const cl::Buffer& touched, std::size_t bricks,
                                      std::size_t brick_volume, std::uint64_t hash,
                                      double length_unit, const BrickReader& read_bricks,
                                      VoronoiField& field);

}  // namespace rvor::opencl
