// SPDX-License-Identifier: Apache-2.0
#pragma once
/// @file
/// Sorting small index lists into ascending order, fast: the rbf sums run in
/// ascending centre index so that every evaluation path gives bitwise the
/// same result.
#include <algorithm>
#include <cstdint>
#include <vector>

namespace rbfmuscle {

/// Sorts distinct indices in [0, bound) ascending. Long lists go through a
/// thread-local bitset of `bound` bits (O(bound/64 + size)); short ones through
/// std::sort. The indices must be distinct (a duplicate would be dropped).
inline void sortAscendingIndices(std::vector<int>& indices, int bound) {
  const std::size_t n = indices.size();
  const std::size_t words = (static_cast<std::size_t>(bound) + 63) / 64;
  if (n < 32 || words > 4 * n) {
    std::sort(indices.begin(), indices.end());
    return;
  }
  thread_local std::vector<std::uint64_t> bits;
  if (bits.size() < words) bits.resize(words, 0);
  for (int i : indices) bits[static_cast<std::size_t>(i) >> 6] |= std::uint64_t{1} << (i & 63);
  std::size_t out = 0;
  for (std::size_t w = 0; w < words && out < n; ++w) {
    std::uint64_t word = bits[w];
    bits[w] = 0;
    while (word != 0) {
      indices[out++] = static_cast<int>(w * 64 + static_cast<std::size_t>(__builtin_ctzll(word)));
      word &= word - 1;
    }
  }
}

}  // namespace rbfmuscle
