// SPDX-License-Identifier: Apache-2.0
#pragma once
/// @file
/// Internal to core/model: a skeleton as plain values, already in mm and rad, whatever file it
/// came from (URDF through urdf_description.h, OpenSim .osim through osim_description.h). The
/// Simbody builder (skeleton.cpp) reads only this.
///
/// Frames: P is the parent body's frame, B this body's frame; the joint frame F is fixed in P
/// (X_PF) and M is fixed in B (X_BM). The joint moves M relative to F: X_PB(q) = X_PF · X_FM(q) · X_BMᵀ.
#include <Eigen/Geometry>

#include <array>
#include <cstddef>
#include <string>
#include <vector>

#include "model/skeleton.h"

namespace rbfmuscle::detail {

/// How a body hangs on its parent.
enum class JointKind {
  kRoot,     ///< the root body: welded to ground with identity pose
  kWeld,     ///< X_FM = identity
  kPin,      ///< X_FM = rotation about `pin_axis` (unit, the same in F and M) by the coordinate
  kSpatial,  ///< X_FM from six transform axes (OpenSim CustomJoint), see SkeletonBody::axes
};

/// One transform axis's function: value = slope · q + intercept, or the intercept alone for a
/// constant (coordinate −1). Values are rad on rotation axes and mm on translation axes; the
/// slope is per rad or per mm of its coordinate (each coordinate drives one axis of its own kind).
struct AxisFunction {
  int coordinate = -1;     ///< index into SkeletonDescription::coordinates, −1 for a constant
  double slope = 0.0;
  double intercept = 0.0;
};

/// One body and the joint that connects it to its parent body.
struct SkeletonBody {
  std::string name;
  int parent = -1;               ///< index into SkeletonDescription::bodies, −1 for the root
  std::string joint_name;        ///< "" for the root
  JointKind joint_kind = JointKind::kRoot;
  Eigen::Isometry3d X_PF = Eigen::Isometry3d::Identity();  ///< joint frame F in the parent (mm)
  Eigen::Isometry3d X_BM = Eigen::Isometry3d::Identity();  ///< joint frame M in this body (mm)
  Eigen::Vector3d pin_axis = Eigen::Vector3d::UnitZ();     ///< kPin: unit axis in F (= in M)
  /// kSpatial: unit axes in F, three rotations then three translations, as Simbody's
  /// MobilizedBody::FunctionBased and OpenSim's SpatialTransform use them:
  /// R_FM = R(axes[0], f0) · R(axes[1], f1) · R(axes[2], f2) (each axis in the frame the rotations
  /// before it produced), p_FM = f3 · axes[3] + f4 · axes[4] + f5 · axes[5] (in F).
  std::array<Eigen::Vector3d, 6> axes{Eigen::Vector3d::UnitX(), Eigen::Vector3d::UnitY(), Eigen::Vector3d::UnitZ(),
                                      Eigen::Vector3d::UnitX(), Eigen::Vector3d::UnitY(), Eigen::Vector3d::UnitZ()};
  std::array<AxisFunction, 6> functions{};  ///< kSpatial: one per axis
  std::vector<int> coordinates;  ///< the joint's coordinates (kPin: one), in mobility order
  double mass_kg = 0.0;
  Eigen::Vector3d com_B_mm = Eigen::Vector3d::Zero();       ///< mass centre in B
  Eigen::Matrix3d inertia_B_kgmm2 = Eigen::Matrix3d::Zero();  ///< about B's origin, in B axes (kg·mm²)
  std::vector<BodyMesh> meshes;
};

/// A whole skeleton: bodies root first, every parent before its children.
struct SkeletonDescription {
  std::string name;     ///< robot or model name
  std::string path;     ///< the file as given
  std::string format;   ///< "URDF" or "OpenSim", for messages
  std::vector<SkeletonBody> bodies;
  std::vector<CoordinateInfo> coordinates;
};

/// Most bodies (links) a skeleton file may give: a human skeleton has tens; far more is not a
/// skeleton, and the build grows faster than the count (50 000 bodies ran for minutes).
inline constexpr std::size_t kMaxSkeletonBodies = 1000;

/// Largest body mass a skeleton file may give (kg), and largest principal moment of inertia
/// about the mass centre (kg·m²): far beyond any body part, close enough that the parallel-axis
/// shifts of the builder stay finite.
inline constexpr double kMaxBodyMass_kg = 1e6;
inline constexpr double kMaxBodyInertia_kgm2 = 1e6;

/// Fraction of the largest principal moment by which every principal moment must exceed 0 and
/// fall short of the sum of the other two (findMassPropertiesProblem).
inline constexpr double kMinInertiaMargin = 1e-9;

/// Why `mass_kg` and the inertia `I_C` about the mass centre (kg·m², any consistent units) cannot
/// be a rigid body's, or "" when they can: a mass that is negative or above kMaxBodyMass_kg, an
/// inertia that is not symmetric, a principal moment above kMaxBodyInertia_kgm2, or one not
/// above 0 or not below the sum of the other two by kMinInertiaMargin of the largest (the
/// triangle inequality every real body meets, which Simbody enforces by throwing while it builds
/// the system or poses it). An inertia of all zeros (a massless point) is accepted.
std::string findMassPropertiesProblem(double mass_kg, const Eigen::Matrix3d& I_C);

/// X_FM of `body`'s joint at the coordinates `q` (all of the skeleton's, rad or mm), computed
/// with Eigen from the description (not through Simbody).
Eigen::Isometry3d calcJointTransform(const SkeletonBody& body, const Eigen::VectorXd& q);

/// Coordinates that put every body frame at ground (X_GB = identity for all bodies), joint by
/// joint: rotations by a damped Gauss–Newton search from a few starts (iterations capped),
/// translations by least squares. Coordinates that move nothing stay at `q_start`.
/// @throws ModelError naming the file, joint and body when a joint cannot place its body within
///   `tolerance_mm` (translation) and `tolerance_rad` (rotation) of ground.
Eigen::VectorXd solveBodiesAtGround(const SkeletonDescription& d, const Eigen::VectorXd& q_start,
                                    double tolerance_mm, double tolerance_rad);

}  // namespace rbfmuscle::detail
