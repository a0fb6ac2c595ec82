#pragma once
/// @file
/// Fibres carried through the motion of their muscle.
///
/// Every fibre point p (rest, M) carries blend weights to the bones: the two end
/// points weight 1 on their own bone (origin end → origin bone, insertion end →
/// insertion bone), so they move rigidly with it; the interior points get
/// calcBlendWeights (dynamics/attachment.h) from the attached centres, exactly as the
/// muscle's free centres and quadrature points. Per frame:
///  1. prediction: p ← dual-quaternion blend of the bone transforms (predictPoints);
///  2. projection: interior points with f < margin in the current field are pushed
///     inside by a monotone ascent of f (projectInside, bounded steps: f never drops, so
///     the point ends at the highest f on its path); an end point below the margin gets
///     the same ascent, but its path is capped at end_max_move_mm (0.499 mm), so it stays
///     within issue 6's 0.5 mm of its bone-rigid place. Why: the ends are deep nodes of
///     the rest field (end_depth), yet where free centres next to an attachment move
///     away, the field there can drop below 0 (one gluteus end, 0.27 field units at
///     50–80° flexion);
///  2b. fallback: an interior point the ascent left at f ≤ 0 (no slope far outside, a
///     local maximum of f outside, or the step cap) is placed from its fibre: between the
///     nearest points before and after it with f > 0 (placeBetweenInsideNeighbours), so it
///     ends inside wherever the muscle holds both (f > 0 guaranteed there);
///  3. lengths Lᵢ = Σ_j ‖p_{j+1} − p_j‖ (mm) and their mean, min, max, mean / rest mean.
/// Each frame starts from the rest fibres (no history): the same transforms and field
/// give the same result.
#include "dynamics/attachment.h"
#include "dynamics/motion_prediction.h"
#include "fibres/fibre_generator.h"
#include "fibres/fibre_projection.h"
#include "rbf/gaussian_field.h"

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <limits>
#include <vector>

namespace rbfmuscle {

/// One frame of the fibres. NaN / 0 until update() ran.
struct FibreFrame {
  static constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
  Eigen::Matrix3Xd points_mm;   ///< current fibre points (3×N(S+1), mm, M), layout of RestFibres
  Eigen::VectorXd lengths_mm;   ///< current length of each fibre (mm)
  double mean_mm = kNaN;        ///< mean length (mm)
  double min_mm = kNaN;         ///< shortest fibre (mm)
  double max_mm = kNaN;         ///< longest fibre (mm)
  double normalised_mean = kNaN;  ///< mean length / rest mean length
  int projected = 0;            ///< points (ends included) pushed back inside this frame
  double end_offset_max_mm = 0; ///< largest move of an end off its bone-rigid place (mm, ≤ end_max_move_mm)
  int placed = 0;               ///< interior points placed from their fibre neighbours (step 2b)
  int outside = 0;              ///< points (ends included) still with f ≤ 0 after steps 2 and 2b
};

/// Carries rest fibres with the bones and the current field (see file comment).
class FibreTracker {
 public:
  /// @param rest the fibres at rest (copied)
  /// @param rest_centres_mm 3×N rest centres of the muscle (M, mm), with `attachments`
  /// @param origin_bone, insertion_bone bones of the fibre ends, in [0, B)
  /// @param blend_length_mm ℓ of calcBlendWeights (mm, > 0; the MuscleDeformer's value)
  /// @throws std::invalid_argument on bad bones, sizes or settings (message names the value).
  FibreTracker(const RestFibres& rest, const Eigen::Matrix3Xd& rest_centres_mm, const Attachments& attachments,
               int origin_bone, int insertion_bone, double blend_length_mm,
               const ProjectionSettings& projection = {});

  /// Moves the fibres for `bone_motion_M` (size B, rest → now, M) inside `field_M`
  /// (the muscle's current field in M). @throws std::invalid_argument on a wrong count.
  const FibreFrame& update(const GaussianField& field_M, const std::vector<Eigen::Isometry3d>& bone_motion_M);

  /// The rest fibres.
  const RestFibres& getRest() const { return rest_; }
  /// The last frame.
  const FibreFrame& getFrame() const { return frame_; }
  /// Blend weights of every fibre point (B×N(S+1)).
  const Eigen::MatrixXd& getWeights() const { return weights_; }
  /// Mean rest length (mm).
  double getRestMean() const { return rest_mean_mm_; }

 private:
  RestFibres rest_;
  Eigen::MatrixXd weights_;
  ProjectionSettings projection_;
  double rest_mean_mm_ = 0;
  std::vector<DualQuaternion> transforms_;
  FibreFrame frame_;
  Eigen::VectorXd values_;  ///< f at every current fibre point (work array of update)
};

}  // namespace rbfmuscle
