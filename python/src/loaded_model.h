// SPDX-License-Identifier: Apache-2.0
#pragma once
/// @file
/// A model loaded for Python: its plugins, the built and initialised model, and the session
/// that steps it. Loading is `rbfmuscle run`'s (host/model_loading.h) and a frame is runModel's
/// (framework/session.h); this class only keeps them together for the life of a Python object.
#include "framework/frame_geometry.h"
#include "framework/model.h"
#include "framework/plugin_loader.h"
#include "framework/registry.h"
#include "framework/session.h"
#include "host/model_loading.h"

#include <memory>
#include <string>
#include <vector>

namespace rbfmuscle::python {

class LoadedModel {
 public:
  /// Loads the model as `rbfmuscle run` does and initialises its components.
  /// @param library_directory where the host's libraries (and the plugin) are
  /// @param progress hears each component's initialisation (may throw to stop)
  /// @throws FrameworkError, UsageError as the command line throws them
  LoadedModel(const ModelSource& source, const std::string& library_directory, const InitProgressFn& progress);

  const Model& getModel() const { return model_; }
  const Session& getSession() const { return *session_; }

  /// Forgets the frames stepped: the next step is frame 0 (every component recomputed).
  void reset();
  /// Session::step: frame getSession().getNumFrames().
  const FrameTiming& step(double time_s, const Eigen::VectorXd& q_rad, bool wants_geometry);

  /// The last frame's geometry of every component (ground, mm).
  /// @throws FrameworkError when no frame was stepped with geometry.
  std::vector<FrameGeometry> getFrameGeometry() const;

  /// Every output's label `COMPONENT.OUTPUT`, in document order.
  std::vector<std::string> listOutputs() const;
  /// The output of that label. @throws FrameworkError listing the labels when there is none.
  const AbstractOutput& findOutput(const std::string& label) const;

 private:
  Registry registry_;
  PluginLoader loader_;  // keeps the plugins open while the components live
  Model model_;
  std::unique_ptr<Session> session_;
};

}  // namespace rbfmuscle::python
