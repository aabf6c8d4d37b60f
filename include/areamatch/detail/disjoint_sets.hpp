#pragma once
/// \file detail/disjoint_sets.hpp
/// Union-find over 0…n−1, the one that segmentation (pieces of a label, connected components),
/// assessment (rigid pieces) and merging (maps joined by accepted matches) share.

#include <algorithm>
#include <cstddef>
#include <numeric>
#include <vector>

namespace areamatch::detail {

/// Disjoint sets with path halving. `join` makes the smaller root the root of both, so which
/// element ends up as a set's root does not depend on the order of the joins (deterministic
/// labels); `attach` lets a caller that chooses the survivor itself make one root the other's child.
class DisjointSets {
 public:
  explicit DisjointSets(std::size_t n) : parent_(n) { std::iota(parent_.begin(), parent_.end(), std::size_t{0}); }

  std::size_t find(std::size_t i) {
    while (parent_[i] != i) i = parent_[i] = parent_[parent_[i]];
    return i;
  }

  /// Joins the sets of a and b; false when they were one already.
  bool join(std::size_t a, std::size_t b) {
    a = find(a);
    b = find(b);
    if (a == b) return false;
    parent_[std::max(a, b)] = std::min(a, b);
    return true;
  }

  /// Makes root `root` a child of root `onto` (both must be roots).
  void attach(std::size_t root, std::size_t onto) { parent_[root] = onto; }

 private:
  std::vector<std::size_t> parent_;
};

}  // namespace areamatch::detail
