// SPDX-License-Identifier: Apache-2.0
#pragma once
/// @file
/// A run frame by frame: the skeleton set to given coordinates, every component updated (in
/// parallel), the invariants the components promise checked (invariant.h), their outputs
/// recorded as one row of the run's table. runModel steps a Session
/// through the model's motion; the Python module steps one with coordinates from Python, so a
/// frame is computed by one path whoever asks for it.
#include "framework/invariant.h"
#include "framework/model.h"
#include "framework/reporter.h"

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <vector>

namespace rbfmuscle {

/// Wall time of the parts of one frame (ms).
struct FrameTiming {
  double skeleton_ms = 0;            ///< coordinates set, body poses read
  std::vector<double> component_ms;  ///< each component's update, in document order
  double output_ms = 0;              ///< the row recorded
};

class Session {
 public:
  /// @param model with its components initialised (Model::initializeComponents); it outlives
  ///   the session, and no other session steps it meanwhile
  /// @param expected_frames rows reserved in the table
  /// @param strict_invariants a frame that breaks an invariant throws instead of warning (on
  ///   stderr, once per invariant)
  /// @throws FrameworkError at the reporter element for a pattern that matches no output, or at
  ///   a component that declares an invariant on an output it does not have
  Session(Model& model, int expected_frames, bool strict_invariants = false);

  /// Frame getNumFrames(): sets the skeleton to `q` (skeleton order; rad, mm for translational
  /// coordinates), updates every component, checks their invariants and records the row (time,
  /// coordinates, outputs).
  /// A component whose bodies did not move since the last frame may keep its last result.
  /// @param wants_geometry whether the components prepare their geometry
  ///   (Component::appendFrameGeometry) in this frame
  /// @throws std::invalid_argument for a wrong count or a non-finite value in `q` (Skeleton);
  ///   FrameworkError at the component's XML location, naming the frame, for an update that
  ///   failed or, with strict_invariants, broke an invariant (the frame is not counted; the
  ///   next one recomputes every component);
  ///   Interrupted (interrupt.h) when the host was asked to stop.
  const FrameTiming& step(double time_s, const Eigen::VectorXd& q, bool wants_geometry);

  /// Frames stepped so far.
  int getNumFrames() const { return frames_; }
  /// True when the last frame was stepped with wants_geometry.
  bool hasFrameGeometry() const { return has_geometry_; }
  /// time, the coordinates and the reported outputs of every frame stepped.
  const StorageTable& getTable() const { return reporter_.getTable(); }
  /// Every invariant broken so far, in the order of their first break.
  const std::vector<InvariantBreak>& getInvariantBreaks() const { return invariants_.getBreaks(); }
  /// Writes the table (Reporter::write).
  const Reporter& getReporter() const { return reporter_; }
  const Model& getModel() const { return model_; }

 private:
  Model& model_;
  Reporter reporter_;
  InvariantChecker invariants_;
  std::vector<Eigen::Isometry3d> X_GB_;  ///< each body's pose at the last frame
  std::vector<char> moved_;              ///< per body: moved since the last frame
  FrameTiming timing_;
  int frames_ = 0;
  bool recompute_all_ = true;  ///< first frame, or one after a failed frame
  bool has_geometry_ = false;
};

}  // namespace rbfmuscle
