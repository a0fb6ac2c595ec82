#pragma once
/// @file
/// A bound on how far a muscle surface may move in one frame: no further from the previous
/// frame's surface than its bones move there, plus a small slack.
#include "geometry/mesh_distance.h"
#include "geometry/triangle_mesh.h"
#include "rbf/gaussian_field.h"

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <optional>
#include <string>
#include <vector>

namespace rbfmuscle {

/// Settings of the step limit (lengths in mm).
struct StepLimitSettings {
  /// Slack (mm) beyond the bones' own move that a surface point may move in one update; ≤ 0
  /// (default): off. The limit costs an extraction of the surface per update and more per trial
  /// (models/hip/README.md: on the iliacus of the main job, 0.5).
  double max_step_mm = 0.0;
  /// Grid spacing of the surfaces compared (mm, > 0); the default is the output surfaces'.
  double cell_mm = 2.0;
  /// Cap on the trials of a shorter step, ≥ 1: the start, then bisection (the scale is found to
  /// 2^−(max_trials − 1)).
  int max_trials = 6;
};

/// Why the limiter stopped.
enum class StepLimitStop {
  kWithinLimit,  ///< the whole step was within the limit (scale 1)
  kScaled,       ///< the step was scaled down to the largest tried scale within the limit
  kHeld,         ///< only t = 0 was within the limit: the start is kept
  kOverLimit,    ///< no tried scale was within the limit: the one of least excess is kept
  kDisabled,     ///< max_step_mm ≤ 0, or no previous surface to compare with
};

/// Name of a stop reason ("within_limit", "scaled", "held", "over_limit", "disabled").
std::string toString(StepLimitStop stop);

/// What the limiter did.
struct StepLimitReport {
  /// Largest excess of the whole step: a surface point's distance to the previous surface
  /// minus the bones' move there (mm; capped at 4 × max_step_mm).
  double full_excess_mm = 0.0;
  double excess_mm = 0.0;     ///< the same for the step kept (mm)
  double scale = 1.0;         ///< t of the step kept, in [0, 1]
  int trials = 0;             ///< trials of a shorter step (0 when the whole step was within the limit)
  StepLimitStop stop_reason = StepLimitStop::kDisabled;
};

/// Limits one frame's correction of a field so that no point of its surface ends further
/// from the previous frame's surface than the bones move there plus max_step_mm.
///
/// The move allowed at a point y is a(y) = max_b ‖ΔT_b y − y‖ + max_step_mm, ΔT_b the bone's
/// motion since the previous frame (M); the excess of a surface is max_y dist(y, S_prev) − a(y)
/// over the vertices of its extracted surface (grid of extractFieldSurface, cell_mm), the
/// distance to S_prev's triangles. If the end of the step has excess > 0, the parameters go
/// back along the straight line from the start, the previous field carried by the prediction:
/// ξ(t) = ξ_s + t (ξ_e − ξ_s), λ(t) = λ_s + t (λ_e − λ_s), and t is bisected within [0, 1]
/// (max_trials trials, t = 0 first; the largest t within the limit is kept, and if none is, the
/// t of least excess).
/// One-sided: a piece that disappears (a crumb the guard removes) is not a jump.
///
/// Why: where the field is flat at its surface (|∇f| a tenth of its rest value), a small
/// change of f moves the surface by several mm in one frame (the iliacus at 67° of flexion:
/// the descent's +1.0 and the volume step's +0.8 of f each moved it about 4 mm, into the
/// femur), and a thin flap cut by the descent is removed by the guard and grown back the next
/// frame. The limit spreads such a change over several frames (the next frame's descent starts
/// where this one stopped) instead of showing it as a jump; the report says how much was held back.
class SurfaceStepLimiter {
 public:
  /// @throws std::invalid_argument for bad settings (names the field).
  explicit SurfaceStepLimiter(const StepLimitSettings& settings);

  /// Takes the surface of `field` over `box_mm` as the previous frame's surface.
  void setPreviousSurface(const GaussianField& field, const Eigen::AlignedBox3d& box_mm);
  /// Takes the surface of the field run() left as the previous frame's surface (the same as
  /// setPreviousSurface with that field and box, without extracting it again).
  void adoptLastSurface();

  /// Moves `field` (the end) back towards `start` as needed (class comment); `bone_steps_M`
  /// are the bones' motions since the previous surface (M). `start` and `field` have the same
  /// centre count, shapes, offset and cut-off.
  /// @throws std::invalid_argument if they differ or the box is empty.
  StepLimitReport run(const GaussianField& start, GaussianField& field, const Eigen::AlignedBox3d& box_mm,
                      const std::vector<Eigen::Isometry3d>& bone_steps_M);

  const StepLimitSettings& getSettings() const { return settings_; }

 private:
  /// Excess (class comment) of the surface of `field` over `box_mm` (mm, at most `cap_mm`; 0
  /// without a previous surface or without a surface in the box); the surface goes to `mesh`.
  double calcExcess(const GaussianField& field, const Eigen::AlignedBox3d& box_mm,
                    const std::vector<Eigen::Isometry3d>& bone_steps_M, double cap_mm, TriangleMesh& mesh) const;

  StepLimitSettings settings_;
  std::optional<MeshDistance> previous_;  ///< the previous surface, unsigned (none: nothing to compare with)
  TriangleMesh last_surface_;              ///< surface of the field run() left
  TriangleMesh trial_surface_;             ///< scratch: surface of a trial
};

}  // namespace rbfmuscle
