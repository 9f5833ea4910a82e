#pragma once
// A small open-addressing table that accumulates witnesses per Delaunay simplex before they reach
// the thread's SimplexMap: a brick holds a few dozen distinct simplices but witnesses each of
// them hundreds of times, and neighbouring bricks (a thread takes them roughly in order) share
// most of them; every witness going through the large map cost a cache miss. It is flushed when
// half full, merging each entry once (SimplexMap::merge_simplex); merging is order-independent,
// so the nerve is the same as with direct adds.
#include <array>
#include <cstdint>
#include <vector>

#include "dual/simplex_map.h"

namespace rvor::dual {

class WitnessCache {
 public:
  WitnessCache() : entries_(kCapacity), occupied_(kCapacity, 0) { used_.reserve(kCapacity); }

  // Merges witnesses of the simplex s.seeds (s.witness_count of them, the extremes in s.farthest
  // and s.nearest); flushes into `out` when the table is half full.
  void merge(const NerveSimplex& s, SimplexMap& out) {
    // Neighbouring canvas simplices mostly witness the same Delaunay simplex: try it first.
    std::size_t i = last_;
    if (!occupied_[i] || !same_seeds(entries_[i].seeds, s.seeds)) {
      i = SeedKeyHash{}(s.seeds) & (kCapacity - 1);
      while (occupied_[i] && !same_seeds(entries_[i].seeds, s.seeds)) i = (i + 1) & (kCapacity - 1);
      last_ = i;
    }
    NerveSimplex& mine = entries_[i];
    if (occupied_[i]) {
      if (witness_less(mine.farthest, s.farthest)) mine.farthest = s.farthest;
      if (witness_less(s.nearest, mine.nearest)) mine.nearest = s.nearest;
      mine.witness_count += s.witness_count;
      return;
    }
    occupied_[i] = 1;
    used_.push_back(static_cast<uint32_t>(i));
    mine = s;
    if (used_.size() * 2 >= kCapacity) flush(out);
  }

  void flush(SimplexMap& out) {
    for (uint32_t i : used_) {
      out.merge_simplex(entries_[i]);
      occupied_[i] = 0;
    }
    used_.clear();
  }

 private:
  static constexpr std::size_t kCapacity = 4096;  // a power of two; ~0.5 MB of entries
  std::vector<NerveSimplex> entries_;
  std::vector<uint8_t> occupied_;
  std::vector<uint32_t> used_;
  std::size_t last_ = 0;
};

}  // namespace rvor::dual
