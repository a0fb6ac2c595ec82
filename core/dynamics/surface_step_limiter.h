#pragma once
/// @file
/// A bound on how far a muscle surface may move in one frame: no further from the previous
/// frame's surface than its bones move there, plus a small slack.
#include "dynamics/local_value_change.h"
#include "geometry/mesh_distance.h"
#include "geometry/triangle_mesh.h"
#include "rbf/gaussian_field.h"

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <cstdint>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace rbfmuscle {

/// Settings of the step limit (lengths in mm).
struct StepLimitSettings {
  /// Slack (mm) beyond the bones' own move that a surface point may move in one update; ≤ 0
  /// (default): off. The limit costs an extraction of the surface per update and more when it
  /// acts (models/hip/README.md: 0.5 on both muscles of the hip flexion scene).
  double max_step_mm = 0.0;
  /// Grid spacing of the surfaces compared (mm, > 0); the default is the output surfaces'.
  double cell_mm = 2.0;
  /// Cap on the trials of a shorter step, ≥ 1: the start, then bisection (the scale is found to
  /// 2^−(max_trials − 1)).
  int max_trials = 6;
  /// Cap on the rounds of local pull-back (≥ 0; 0: none), each a set of local edits and a look.
  int max_pull_rounds = 6;
};

/// Why the limiter stopped.
enum class StepLimitStop {
  kWithinLimit,  ///< the whole step was within the limit (scale 1)
  kScaled,       ///< the step was scaled down to the largest tried scale within the limit
  kHeld,         ///< only t = 0 was within the limit: the start is kept
  kPulledBack,   ///< points still beyond the limit after the scaling were pulled back to it
  kOverLimit,    ///< points are still beyond the limit after the trial and round caps
  kDisabled,     ///< max_step_mm ≤ 0, or no previous surface to compare with
};

/// Name of a stop reason ("within_limit", "scaled", "held", "pulled_back", "over_limit", "disabled").
std::string toString(StepLimitStop stop);

/// What the limiter did.
struct StepLimitReport {
  /// Largest excess of the whole step: a surface point's distance to the previous surface
  /// minus the bones' move there and the slack (mm; capped at 4 × max_step_mm).
  double full_excess_mm = 0.0;
  double excess_mm = 0.0;     ///< the same for the field left (mm; ≤ 0 when within the limit)
  double scale = 1.0;         ///< t of the step kept, in [0, 1]
  int trials = 0;             ///< trials of a shorter step (0 when the whole step was within the limit)
  int pull_rounds = 0;        ///< rounds of pull-back
  int pull_edits = 0;         ///< local edits made by the pull-back
  StepLimitStop stop_reason = StepLimitStop::kDisabled;
};

/// Limits one frame's change of a field so that no point of its surface ends further from the
/// previous frame's surface than the bones move there plus max_step_mm.
///
/// The move allowed at a point y is a(y) = max_b ‖ΔT_b y − y‖ + max_step_mm, ΔT_b the bone's
/// motion since the previous frame (M); the excess of a surface is max_y dist(y, S_prev) − a(y)
/// over the vertices of its extracted surface (grid of extractFieldSurface, cell_mm, on the
/// lattice cell_mm·ℤ³ of M), the distance to S_prev's triangles.
///
/// 1. **Scale.** If the end of the step has excess > 0, the parameters go back along the straight
///    line from the start, the previous field carried by the prediction:
///    ξ(t) = ξ_s + t (ξ_e − ξ_s), λ(t) = λ_s + t (λ_e − λ_s), and t is bisected within [0, 1]
///    (max_trials trials, t = 0 first). A trial is within when its excess is ≤ 0 and its surface
///    has no more pieces than the end's (a trial that splits a piece off would have the guard
///    bridge it afterwards, somewhere new: the gluteus at 8° of flexion, 1.6 mm). The largest t
///    within is kept, and if none is, the t of least excess.
/// 2. **Pull back.** Points still beyond the limit (where the carried start itself moved too far:
///    a flat valley of the gluteus sinking below zero at 62°) are pulled back locally: each round,
///    at the worst point and others at least two cells apart, the grid node of the point's edge on
///    the wrong side (outside the new surface where it sank into the previous muscle, inside it
///    where it bulged out of it; the side is the previous field's sign at the point) is moved across
///    zero through the free weights around it (changeValueAt), to
///    ±min(0.5, max(0.05, (excess + max_step_mm/2)·|∇f|)), halved after a round that made the
///    excess worse. The best round is kept; max_pull_rounds caps them.
/// One-sided: a piece that disappears (a crumb the guard removes) is not a jump.
///
/// Cheap where the surface stays: a vertex on a grid edge that the previous surface also crossed
/// is within the limit when the two crossings are within a(y) of each other, with no query;
/// only the others are measured against S_prev's triangles (its tree built on first need).
///
/// Why: where the field is flat at its surface (|∇f| a tenth of its rest value), a small
/// change of f moves the surface by several mm in one frame (the iliacus at 67° of flexion:
/// the descent's +1.0 and the volume step's +0.8 of f each moved it about 4 mm, into the
/// femur). The limit spreads such a change over several frames (the next frame's descent starts
/// where this one stopped) instead of showing it as a jump; the report says how much was held back.
class SurfaceStepLimiter {
 public:
  /// @param limits the weights the pull-back may change (free centres first), and how far
  /// @throws std::invalid_argument for bad settings (names the field) or limits of another size.
  SurfaceStepLimiter(const StepLimitSettings& settings, WeightEditLimits limits);

  /// Takes the surface of `field` over `box_mm` as the previous frame's surface.
  void setPreviousSurface(const GaussianField& field, const Eigen::AlignedBox3d& box_mm);
  /// Takes the surface of the field run() or pullBack() last left as the previous frame's surface
  /// (the same as setPreviousSurface with that field and box, without extracting it again).
  void adoptLastSurface();

  /// Moves `field` (the end) back towards `start` and pulls points back as needed (class comment);
  /// `bone_steps_M` are the bones' motions since the previous surface (M). `start` and `field`
  /// have the same centre count, shapes, offset and cut-off.
  /// @throws std::invalid_argument if they differ, the box is empty or a field has another centre count.
  StepLimitReport run(const GaussianField& start, GaussianField& field, const Eigen::AlignedBox3d& box_mm,
                      const std::vector<Eigen::Isometry3d>& bone_steps_M);

  /// Step 2 alone (class comment), for a field changed after run() in the same frame (the island
  /// guard's repairs).
  /// @throws std::invalid_argument as run().
  StepLimitReport pullBack(GaussianField& field, const Eigen::AlignedBox3d& box_mm,
                           const std::vector<Eigen::Isometry3d>& bone_steps_M);

  const StepLimitSettings& getSettings() const { return settings_; }

 private:
  /// A surface, the field it is the zero set of, and per vertex its grid edge on the lattice of M.
  struct Surface {
    TriangleMesh mesh;
    std::vector<std::uint64_t> edges;                       ///< per vertex (latticeEdgeKey)
    std::vector<std::pair<std::uint64_t, int>> by_edge;     ///< (edge, vertex), sorted (previous only)
    GaussianField field;
  };

  /// Extracts the surface of `field` into `out` and returns its excess (class comment; mm, at
  /// most `cap_mm`; 0 without a previous surface or without a surface in the box). With `over`,
  /// the (excess, vertex) of every vertex beyond the limit.
  double measure(const GaussianField& field, const Eigen::AlignedBox3d& box_mm,
                 const std::vector<Eigen::Isometry3d>& bone_steps_M, double cap_mm, Surface& out,
                 std::vector<std::pair<double, int>>* over = nullptr) const;
  /// Step 2 on `field`, whose surface is last_; leaves the best round's field and surface.
  void pullPointsBack(GaussianField& field, const Eigen::AlignedBox3d& box_mm,
                      const std::vector<Eigen::Isometry3d>& bone_steps_M, double cap_mm, StepLimitReport& report);
  /// Checks a field against the limits' size.
  void checkField(const GaussianField& field, const char* where) const;

  StepLimitSettings settings_;
  WeightEditLimits limits_;
  std::optional<Surface> previous_;                   ///< none: nothing to compare with
  mutable std::optional<MeshDistance> previous_tree_;  ///< unsigned, built on first need
  Surface last_;   ///< the surface of the field run() or pullBack() left
  Surface trial_;  ///< scratch: the surface of a trial
  Surface best_;   ///< scratch: the best pull-back round's surface
  std::vector<std::pair<double, int>> over_;
  std::vector<Eigen::Vector3d> picked_;
  ActiveCentres active_;
};

}  // namespace rbfmuscle
