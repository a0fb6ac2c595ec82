// SPDX-License-Identifier: Apache-2.0
#pragma once
/// @file
/// The path of a muscle of an OpenSim model (.osim): its path points, each fixed to a body of the
/// skeleton built from the same file, for a line of action to compare with or for attachments,
/// so that a user with an OpenSim model need not copy points by hand.
///
/// Read from the muscle's GeometryPath (any element of the ForceSet that has one, e.g.
/// Thelen2003Muscle, Millard2012EquilibriumMuscle, PathActuator), in the 3.x and 4.x layouts:
/// - PathPoint: `<location>` in the frame of `<body>` (3.x) or `<socket_parent_frame>` (4.x),
///   which must name a body or ground;
/// - ConditionalPathPoint: on the path only while `<coordinate>` (3.x) or
///   `<socket_coordinate>` (4.x) lies within `<range>` (rad, or model length units for a
///   translational coordinate, converted to mm).
/// Not modelled, and reported in MusclePath::notes: wrapping (PathWrapSet); the path runs
/// straight between its points. Refused with ModelError naming the file, XML line and element:
/// MovingPathPoint (a point that slides with a coordinate), a point on a PhysicalOffsetFrame,
/// a body or coordinate the skeleton does not have, a path of fewer than 2 points.
#include <Eigen/Geometry>

#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "model/model_error.h"

namespace rbfmuscle {

class Skeleton;

/// One path point of an OpenSim muscle.
struct MusclePathPoint {
  std::string name;
  int body = -1;                                ///< index into the skeleton's bodies
  Eigen::Vector3d location_B_mm = Eigen::Vector3d::Zero();  ///< in that body's frame (mm)
  int coordinate = -1;  ///< a conditional point's coordinate (skeleton index); -1: always on the path
  double active_min = -std::numeric_limits<double>::infinity();  ///< rad or mm
  double active_max = std::numeric_limits<double>::infinity();
};

/// A muscle's path, origin first.
struct MusclePath {
  std::string muscle;
  std::vector<MusclePathPoint> points;
  std::vector<std::string> notes;  ///< what the model has and the path leaves out (wrapping)
};

/// Reads muscle `muscle` of the OpenSim model `osim_path`. The points are given in that model's
/// body frames, so `skeleton` must be built from the same file (compared as files, not names).
/// @throws ModelError naming the file (and XML line and element where there is one) for a
///   skeleton read from another file, a muscle not in the model (the model's muscles listed),
///   and each construct refused above.
MusclePath readOsimMusclePath(const std::string& osim_path, const std::string& muscle, const Skeleton& skeleton);

/// A property's reference to muscles of an OpenSim model: "FILE.osim: NAME, NAME, …".
struct OsimMuscleReference {
  std::string file;  ///< as written (the caller resolves a relative path)
  std::vector<std::string> muscles;
};

/// The reference in `spec` when its text before the first ':' ends in ".osim" (any case), else
/// nothing. @throws ModelError quoting the spec for an empty or stray-',' name list.
std::optional<OsimMuscleReference> parseOsimMuscleReference(const std::string& spec);

}  // namespace rbfmuscle
