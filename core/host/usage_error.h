// SPDX-License-Identifier: Apache-2.0
#pragma once
/// @file
/// The error of a bad command line (or of a Python call built from one).
#include <stdexcept>

namespace rbfmuscle {

/// Bad command line: main prints the message and the usage, exits with 2.
class UsageError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

}  // namespace rbfmuscle
