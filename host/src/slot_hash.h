#pragma once
// Summable hashes of per-slot data (internal): a canvas's contents (Canvas::finalize) and the
// field the OpenCL engine holds. Each word is mixed with its index and the mixes are summed, so
// two inputs that differ in one word always hash differently, threads may sum ranges in any
// order, and a change of some words updates the sum in time proportional to them.
#include <cstdint>

// A loop summing indexed_word_hash vectorises its 64-bit multiplies with AVX2 only: on x86-64
// such a function is cloned for it (chosen at load time). Elsewhere, or where the compiler has no
// target_clones, it is one plain function.
#if defined(__x86_64__) && defined(__has_attribute)
#if __has_attribute(target_clones)
#define RVOR_CLONED_FOR_AVX2 __attribute__((target_clones("avx2", "default")))
#endif
#endif
#ifndef RVOR_CLONED_FOR_AVX2
#define RVOR_CLONED_FOR_AVX2
#endif

namespace rvor {

// For a fixed index a bijection of the word: an xor with an index key, a multiplication by an odd
// constant and a xorshift, each invertible. (splitmix64's finaliser, two multiplications and
// xorshifts more, made an insertion's digest of the caller's 16.8M slots 7.2 ms against 4.6 ms on
// two cores here: `build/bin/bench_slot_hashes`, docs/scheme.md "A cheaper mix".)
inline std::uint64_t indexed_word_hash(std::uint64_t index, std::uint64_t word) {
  const std::uint64_t x = (word ^ (index * 0x9E3779B97F4A7C15ull)) * 0xBF58476D1CE4E5B9ull;
  return x ^ (x >> 32);
}

}  // namespace rvor
