// SPDX-License-Identifier: Apache-2.0
#pragma once
/// @file
/// Loading a model as `rbfmuscle run` does: the model file, the command line's changes to it,
/// the plugins, the built model. The host and the Python module load through here, so a model
/// and its errors are the same from either.
#include "framework/model.h"
#include "framework/model_document.h"
#include "framework/plugin_loader.h"
#include "framework/registry.h"

#include <string>
#include <vector>

namespace rbfmuscle {

/// A model file and the command line's changes to it.
struct ModelSource {
  std::string model_path;
  std::vector<std::string> plugins;    ///< -L PLUGIN, loaded before the model's <plugin> elements
  std::vector<std::string> overrides;  ///< --set COMPONENT.PROPERTY=VALUE, in order (later ones win)
  std::string motion;                  ///< --motion FILE, relative to the working directory ("" = the model's)
  std::vector<std::string> reports;    ///< --report C.OUTPUT patterns, replacing the model's <reporter> (none = its own)
};

/// Reads the model file, then applies the overrides, the motion and the reported outputs
/// (model_overrides.h).
/// @throws FrameworkError naming the file, line or `--set` for a bad model file or override;
///   UsageError for an override or motion not of the command line's form
ModelDocument readModelSource(const ModelSource& source);

/// Loads each plugin (PluginLoader::load), looked for as given, then in `model_directory`, then
/// in `library_directory` (where the host's libraries are; either may be "").
/// @throws FrameworkError from PluginLoader::load
void loadPlugins(const std::vector<std::string>& specs, const std::string& model_directory,
                 const std::string& library_directory, PluginLoader& loader, Registry& registry);

/// Loads `plugins`, then the document's own (an error names the `<plugin>` element), and builds
/// the model (Model::build). The loader keeps the libraries open for the model's components.
/// @throws FrameworkError from loadPlugins and Model::build
Model buildModel(ModelDocument document, const std::vector<std::string>& plugins,
                 const std::string& library_directory, PluginLoader& loader, Registry& registry);

}  // namespace rbfmuscle
