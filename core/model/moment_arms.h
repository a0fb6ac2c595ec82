// SPDX-License-Identifier: Apache-2.0
#pragma once
/// @file
/// Moment arms of lengths that depend on the skeleton's pose: r = −∂l/∂q (OpenSim's sign: a
/// muscle that shortens as q grows has a positive moment arm), in mm per rad for a rotational
/// coordinate and mm per mm for a translational one.
///
/// By a central difference that re-runs the whole measurement at q ± δ on a skeleton of its
/// own, not by differences between frames: (l(q − δ) − l(q + δ)) / 2δ, with δ = kMomentArmStep_rad
/// or kMomentArmStep_mm. The error is δ²/6 · l‴, far below 0.1 mm for fibre lengths of tens of
/// mm, plus the measurement's noise over 2δ: a point that a contact moves by a step between
/// q − δ and q + δ moves its fibre's arm by about that step / 2δ (docs/moment_arms.md measures
/// how much the arms change between frames).
#include <Eigen/Core>

#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "model/skeleton.h"

namespace rbfmuscle {

constexpr double kMomentArmStep_rad = 1e-2;  ///< δ for a rotational coordinate (0.57°)
constexpr double kMomentArmStep_mm = 0.1;    ///< δ for a translational coordinate

/// Coordinates named by a property text: "" none, "all" every coordinate, or names separated
/// by ','. @throws ModelError naming the unknown coordinate and listing the skeleton's.
std::vector<int> parseCoordinateList(const std::string& text, const Skeleton& skeleton);

/// Moment arms of a vector of lengths over a few coordinates of a skeleton.
class MomentArms {
 public:
  /// The lengths at a pose: `posed` is realized at coordinates `q` (rad or mm).
  using Measure = std::function<Eigen::VectorXd(const Skeleton& posed, const Eigen::VectorXd& q)>;

  /// A skeleton of its own is read from `skeleton`'s file, with the same rest pose, so that
  /// probing never moves the run's skeleton. @param coordinates indices into its coordinates.
  MomentArms(const Skeleton& skeleton, std::vector<int> coordinates);
  ~MomentArms();

  /// r for every coordinate at `q`: measures 2 × coordinates times.
  /// @throws std::invalid_argument when a measurement's size differs from the first one.
  void update(const Eigen::VectorXd& q, const Measure& measure);

  const std::vector<int>& getCoordinates() const { return coordinates_; }
  /// The moment arm of each length about coordinate `k` (k indexes getCoordinates()).
  const Eigen::VectorXd& getArms(size_t k) const { return arms_[k]; }

 private:
  std::unique_ptr<Skeleton> probe_;
  std::vector<int> coordinates_;
  std::vector<Eigen::VectorXd> arms_;
};

}  // namespace rbfmuscle
