#pragma once
// Accumulates witnesses per Delaunay simplex (keyed by its sorted seeds) during nerve extraction.
// One map per scanning thread; merging is order-independent (ties broken by slot, then position),
// so the nerve does not depend on the thread schedule.
#include <algorithm>
#include <array>
#include <cstdint>
#include <tuple>
#include <unordered_map>
#include <vector>

#include "rvor/nerve.h"

namespace rvor::dual {

struct SeedKeyHash {
  std::size_t operator()(const std::array<int32_t, 4>& k) const {
    uint64_t h = 1469598103934665603ull;
    for (int32_t v : k) h = (h ^ static_cast<uint32_t>(v)) * 1099511628211ull;
    return static_cast<std::size_t>(h ^ (h >> 29));
  }
};

// Key equality without memcmp (std::array's operator== calls it; keys are compared millions of
// times).
inline bool same_seeds(const std::array<int32_t, 4>& a, const std::array<int32_t, 4>& b) {
  return ((a[0] ^ b[0]) | (a[1] ^ b[1]) | (a[2] ^ b[2]) | (a[3] ^ b[3])) == 0;
}

struct SeedKeyEqual {
  bool operator()(const std::array<int32_t, 4>& a, const std::array<int32_t, 4>& b) const {
    return same_seeds(a, b);
  }
};

// Strict order on witnesses: distance, then slot, then position (deterministic merges).
inline bool witness_less(const Witness& a, const Witness& b) {
  if (a.distance != b.distance) return a.distance < b.distance;
  if (a.slot != b.slot) return a.slot < b.slot;
  return std::lexicographical_compare(a.position.data(), a.position.data() + 3, b.position.data(),
                                      b.position.data() + 3);
}

class SimplexMap {
 public:
  using Map = std::unordered_map<std::array<int32_t, 4>, NerveSimplex, SeedKeyHash, SeedKeyEqual>;

  void add_degenerate(DegenerateWitness w) {
    ++degenerate_count_;
    degenerate_.push_back(std::move(w));
  }

  // Merges the witnesses accumulated elsewhere for one simplex.
  void merge_simplex(const NerveSimplex& s) {
    auto [it, inserted] = map_.try_emplace(s.seeds, s);
    if (inserted) return;
    NerveSimplex& mine = it->second;
    if (witness_less(mine.farthest, s.farthest)) mine.farthest = s.farthest;
    if (witness_less(s.nearest, mine.nearest)) mine.nearest = s.nearest;
    mine.witness_count += s.witness_count;
  }

  void merge(const SimplexMap& other) {
    for (const auto& entry : other.map_) merge_simplex(entry.second);
    degenerate_count_ += other.degenerate_count_;
    degenerate_.insert(degenerate_.end(), other.degenerate_.begin(), other.degenerate_.end());
  }

  const Map& simplices() const { return map_; }
  std::size_t degenerate_count() const { return degenerate_count_; }

  // The first `limit` degenerate cells in index order (k, j, i).
  std::vector<DegenerateWitness> take_degenerate(std::size_t limit) {
    std::sort(degenerate_.begin(), degenerate_.end(),
              [](const DegenerateWitness& a, const DegenerateWitness& b) {
                return std::tie(a.cell_base.k, a.cell_base.j, a.cell_base.i) <
                       std::tie(b.cell_base.k, b.cell_base.j, b.cell_base.i);
              });
    if (degenerate_.size() > limit) degenerate_.resize(limit);
    return std::move(degenerate_);
  }

 private:
  Map map_;
  std::size_t degenerate_count_ = 0;
  std::vector<DegenerateWitness> degenerate_;
};

}  // namespace rvor::dual
