// SPDX-License-Identifier: Apache-2.0
#include "loaded_model.h"

#include <utility>

namespace rbfmuscle::python {

LoadedModel::LoadedModel(const ModelSource& source, const std::string& library_directory,
                         const InitProgressFn& progress)
    : model_(buildModel(readModelSource(source), source.plugins, library_directory, loader_, registry_)) {
  // No run directory: the Python module writes no run files.
  model_.initializeComponents("", progress);
  reset();
}

void LoadedModel::reset() { session_ = std::make_unique<Session>(model_, model_.getMotion().getNumFrames()); }

const FrameTiming& LoadedModel::step(double time_s, const Eigen::VectorXd& q_rad, bool wants_geometry) {
  return session_->step(time_s, q_rad, wants_geometry);
}

std::vector<FrameGeometry> LoadedModel::getFrameGeometry() const {
  if (!session_->hasFrameGeometry())
    throw FrameworkError("no geometry for the last frame: step (or run) with geometry=True first");
  std::vector<FrameGeometry> geometry;
  for (const auto& component : model_.getComponents()) component->appendFrameGeometry(geometry);
  return geometry;
}

std::vector<std::string> LoadedModel::listOutputs() const {
  std::vector<std::string> labels;
  for (const auto& component : model_.getComponents())
    for (const AbstractOutput* output : component->getOutputs())
      labels.push_back(component->getName() + "." + output->getName());
  return labels;
}

const AbstractOutput& LoadedModel::findOutput(const std::string& label) const {
  const std::size_t dot = label.find('.');
  for (const auto& component : model_.getComponents())
    if (dot != std::string::npos && component->getName() == label.substr(0, dot))
      if (const AbstractOutput* output = component->findOutput(label.substr(dot + 1))) return *output;
  std::string labels;
  for (const std::string& name : listOutputs()) labels += (labels.empty() ? "" : ", ") + name;
  throw FrameworkError("no output '" + label + "' in " + model_.getDocument().path +
                       " (outputs: " + (labels.empty() ? "none" : labels) + ")");
}

}  // namespace rbfmuscle::python
