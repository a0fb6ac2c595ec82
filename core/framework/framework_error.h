// SPDX-License-Identifier: Apache-2.0
#pragma once
/// @file
/// Errors of the component framework and where in a model file they arise.
#include <stdexcept>
#include <string>

namespace rbfmuscle {

/// Thrown for a bad model file, component configuration, plugin or run; the
/// message names the file, XML line and element (or plugin path) at fault and
/// what was expected. The message is complete: callers print it as is.
class FrameworkError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// A place in a model XML file, for error messages.
struct SourceLocation {
  std::string file;     ///< path of the model file as given
  int line = 0;         ///< 1-based line of the element (0 = unknown)
  std::string element;  ///< e.g. `<BodyOriginReporter name="femur_origin">`

  /// "FILE:LINE: ELEMENT" (parts that are empty are left out).
  std::string describe() const;
};

/// Throws FrameworkError with "LOCATION: what".
[[noreturn]] void throwAt(const SourceLocation& where, const std::string& what);

}  // namespace rbfmuscle
