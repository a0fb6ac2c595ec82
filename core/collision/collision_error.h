// SPDX-License-Identifier: Apache-2.0
#pragma once
/// @file
/// Exception type of the collision layer.
#include <stdexcept>
#include <string>

namespace rbfmuscle {

/// Thrown when a bone cannot be used for contact queries or a query is malformed; the
/// message names the bone (or argument) and what was expected, e.g.
/// "BoneSet: bone 'femur_r': mesh has no triangles".
class CollisionError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

}  // namespace rbfmuscle
