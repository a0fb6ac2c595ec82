// SPDX-License-Identifier: Apache-2.0
#pragma once
/// @file
/// Internal to core/model: a URDF file read with urdfdom into plain values,
/// already in mm, so that the Simbody builder never sees urdf:: types.
#include <Eigen/Geometry>

#include <cstdint>
#include <string>
#include <vector>

#include "model/skeleton.h"
#include "model/skeleton_description.h"

namespace rbfmuscle::detail {

/// How a link hangs on its parent.
enum class UrdfJointKind {
  kRoot,      ///< the root link: welded to ground with identity pose
  kFixed,     ///< URDF `fixed`: welded to the parent at X_PJ
  kRevolute,  ///< URDF `revolute` or `continuous`: one angle about axis_J
};

/// One link with the joint that connects it to its parent link.
struct UrdfLink {
  std::string name;
  int parent = -1;                       ///< index into UrdfDescription::links, -1 for the root
  std::string joint_name;                ///< URDF joint to the parent ("" for the root)
  UrdfJointKind joint_kind = UrdfJointKind::kRoot;
  Eigen::Isometry3d X_PJ = Eigen::Isometry3d::Identity();  ///< joint frame J in parent (mm)
  Eigen::Vector3d axis_J = Eigen::Vector3d::UnitZ();       ///< unit rotation axis in J
  double mass_kg = 0.0;                  ///< URDF mass, or a tiny default when absent
  Eigen::Vector3d com_B_mm = Eigen::Vector3d::Zero();      ///< mass centre in the link frame
  /// Inertia about the link frame origin, in link axes (kg·mm²).
  Eigen::Matrix3d inertia_B_kgmm2 = Eigen::Matrix3d::Zero();
  std::vector<BodyMesh> meshes;          ///< visual then collision meshes
};

/// A whole URDF model, links root first in depth-first order.
struct UrdfDescription {
  std::string name;                      ///< robot name
  std::string path;                      ///< the URDF file as given
  std::vector<UrdfLink> links;
};

/// Mass given to a link without <inertial> (kg); its inertia about the link
/// origin is then kDefaultLinkMass_kg × 1 mm² × identity.
inline constexpr double kDefaultLinkMass_kg = 1e-6;

/// Bounds readUrdf puts on a URDF. A human skeleton has tens of links, spans about 2 m and
/// its meshes are in metres (scale 1) or mm (scale 0.001):
/// - at most kMaxSkeletonBodies links;
/// - origins (joints, meshes) within 1000 m of their parent frame;
inline constexpr double kMaxUrdfTranslation_m = 1000.0;
/// - mesh scale factors from 1e-6 to 1e6 (0 collapses a bone, a negative factor mirrors it
///   inside out: both are refused here, not later as a geometry problem);
inline constexpr double kMinUrdfMeshScale = 1e-6;
inline constexpr double kMaxUrdfMeshScale = 1e6;
/// - files of at most 64 MiB.
inline constexpr std::uintmax_t kMaxUrdfFileBytes = 64ull << 20;

/// Reads and checks a URDF file. Lengths m → mm; mesh paths resolved relative
/// to the URDF file's directory.
/// @throws ModelError naming the file for a missing or unparsable file or one that is not a
///   regular file, joints that close a loop of links (naming the joints and the links), a link
///   with two or more parent joints (naming the link and the joints), a
///   link not connected to the root, a joint of unsupported type, a zero or non-finite axis,
///   a non-finite or implausible origin, mass or inertia, a mesh scale outside the bounds
///   above, or a mesh that does not exist.
UrdfDescription readUrdf(const std::string& path);

/// Parses the text of a URDF file held in memory (what readUrdf does after reading the file);
/// `path` names the file in errors, and mesh paths are resolved relative to its directory.
/// @throws ModelError as readUrdf.
UrdfDescription parseUrdf(const std::string& text, const std::string& path);

/// The same skeleton as the neutral description the Simbody builder reads: the root welded to
/// ground, fixed joints welded at X_PJ, revolute joints pins about axis_J with X_PF = X_PJ and
/// X_BM = identity, coordinates named after the revolute joints (rotational, default 0, range ±∞).
SkeletonDescription describeUrdf(const UrdfDescription& urdf);

}  // namespace rbfmuscle::detail
