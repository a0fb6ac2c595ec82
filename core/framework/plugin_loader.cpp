// SPDX-License-Identifier: Apache-2.0
#include "framework/plugin_loader.h"

#include "io/file_checks.h"

#include "framework/framework_error.h"

#include <dlfcn.h>

#include <algorithm>
#include <filesystem>

namespace rbfmuscle {

std::vector<std::string> listPluginCandidates(const std::string& spec,
                                              const std::vector<std::string>& search_dirs) {
  namespace fs = std::filesystem;
  std::vector<std::string> names{spec};
  const bool bare = spec.find('/') == std::string::npos;
  if (bare && spec.find(".so") == std::string::npos) {
    names.push_back("lib" + spec + ".so");
    names.push_back(spec + ".so");
  }
  std::vector<std::string> candidates = names;
  if (!fs::path(spec).is_absolute())
    for (const auto& dir : search_dirs)
      for (const auto& name : names) candidates.push_back((fs::path(dir) / name).string());
  return candidates;
}

std::string PluginLoader::load(const std::string& spec, const std::vector<std::string>& search_dirs,
                               Registry& registry) {
  namespace fs = std::filesystem;
  const std::vector<std::string> candidates = listPluginCandidates(spec, search_dirs);
  std::string path;
  for (const auto& candidate : candidates) {
    std::error_code ec;
    if (fs::is_regular_file(candidate, ec)) {
      path = fs::canonical(candidate, ec).string();
      if (!ec) break;
      path.clear();
    }
  }
  if (path.empty()) {
    std::string tried;
    for (const auto& candidate : candidates) {
      tried += (tried.empty() ? "" : ", ") + candidate;
      std::error_code ec;
      if (fs::exists(candidate, ec))  // there, but a device, FIFO or directory
        tried += " (" + io::findInputFileProblem(candidate, "a shared library") + ")";
    }
    throw FrameworkError("plugin " + spec + ": not found (tried: " + tried + ")");
  }
  if (std::find(loaded_.begin(), loaded_.end(), path) != loaded_.end()) return path;

  dlerror();
  void* handle = dlopen(path.c_str(), RTLD_NOW | RTLD_LOCAL);
  if (handle == nullptr) {
    const char* message = dlerror();
    throw FrameworkError("plugin " + path + ": " + (message ? message : "dlopen failed"));
  }
  void* symbol = dlsym(handle, kPluginEntryPoint);
  if (symbol == nullptr) {
    dlclose(handle);
    throw FrameworkError("plugin " + path + ": no entry point " + kPluginEntryPoint);
  }
  const auto register_types = reinterpret_cast<RegisterTypesFunction>(symbol);
  registry.setCurrentOrigin(path);
  try {
    register_types(registry);
  } catch (const FrameworkError&) {
    registry.setCurrentOrigin("");
    throw;
  } catch (const std::exception& error) {
    registry.setCurrentOrigin("");
    throw FrameworkError("plugin " + path + ": " + kPluginEntryPoint + " failed: " + error.what());
  }
  registry.setCurrentOrigin("");
  loaded_.push_back(path);
  return path;
}

}  // namespace rbfmuscle
