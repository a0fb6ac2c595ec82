// SPDX-License-Identifier: Apache-2.0
#pragma once
/// @file
/// Disjoint sets of the integers 0 … n − 1 (union–find with path halving), for the pieces of
/// meshes and grids.
#include <cstddef>
#include <numeric>
#include <vector>

namespace rbfmuscle {

/// Each integer starts in a set of its own; join() merges two sets, find() names a set by its
/// root. Which element becomes the root depends only on the order of the calls.
class DisjointSets {
 public:
  explicit DisjointSets(std::size_t count) : parent_(count) { std::iota(parent_.begin(), parent_.end(), 0); }

  /// The root of x's set (halving the path on the way).
  int find(int x) {
    while (parent_[std::size_t(x)] != x) x = parent_[std::size_t(x)] = parent_[std::size_t(parent_[std::size_t(x)])];
    return x;
  }
  /// Merges the sets of a and b under b's root.
  void join(int a, int b) { parent_[std::size_t(find(a))] = find(b); }
  /// Number of elements.
  std::size_t size() const { return parent_.size(); }

 private:
  std::vector<int> parent_;
};

}  // namespace rbfmuscle
