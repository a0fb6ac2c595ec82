// SPDX-License-Identifier: Apache-2.0
#pragma once
/// @file
/// Warnings about mesh files (defects the loader repaired): where they go.
#include <functional>
#include <string>

namespace rbfmuscle {

/// Receives one warning, "<file>: <what was found and what was done>", without a prefix or
/// a trailing newline.
using MeshWarningFn = std::function<void(const std::string& message)>;

/// Writes "rbfmuscle: warning: <message>" and a newline to stderr. A message already
/// written by this process is not written again (a bone mesh loaded by several muscles
/// warns once). Thread-safe.
void printMeshWarning(const std::string& message);

}  // namespace rbfmuscle
