// SPDX-License-Identifier: Apache-2.0
#pragma once
/// @file
/// The multibody skeleton: a Simbody tree built from a URDF file or an OpenSim model (.osim).
///
/// Units and frames: lengths in mm, angles in rad. Ground G is the URDF root
/// link's frame (for the hip model: the CT frame of the LHDL data), or OpenSim's
/// ground. URDF and OpenSim files are in metres by convention; the readers convert
/// them to mm once.
#include <Eigen/Geometry>

#include "model/model_error.h"

#include <limits>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

namespace rbfmuscle {

namespace detail {
struct SkeletonDescription;
}  // namespace detail

/// What a coordinate moves: an angle (rad) or a length (mm).
enum class CoordinateMotion { kRotational, kTranslational };

/// One coordinate of the skeleton.
struct CoordinateInfo {
  std::string name;
  CoordinateMotion motion = CoordinateMotion::kRotational;
  /// Range (rad or mm) as the model file states it; motions are prescribed, so values
  /// outside are allowed. URDF limits are not read: ±infinity.
  double range_min = -std::numeric_limits<double>::infinity();
  double range_max = std::numeric_limits<double>::infinity();
  double default_value = 0.0;  ///< rad or mm (URDF: 0; OpenSim: `default_value`)
  std::string joint;           ///< the joint that owns it
};

/// One mesh attached to a body (URDF visual or collision element; OpenSim geometry file).
struct BodyMesh {
  std::string path;               ///< absolute path, resolved relative to the model file
  Eigen::Isometry3d X_BM;         ///< mesh frame M in body frame B (mm)
  Eigen::Vector3d scale_to_mm;    ///< multiply mesh coordinates by this to get mm in M
  bool collision = false;         ///< true for <collision>, false for <visual> (OpenSim: false)
};

/// Kinematic skeleton: one Simbody MobilizedBody per moving body. From a URDF: one pin
/// per revolute joint (one-DOF joints chained for multi-DOF anatomical joints), fixed
/// joints welded. From an OpenSim model: a CustomJoint becomes one
/// MobilizedBody::FunctionBased (as OpenSim builds it), a PinJoint a pin, a WeldJoint a
/// weld; OpenSim's ground is the root body. Only kinematics is used: set coordinates,
/// read poses.
class Skeleton {
 public:
  /// Parses the URDF with urdfdom and builds the Simbody system.
  /// @throws ModelError naming the file when it is missing, unparsable, has a
  ///   joint type other than revolute/continuous/fixed, or names a missing mesh.
  static Skeleton fromUrdf(const std::string& urdf_path);

  /// Reads an OpenSim model (osim_description.h: 3.x and 4.x layouts) and builds the
  /// Simbody system. @throws ModelError naming the file, the XML line and the element for
  ///   anything the reader does not support or cannot read.
  static Skeleton fromOsim(const std::string& osim_path);

  /// fromUrdf for `.urdf`, fromOsim for `.osim` (extension, any case).
  /// @throws ModelError naming the file for any other extension, or as those do.
  static Skeleton fromFile(const std::string& path);

  /// fromUrdf and fromOsim for the text of the file held in memory; `path` names the file in
  /// errors and is the place mesh and geometry paths are resolved from.
  /// @throws ModelError as those do.
  static Skeleton fromUrdfText(const std::string& text, const std::string& path);
  static Skeleton fromOsimText(const std::string& text, const std::string& path);

  Skeleton(Skeleton&&) noexcept;
  Skeleton& operator=(Skeleton&&) noexcept;
  ~Skeleton();

  const std::string& getName() const;
  /// The model file as given (URDF or .osim).
  const std::string& getModelPath() const;
  /// Same as getModelPath() (the name from when only URDF was read).
  const std::string& getUrdfPath() const;

  /// Joint coordinates in tree order (the URDF revolute joint names; OpenSim coordinate names).
  const std::vector<std::string>& getCoordinateNames() const;
  /// Kind, range, default value and joint of each coordinate, in the same order.
  const std::vector<CoordinateInfo>& getCoordinates() const;
  /// Default values of all coordinates (rad or mm): the pose the skeleton starts in.
  Eigen::VectorXd getDefaultCoordinateValues() const;

  /// The rest pose: where the meshes of the scene (bones, muscles) were segmented, taken by
  /// components as their reference and by motions for the coordinates they do not mention.
  /// The default values unless set.
  const Eigen::VectorXd& getRestCoordinateValues() const;
  /// @throws std::invalid_argument for a wrong size or a non-finite value.
  void setRestCoordinateValues(const Eigen::VectorXd& q);

  /// Coordinates that put every body frame at ground (X_GB = identity), as in models whose
  /// bodies are all given in one image frame (the LHDL OpenSim model: the CT frame). Solved
  /// joint by joint from the model's own numbers, not through Simbody.
  /// @throws ModelError naming the file, joint and body when a joint cannot place its body
  ///   within 0.01 mm and 1e-6 rad of ground.
  Eigen::VectorXd solveBodiesAtGround() const;

  /// Bodies, root first (the root is welded to ground; from an OpenSim model it is `ground`).
  const std::vector<std::string>& getBodyNames() const;
  /// Index into getCoordinateNames(), or -1 when there is none of that name.
  int findCoordinateIndex(const std::string& name) const;
  /// Index into getBodyNames(), or -1 when there is none of that name.
  int findBodyIndex(const std::string& name) const;

  /// Sets all coordinates (rad for rotational, mm for translational ones; size = number of
  /// coordinates) and realizes the Simbody state to Position stage. Values outside joint
  /// limits are allowed (motions are prescribed) but must be finite.
  void setCoordinateValues(const Eigen::VectorXd& q_rad);
  const Eigen::VectorXd& getCoordinateValues() const;

  /// Pose of body B in ground, X_GB (translation in mm), at the last set coordinates.
  Eigen::Isometry3d getBodyTransform(int body_index) const;

  /// Meshes the model attaches to a body (URDF visual and collision; OpenSim geometry).
  const std::vector<BodyMesh>& getBodyMeshes(int body_index) const;

 private:
  struct Impl;
  explicit Skeleton(std::unique_ptr<Impl> impl);
  /// Builds the Simbody system of a description (skeleton_description.h) at its default values.
  static Skeleton build(detail::SkeletonDescription description);
  void checkCoordinates(const Eigen::VectorXd& q, const char* caller) const;
  std::unique_ptr<Impl> impl_;
};

}  // namespace rbfmuscle
