// SPDX-License-Identifier: Apache-2.0
#include "fibres/line_of_action.h"

#include "io/text.h"

#include <stdexcept>
#include <string>

namespace rbfmuscle {

ViaPointPath makeViaPointPath(const Eigen::Matrix3Xd& points_mm, int first_bone, int last_bone) {
  const Eigen::Index k = points_mm.cols();
  if (k < 2) throw std::invalid_argument("makeViaPointPath: a path needs ≥ 2 points, got " + std::to_string(k));
  if (!points_mm.allFinite()) throw std::invalid_argument("makeViaPointPath: a path point is not finite");
  for (int bone : {first_bone, last_bone})
    if (bone < 0) throw std::invalid_argument("makeViaPointPath: bone " + std::to_string(bone) + " is negative");
  ViaPointPath path{points_mm, std::vector<int>(static_cast<size_t>(k), first_bone), {}};
  path.bones.back() = last_bone;
  double total = 0;
  for (Eigen::Index i = 1; i < k; ++i) total += (points_mm.col(i) - points_mm.col(i - 1)).norm();
  double arc = 0;
  for (Eigen::Index i = 1; i + 1 < k; ++i) {
    arc += (points_mm.col(i) - points_mm.col(i - 1)).norm();
    path.bones[static_cast<size_t>(i)] = arc < 0.5 * total ? first_bone : last_bone;
  }
  return path;
}

ViaPointText splitViaPointBodies(const std::string& text) {
  ViaPointText split;
  if (text.find('@') == std::string::npos) {
    split.points = text;
    return split;
  }
  std::vector<std::string> items = io::splitTrimmed(text, ';');
  if (items.size() > 1 && items.back().empty()) items.pop_back();  // a trailing ';'
  for (size_t i = 0; i < items.size(); ++i) {
    const std::string where = "via point " + std::to_string(i + 1) + " '" + items[i] + "'";
    const size_t at = items[i].find('@');
    if (at == std::string::npos)
      throw std::invalid_argument(where + " names no body; write 'x y z @ BODY' for every point or for none");
    const std::string body = io::trimWhitespace(items[i].substr(at + 1));
    if (body.empty() || body.find_first_of(" \t\r\n@") != std::string::npos)
      throw std::invalid_argument(where + ": expected one body name after '@'");
    split.bodies.push_back(body);
    split.points += (i ? ";" : "") + items[i].substr(0, at);
  }
  return split;
}

double calcPathLength(const ViaPointPath& path, const std::vector<Eigen::Isometry3d>& bone_motion_M,
                      const Eigen::VectorXd& q) {
  if (!path.conditions.empty() && path.conditions.size() != static_cast<size_t>(path.points_mm.cols()))
    throw std::invalid_argument("calcPathLength: " + std::to_string(path.conditions.size()) + " conditions for " +
                                std::to_string(path.points_mm.cols()) + " points");
  double length = 0;
  Eigen::Vector3d previous = Eigen::Vector3d::Zero();
  bool first = true;
  for (Eigen::Index i = 0; i < path.points_mm.cols(); ++i) {
    if (!path.conditions.empty()) {
      const PathPointCondition& c = path.conditions[static_cast<size_t>(i)];
      if (c.coordinate >= q.size())
        throw std::invalid_argument("calcPathLength: point " + std::to_string(i) + " depends on coordinate " +
                                    std::to_string(c.coordinate) + " but " + std::to_string(q.size()) + " were given");
      if (c.coordinate >= 0 && !(q[c.coordinate] >= c.min && q[c.coordinate] <= c.max)) continue;
    }
    const int bone = path.bones[static_cast<size_t>(i)];
    if (bone < 0 || bone >= static_cast<int>(bone_motion_M.size()))
      throw std::invalid_argument("calcPathLength: point " + std::to_string(i) + " is on bone " + std::to_string(bone) +
                                  " but " + std::to_string(bone_motion_M.size()) + " transforms were given");
    const Eigen::Vector3d p = bone_motion_M[static_cast<size_t>(bone)] * Eigen::Vector3d(path.points_mm.col(i));
    if (!first) length += (p - previous).norm();
    previous = p;
    first = false;
  }
  return length;
}

}  // namespace rbfmuscle
