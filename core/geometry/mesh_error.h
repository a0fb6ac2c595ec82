// SPDX-License-Identifier: Apache-2.0
#pragma once
/// @file
/// Exception type of the geometry layer.
#include <stdexcept>
#include <string>

namespace rbfmuscle {

/// Thrown for any mesh that cannot be read, written or used; the message names the
/// file (or source name) and the problem, e.g. "iliacus.ply: 12 boundary edges — ...".
class MeshError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

}  // namespace rbfmuscle
