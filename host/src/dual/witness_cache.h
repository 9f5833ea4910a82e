#pragma once
// A small open-addressing table that accumulates the witnesses of one brick per Delaunay simplex
// before they reach the thread's SimplexMap: a brick holds a few dozen distinct simplices but
// witnesses each of them hundreds of times, and every witness going through the large map cost
// a cache miss. Flushing merges each entry once (SimplexMap::merge_simplex); merging is
// order-independent, so the nerve is the same as with direct adds.
#include <array>
#include <cstdint>
#include <vector>

#include "dual/simplex_map.h"

namespace rvor::dual {

class WitnessCache {
 public:
  WitnessCache() : entries_(kCapacity), occupied_(kCapacity, 0) { used_.reserve(kCapacity); }

  // Adds a witness of the simplex on the sorted seeds key[0..size); flushes into `out` when the
  // table is half full (bricks with many distinct simplices: seeds denser than voxels).
  void add(const std::array<int32_t, 4>& key, int size, const Witness& w, SimplexMap& out) {
    // Neighbouring canvas simplices mostly witness the same Delaunay simplex: try it first.
    std::size_t i = last_;
    if (!occupied_[i] || entries_[i].seeds != key) {
      i = SeedKeyHash{}(key) & (kCapacity - 1);
      while (occupied_[i] && entries_[i].seeds != key) i = (i + 1) & (kCapacity - 1);
      last_ = i;
    }
    NerveSimplex& s = entries_[i];
    if (occupied_[i]) {
      if (witness_less(s.farthest, w)) s.farthest = w;
      if (witness_less(w, s.nearest)) s.nearest = w;
      ++s.witness_count;
      return;
    }
    occupied_[i] = 1;
    used_.push_back(static_cast<uint32_t>(i));
    s.seeds = key;
    s.vertex_count = size;
    s.farthest = s.nearest = w;
    s.witness_count = 1;
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
  static constexpr std::size_t kCapacity = 1024;  // a power of two
  std::vector<NerveSimplex> entries_;
  std::vector<uint8_t> occupied_;
  std::vector<uint32_t> used_;
  std::size_t last_ = 0;
};

}  // namespace rvor::dual
