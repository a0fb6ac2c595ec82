#pragma once
/// @file
/// The multibody skeleton: a Simbody tree built from a URDF file.
///
/// Units and frames: lengths in mm, angles in rad. Ground G is the URDF root
/// link's frame (for the hip model: the CT frame of the LHDL data). URDF files
/// are in metres by convention; the reader converts them to mm once.
#include <Eigen/Geometry>

#include "model/model_error.h"

#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

namespace rbfmuscle {

/// One mesh attached to a body (URDF visual or collision element).
struct BodyMesh {
  std::string path;               ///< absolute path, resolved relative to the URDF file
  Eigen::Isometry3d X_BM;         ///< mesh frame M in body frame B (mm)
  Eigen::Vector3d scale_to_mm;    ///< multiply mesh coordinates by this to get mm in M
  bool collision = false;         ///< true for <collision>, false for <visual>
};

/// Kinematic skeleton: one Simbody MobilizedBody per moving URDF link, one pin
/// per revolute joint (one-DOF joints chained for multi-DOF anatomical joints),
/// fixed joints welded. Only kinematics is used: set coordinates, read poses.
class Skeleton {
 public:
  /// Parses the URDF with urdfdom and builds the Simbody system.
  /// @throws ModelError naming the file when it is missing, unparsable, has a
  ///   joint type other than revolute/continuous/fixed, or names a missing mesh.
  static Skeleton fromUrdf(const std::string& urdf_path);

  Skeleton(Skeleton&&) noexcept;
  Skeleton& operator=(Skeleton&&) noexcept;
  ~Skeleton();

  const std::string& getName() const;
  const std::string& getUrdfPath() const;

  /// Joint coordinates in tree order (the URDF revolute joint names).
  const std::vector<std::string>& getCoordinateNames() const;
  /// Links, root first (the root is welded to ground).
  const std::vector<std::string>& getBodyNames() const;
  /// Index into getCoordinateNames(), or -1 when there is none of that name.
  int findCoordinateIndex(const std::string& name) const;
  /// Index into getBodyNames(), or -1 when there is none of that name.
  int findBodyIndex(const std::string& name) const;

  /// Sets all coordinates (rad, size = number of coordinates) and realizes the
  /// Simbody state to Position stage. Values outside joint limits are allowed
  /// (motions are prescribed) but must be finite.
  void setCoordinateValues(const Eigen::VectorXd& q_rad);
  const Eigen::VectorXd& getCoordinateValues() const;

  /// Pose of body B in ground, X_GB (translation in mm), at the last set coordinates.
  Eigen::Isometry3d getBodyTransform(int body_index) const;

  /// Meshes the URDF attaches to a body (visual and collision).
  const std::vector<BodyMesh>& getBodyMeshes(int body_index) const;

 private:
  struct Impl;
  explicit Skeleton(std::unique_ptr<Impl> impl);
  std::unique_ptr<Impl> impl_;
};

}  // namespace rbfmuscle
