// SPDX-License-Identifier: Apache-2.0
#pragma once
/// @file
/// Loads component plugins: shared libraries exporting
///
///     extern "C" void rbfmuscle_register_types(rbfmuscle::Registry& registry);
///
/// (as OpenSim's RegisterTypes_osimPlugin, loaded like `opensim-cmd -L`).
#include "framework/registry.h"

#include <string>
#include <vector>

namespace rbfmuscle {

/// Name of the one symbol a plugin exports.
inline constexpr const char* kPluginEntryPoint = "rbfmuscle_register_types";

/// Signature of the plugin entry point.
using RegisterTypesFunction = void (*)(Registry&);

/// Paths tried for a plugin given as `spec`, in order: `spec` as given
/// (relative to the working directory), then `DIR/spec` for each of
/// `search_dirs` (the host passes the model file's directory, then its own
/// ../lib). A bare name without ".so" (e.g. `rbfmuscle_testplugin`) is also
/// tried as `libNAME.so` and `NAME.so` in each place.
std::vector<std::string> listPluginCandidates(const std::string& spec,
                                              const std::vector<std::string>& search_dirs);

/// Opens plugins with dlopen(RTLD_NOW | RTLD_LOCAL) and calls their entry
/// point. Libraries are never closed: the registry's factories and every
/// component's code live in them until the process exits.
class PluginLoader {
 public:
  /// Finds, opens and registers one plugin; a library already loaded (same
  /// canonical path) is not registered twice.
  /// @return the path that was loaded.
  /// @throws FrameworkError "plugin SPEC: not found (tried: ...)",
  ///   "plugin PATH: DLERROR", "plugin PATH: no entry point rbfmuscle_register_types",
  ///   or "plugin PATH: ..." for an error thrown while registering.
  std::string load(const std::string& spec, const std::vector<std::string>& search_dirs,
                   Registry& registry);
  /// Canonical paths of the loaded libraries, in load order.
  const std::vector<std::string>& getLoadedPaths() const { return loaded_; }

 private:
  std::vector<std::string> loaded_;
};

}  // namespace rbfmuscle
