// SPDX-License-Identifier: Apache-2.0
#pragma once
/// @file
/// A number in a message as a user would write it (1e+300, 0.02, -7): the stream's default six
/// significant digits, header-only so that each library's errors use the same form.
#include <sstream>
#include <string>

namespace rbfmuscle::io {

inline std::string formatNumber(double value) {
  std::ostringstream text;
  text << value;
  return text.str();
}

}  // namespace rbfmuscle::io
