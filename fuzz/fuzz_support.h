// SPDX-License-Identifier: Apache-2.0
#pragma once
/// @file
/// What the fuzz targets share. A loader may refuse an input only with its own error type
/// (MeshError, RbfFileError, ModelError, FrameworkError): each target catches that type alone,
/// so any other exception escapes LLVMFuzzerTestOneInput and libFuzzer reports it as a crash,
/// as it does ASan and UBSan findings. What a loader accepts must also keep its promises
/// (finite values), checked with requireThat.
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>

namespace rbfmuscle::fuzz {

/// The fuzzer's bytes as a string, as a loader reads a file.
inline std::string asText(const std::uint8_t* data, std::size_t size) {
  return std::string(reinterpret_cast<const char*>(data), size);
}

/// Stops the run as a crash when an accepted input breaks a promise of its loader.
inline void requireThat(bool holds, const char* promise) {
  if (holds) return;
  std::fprintf(stderr, "fuzz: accepted input breaks the loader's promise: %s\n", promise);
  std::abort();
}

}  // namespace rbfmuscle::fuzz
