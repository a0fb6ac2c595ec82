// SPDX-License-Identifier: Apache-2.0
#include "geometry/mesh_warning.h"

#include <cstdio>
#include <mutex>
#include <set>

namespace rbfmuscle {

void printMeshWarning(const std::string& message) {
  static std::mutex mutex;
  static std::set<std::string> written;
  const std::lock_guard<std::mutex> lock(mutex);
  if (!written.insert(message).second) return;
  std::fprintf(stderr, "rbfmuscle: warning: %s\n", message.c_str());
  std::fflush(stderr);
}

}  // namespace rbfmuscle
