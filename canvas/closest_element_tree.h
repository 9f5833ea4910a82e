#pragma once
// A bounding-volume hierarchy over a mesh's elements for closest-element queries from points
// outside the mesh (private to rvor_medit). A uniform grid searched ring by ring visits every
// empty bucket of a hole or of the space around the mesh; the tree skips them by their boxes.
#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <utility>
#include <vector>

#include "rvor/metric_field.h"

namespace rvor::detail {

class ClosestElementTree {
 public:
  // boxes[e]: element e's bounding box; elements whose box is empty (lo > hi) are left out.
  explicit ClosestElementTree(const std::vector<Box>& boxes) {
    for (std::size_t e = 0; e < boxes.size(); ++e)
      if ((boxes[e].lo.array() <= boxes[e].hi.array()).all())
        elements_.push_back(static_cast<int>(e));
    if (!elements_.empty()) build(boxes, 0, static_cast<int>(elements_.size()));
  }

  // The element nearest to p, `distance(e)` giving p's distance to element e; -1 without one.
  template <typename Distance>
  int closest(const Vec3& p, Distance distance) const {
    int best = -1;
    double best_distance = std::numeric_limits<double>::infinity();
    if (nodes_.empty()) return best;
    // A stack on the call's own frame: queries run per voxel, a heap allocation each would cost
    // more than the search. The tree is balanced, so its depth stays below 64.
    // Each node with its box's distance to p, computed once when its parent is expanded.
    std::pair<int, double> stack[2 * kMaxDepth];
    int size = 0;
    stack[size++] = {0, box_distance(p, nodes_[0].box)};
    while (size > 0) {
      const auto [index, node_distance] = stack[--size];
      const Node& node = nodes_[static_cast<std::size_t>(index)];
      if (best >= 0 && node_distance >= best_distance) continue;
      if (node.count > 0) {
        for (int n = node.first; n < node.first + node.count; ++n) {
          const int e = elements_[static_cast<std::size_t>(n)];
          const double d = distance(e);
          // A NaN distance (overflow) still names an element, and any number replaces it.
          if (best < 0 || d < best_distance || std::isnan(best_distance))
            best = e, best_distance = d;
        }
        continue;
      }
      const double left = box_distance(p, nodes_[node.left].box);
      const double right = box_distance(p, nodes_[node.right].box);
      // The nearer one on top.
      stack[size++] = left < right ? std::pair{node.right, right} : std::pair{node.left, left};
      stack[size++] = left < right ? std::pair{node.left, left} : std::pair{node.right, right};
    }
    return best;
  }

 private:
  struct Node {
    Box box;
    int first = 0, count = 0;  // a leaf's elements_[first, first + count); count 0: inner
    int left = -1, right = -1;
  };
  static constexpr int kLeafSize = 4;
  static constexpr int kMaxDepth = 64;  // median splits: log2(elements) levels

  static double box_distance(const Vec3& p, const Box& box) {
    return (box.lo - p).cwiseMax(p - box.hi).cwiseMax(0.0).norm();
  }

  // Builds the node over elements_[first, first + count) (split at the median centre along the
  // longest axis of the centres); returns its index.
  int build(const std::vector<Box>& boxes, int first, int count) {
    const int index = static_cast<int>(nodes_.size());
    nodes_.emplace_back();
    Box box{Vec3::Constant(std::numeric_limits<double>::infinity()),
            Vec3::Constant(-std::numeric_limits<double>::infinity())};
    Box centres = box;
    for (int n = first; n < first + count; ++n) {
      const Box& b = boxes[static_cast<std::size_t>(elements_[static_cast<std::size_t>(n)])];
      box.lo = box.lo.cwiseMin(b.lo), box.hi = box.hi.cwiseMax(b.hi);
      const Vec3 centre = 0.5 * (b.lo + b.hi);
      centres.lo = centres.lo.cwiseMin(centre), centres.hi = centres.hi.cwiseMax(centre);
    }
    nodes_[static_cast<std::size_t>(index)].box = box;
    if (count <= kLeafSize) {
      nodes_[static_cast<std::size_t>(index)].first = first;
      nodes_[static_cast<std::size_t>(index)].count = count;
      return index;
    }
    int axis = 0;
    (centres.hi - centres.lo).maxCoeff(&axis);
    const auto begin = elements_.begin() + first;
    std::nth_element(begin, begin + count / 2, begin + count, [&](int a, int b) {
      return boxes[static_cast<std::size_t>(a)].lo[axis] +
                 boxes[static_cast<std::size_t>(a)].hi[axis] <
             boxes[static_cast<std::size_t>(b)].lo[axis] +
                 boxes[static_cast<std::size_t>(b)].hi[axis];
    });
    const int left = build(boxes, first, count / 2);
    const int right = build(boxes, first + count / 2, count - count / 2);
    nodes_[static_cast<std::size_t>(index)].left = left;
    nodes_[static_cast<std::size_t>(index)].right = right;
    return index;
  }

  std::vector<int> elements_;
  std::vector<Node> nodes_;
};

}  // namespace rvor::detail
