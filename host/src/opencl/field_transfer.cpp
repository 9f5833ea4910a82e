#include "field_transfer.h"

#include <cstring>
#include <vector>

#include "../slot_hash.h"
#include "../slot_ranges.h"

namespace rvor::opencl {
namespace {

constexpr std::uint32_t kLabelNone = 0x7FFFFFFFu;

std::uint64_t state_word(float distance, int32_t label) {
  std::uint32_t bits;
  std::memcpy(&bits, &distance, sizeof bits);
  return (std::uint64_t{bits} << 32) | static_cast<std::uint32_t>(label);
}

std::uint64_t slot_hash(std::size_t slot, const float* distance, const std::int32_t* label) {
  return indexed_word_hash(slot, state_word(distance[slot], label[slot]));
}

std::uint64_t field_slot_hash(const VoronoiField& field, std::size_t slot) {
  return slot_hash(slot, field.distance.data(), field.label.data());
}

void store_word(cl_ulong word, std::size_t slot, float length_unit, VoronoiField& field) {
  const std::uint32_t bits = static_cast<std::uint32_t>(word >> 32);
  std::memcpy(&field.distance[slot], &bits, sizeof bits);
  field.distance[slot] *= length_unit;
  const std::uint32_t label = static_cast<std::uint32_t>(word) & kLabelNone;
  field.label[slot] = label == kLabelNone ? -1 : static_cast<int32_t>(label);
}

// The state words, mapped for reading while it lives (unmapped however the scope ends).
class MappedStates {
 public:
  MappedStates(const cl::CommandQueue& queue, const cl::Buffer& state, std::size_t slots)
      : queue_(queue),
        state_(state),
        words_(static_cast<cl_ulong*>(
            queue.enqueueMapBuffer(state, CL_TRUE, CL_MAP_READ, 0, slots * sizeof(cl_ulong)))) {}
  MappedStates(const MappedStates&) = delete;
  MappedStates& operator=(const MappedStates&) = delete;
  // A destructor must not throw; the words were read already, so a failed unmap loses nothing
  // (the next command on the queue reports a broken device).
  ~MappedStates() {
    try {
      queue_.enqueueUnmapMemObject(state_, words_);
      queue_.finish();
    } catch (...) {
    }
  }
  const cl_ulong* words() const { return words_; }

 private:
  const cl::CommandQueue& queue_;
  const cl::Buffer& state_;
  cl_ulong* words_;
};

// The sum of the slot hashes of [begin, end) and whether a slot fails insertable_slot
// (rvor/propagation.h) for `solved_seeds`. An insertion digests the caller's whole field (16.8M
// slots at 256^3), so this loop is cloned for AVX2 (slot_hash.h), where it vectorises its 64-bit
// multiplications (`build/bin/bench_slot_hashes` times it).
RVOR_CLONED_FOR_AVX2 FieldDigest digest_slots(const float* distance, const std::int32_t* label,
                                              std::size_t solved_seeds, std::size_t begin,
                                              std::size_t end) {
  std::uint64_t sum = 0;
  std::uint32_t insertable = 1;
  for (std::size_t slot = begin; slot < end; ++slot) {
    sum += slot_hash(slot, distance, label);
    insertable &= insertable_slot(distance[slot], label[slot], solved_seeds);
  }
  return {sum, insertable == 0};
}

}  // namespace

FieldDigest digest_field(const VoronoiField& field, std::size_t solved_seeds) {
  FieldDigest total;
  for (const FieldDigest& p :
       over_slot_ranges(field.distance.size(), [&](std::size_t begin, std::size_t end) {
         return digest_slots(field.distance.data(), field.label.data(), solved_seeds, begin, end);
       })) {
    total.hash += p.hash;
    total.faulty = total.faulty || p.faulty;
  }
  return total;
}

std::uint64_t field_hash(const VoronoiField& field) {
  return digest_field(field, 0).hash;
}

void upload_field(const cl::CommandQueue& queue, const cl::Buffer& state, const VoronoiField& field,
                  double length_unit) {
  const float unit = static_cast<float>(length_unit);
  std::vector<cl_ulong> words(field.distance.size());
  for (std::size_t n = 0; n < words.size(); ++n)
    words[n] =
        field.label[n] < 0 ? kInfiniteState : state_word(field.distance[n] / unit, field.label[n]);
  queue.enqueueWriteBuffer(state, CL_TRUE, 0, words.size() * sizeof(cl_ulong), words.data());
}

// The state is mapped rather than read into a copy: on a device that uses host memory (PoCL on
// the CPU) the words are read in place, and the conversion runs on every core.
std::uint64_t download_field(const cl::CommandQueue& queue, const cl::Buffer& state,
                             std::size_t slots, double length_unit, VoronoiField& field) {
  const float unit = static_cast<float>(length_unit);
  field.distance.resize(slots);
  field.label.resize(slots);
  const MappedStates mapped(queue, state, slots);
  return sum_over_slots(slots, [&](std::size_t slot) {
    store_word(mapped.words()[slot], slot, unit, field);
    return field_slot_hash(field, slot);
  });
}

std::uint64_t download_touched_bricks(const cl::CommandQueue& queue, const cl::Buffer& state,
                                      const cl::Buffer& touched, std::size_t bricks,
                                      std::size_t brick_volume, std::uint64_t hash,
                                      double length_unit, const BrickReader& read_bricks,
                                      VoronoiField& field) {
  std::vector<cl_uchar> marks(bricks);
  queue.enqueueReadBuffer(touched, CL_TRUE, 0, bricks, marks.data());
  std::vector<cl_int> listed;
  for (std::size_t b = 0; b < bricks; ++b)
    if (marks[b]) listed.push_back(static_cast<cl_int>(b));
  // Beyond a quarter of the canvas, one read of everything costs less than packing the bricks.
  if (4 * listed.size() > bricks)
    return download_field(queue, state, bricks * brick_volume, length_unit, field);
  std::vector<cl_ulong> words(listed.size() * brick_volume);
  read_bricks(listed, words.data());
  for (std::size_t n = 0; n < listed.size(); ++n) {
    for (std::size_t v = 0; v < brick_volume; ++v) {
      const std::size_t slot = static_cast<std::size_t>(listed[n]) * brick_volume + v;
      hash -= field_slot_hash(field, slot);
      store_word(words[n * brick_volume + v], slot, static_cast<float>(length_unit), field);
      hash += field_slot_hash(field, slot);
    }
  }
  return hash;
}

}  // namespace rvor::opencl
