// SPDX-License-Identifier: Apache-2.0
#pragma once
/// @file
/// The exception type of the model layer (URDF, motion and storage readers).
#include <stdexcept>

namespace rbfmuscle {

/// Thrown for a bad URDF, motion or storage file; the message names the file
/// and the element, column or line at fault and what was expected.
class ModelError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

}  // namespace rbfmuscle
