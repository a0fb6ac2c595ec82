// SPDX-License-Identifier: Apache-2.0
#pragma once
/// @file
/// Halton low-discrepancy points: even, deterministic cover of a box.
#include <Eigen/Core>
#include <Eigen/Geometry>

#include <cstdint>

namespace rbfmuscle {

/// Radical inverse of `index` in `base`: the base-b digits of index mirrored
/// about the radix point, in [0, 1).
double calcRadicalInverse(std::uint64_t index, int base);

/// `count` Halton(2,3,5) points in `box_mm` (3×count, mm): point k is
/// box.min + (φ₂(k), φ₃(k), φ₅(k)) ⊙ box.sizes() for k = first_index + 1 … .
/// Different `first_index` give disjoint stretches of the same sequence.
Eigen::Matrix3Xd makeHaltonPoints(const Eigen::AlignedBox3d& box_mm, int count,
                                  std::uint64_t first_index = 0);

}  // namespace rbfmuscle
