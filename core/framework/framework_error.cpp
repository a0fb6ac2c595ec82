// SPDX-License-Identifier: Apache-2.0
#include "framework/framework_error.h"

namespace rbfmuscle {

std::string SourceLocation::describe() const {
  std::string text = file;
  if (line > 0) text += ":" + std::to_string(line);
  if (!element.empty()) text += (text.empty() ? "" : ": ") + element;
  return text;
}

void throwAt(const SourceLocation& where, const std::string& what) {
  const std::string prefix = where.describe();
  throw FrameworkError(prefix.empty() ? what : prefix + ": " + what);
}

}  // namespace rbfmuscle
