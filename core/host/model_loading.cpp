// SPDX-License-Identifier: Apache-2.0
#include "host/model_loading.h"

#include "host/model_overrides.h"

namespace rbfmuscle {

ModelDocument readModelSource(const ModelSource& source) {
  ModelDocument document = readModelDocument(source.model_path);
  for (const std::string& assignment : source.overrides) applyPropertyOverride(document, assignment);
  if (!source.motion.empty()) overrideMotion(document, source.motion);
  if (!source.reports.empty()) overrideReporter(document, source.reports);
  return document;
}

void loadPlugins(const std::vector<std::string>& specs, const std::string& model_directory,
                 const std::string& library_directory, PluginLoader& loader, Registry& registry) {
  std::vector<std::string> dirs;
  if (!model_directory.empty()) dirs.push_back(model_directory);
  if (!library_directory.empty()) dirs.push_back(library_directory);
  for (const auto& spec : specs) loader.load(spec, dirs, registry);
}

Model buildModel(ModelDocument document, const std::vector<std::string>& plugins,
                 const std::string& library_directory, PluginLoader& loader, Registry& registry) {
  loadPlugins(plugins, document.directory, library_directory, loader, registry);
  for (const FileReference& plugin : document.plugins) {
    try {
      loadPlugins({plugin.path}, document.directory, library_directory, loader, registry);
    } catch (const FrameworkError& error) {
      throwAt(plugin.location, error.what());
    }
  }
  return Model::build(std::move(document), registry);
}

}  // namespace rbfmuscle
