// SPDX-License-Identifier: Apache-2.0
#pragma once
/// @file
/// What a component sees: InitContext once before the run, FrameState every frame.
#include "framework/socket.h"

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <functional>
#include <map>
#include <memory>
#include <mutex>

#include <string>
#include <vector>

namespace rbfmuscle {

class Skeleton;

/// Handed to Component::initialize(): where files are, and the skeleton at
/// its initial (all-zero) coordinates.
class InitContext {
 public:
  InitContext(std::string model_directory, std::string output_directory, const Skeleton& skeleton)
      : model_directory_(std::move(model_directory)),
        output_directory_(std::move(output_directory)), skeleton_(&skeleton) {}

  /// Absolute directory of the model XML file.
  const std::string& getModelDirectory() const { return model_directory_; }
  /// Directory for files a component writes; its content ends up in the run's
  /// OUTDIR (it is a staging directory renamed into place after success).
  const std::string& getOutputDirectory() const { return output_directory_; }
  /// `path` unchanged when absolute, else resolved against the model directory, inside it:
  /// a component's files (meshes it reads, caches it writes) belong to the model, so a
  /// relative path whose normal form starts with `..` (e.g. `../../../tmp/x.rbf`) is refused
  /// before anything is read or written. An absolute path is the user's explicit choice of a
  /// file elsewhere and is used as written. The check is on the text: a symbolic link inside
  /// the model directory is followed (whoever placed it chose so).
  /// @throws FrameworkError naming the path and the model directory.
  std::string resolvePath(const std::string& path) const;
  /// The skeleton at its rest pose (all coordinates 0) while components initialize.
  const Skeleton& getSkeleton() const { return *skeleton_; }

  /// An object the components of a run share (a bone's distance grid, built once for every
  /// muscle that touches the bone), made by `make` for the first component that asks for
  /// `key` and handed to the others. Holders keep it alive; thread-safe.
  template <class T>
  std::shared_ptr<T> findOrMakeShared(const std::string& key, const std::function<std::shared_ptr<T>()>& make) const {
    std::lock_guard<std::mutex> lock(shared_->mutex);
    std::shared_ptr<void>& slot = shared_->objects[key];
    if (!slot) slot = make();
    return std::static_pointer_cast<T>(slot);
  }

 private:
  struct Shared {
    std::mutex mutex;
    std::map<std::string, std::shared_ptr<void>> objects;
  };
  std::shared_ptr<Shared> shared_ = std::make_shared<Shared>();
  std::string model_directory_;
  std::string output_directory_;
  const Skeleton* skeleton_;
};

/// One frame of the prescribed motion after the skeleton was realized.
/// Holds references to buffers owned by the run loop (no allocation per frame).
class FrameState {
 public:
  /// @param q_rad coordinates (rad) in skeleton order
  /// @param X_GB pose of each body B in ground G (translation in mm), by body index
  /// @param body_moved per body: 1 when X_GB differs from the previous frame (1 at frame 0)
  /// @param wants_geometry whether the frame's geometry is written (--frames-mesh)
  FrameState(int frame_index, double time_s, const Eigen::VectorXd& q_rad,
             const std::vector<Eigen::Isometry3d>& X_GB, const std::vector<char>& body_moved,
             bool wants_geometry = false)
      : frame_index_(frame_index), time_s_(time_s), q_rad_(&q_rad), X_GB_(&X_GB),
        body_moved_(&body_moved), wants_geometry_(wants_geometry) {}

  /// 0-based frame number in the motion.
  int getFrameIndex() const { return frame_index_; }
  /// Motion time (s).
  double getTime() const { return time_s_; }
  /// All skeleton coordinates (rad).
  const Eigen::VectorXd& getCoordinates() const { return *q_rad_; }
  int getNumBodies() const { return static_cast<int>(X_GB_->size()); }
  /// X_GB: body frame B in ground G, translation in mm.
  const Eigen::Isometry3d& getBodyTransform(int body_index) const { return (*X_GB_)[body_index]; }
  const Eigen::Isometry3d& getBodyTransform(const BodySocket& body) const {
    return (*X_GB_)[body.getBodyIndex()];
  }
  /// True when the body moved since the previous frame (always true at frame 0);
  /// lets a component skip work when nothing it depends on moved.
  bool hasBodyMoved(int body_index) const { return (*body_moved_)[body_index] != 0; }
  /// True when appendFrameGeometry will be called for this frame: a component may prepare
  /// its geometry (and the figures that come with it) only then.
  bool wantsGeometry() const { return wants_geometry_; }

 private:
  int frame_index_;
  double time_s_;
  const Eigen::VectorXd* q_rad_;
  const std::vector<Eigen::Isometry3d>* X_GB_;
  const std::vector<char>* body_moved_;
  bool wants_geometry_;
};

}  // namespace rbfmuscle
