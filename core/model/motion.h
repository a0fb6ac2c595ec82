// SPDX-License-Identifier: Apache-2.0
#pragma once
/// @file
/// A prescribed motion: coordinate values over frames, read from an OpenSim
/// .mot/.sto file (angles in degrees when its header says `inDegrees=yes`).
#include <Eigen/Core>

#include <string>
#include <vector>

namespace rbfmuscle {

class Skeleton;
struct StorageTable;

/// Largest coordinate magnitude a motion may hold: 1e4 rad (about 1600 turns; 1e4 mm for a
/// translational coordinate). A joint angle of a human motion stays within a turn; far beyond,
/// a value is in wrong units or corrupt, and angles of 1e10 rad or more lose all precision in
/// sin and cos and made runs hang.
inline constexpr double kMaxCoordinate_rad = 1e4;

/// Coordinate values per frame, in the skeleton's coordinate order: rad for rotational
/// coordinates, mm for translational ones. Coordinates the file does not mention stay at the
/// skeleton's rest values (Skeleton::getRestCoordinateValues: 0 for a URDF skeleton).
class Motion {
 public:
  /// Reads `path` and maps its columns onto `skeleton`'s coordinates by name. A column is a
  /// coordinate name, or an OpenSim 4 state path `/jointset/JOINT/COORDINATE/value`; state
  /// columns ending in `/speed` are skipped (the motion prescribes positions). Rotational
  /// values are degrees when the header says `inDegrees=yes`, else rad; translational values
  /// are in the model's length unit, metres (OpenSim's convention), and become mm.
  /// @throws ModelError naming the file and the column for a coordinate the
  ///   skeleton does not have, or for a file without frames; naming the file, line, frame and
  ///   column for a value that is not finite or whose magnitude exceeds kMaxCoordinate_rad
  ///   (after conversion from degrees), or a time that does not increase.
  static Motion fromFile(const std::string& path, const Skeleton& skeleton);
  /// fromFile for a table already read (readStorage, parseStorageText); `path` names the file
  /// in errors. @throws ModelError as fromFile.
  static Motion fromTable(const StorageTable& table, const std::string& path, const Skeleton& skeleton);

  int getNumFrames() const { return static_cast<int>(times_s_.size()); }
  double getTime(int frame) const { return times_s_[frame]; }
  /// Coordinates of one frame (rad), size = skeleton coordinate count.
  const Eigen::VectorXd& getCoordinates(int frame) const { return q_rad_[frame]; }
  const std::string& getPath() const { return path_; }

 private:
  std::string path_;
  std::vector<double> times_s_;
  std::vector<Eigen::VectorXd> q_rad_;
};

}  // namespace rbfmuscle
