#pragma once
/// @file
/// The per-frame driver of one muscle: predict from the bones, descend on the
/// curvature cost, hold the volume.
#include "dynamics/attachment.h"
#include "dynamics/curvature_descent.h"
#include "dynamics/motion_prediction.h"
#include "dynamics/quadrature.h"
#include "dynamics/surface_step_limiter.h"
#include "dynamics/volume_keeper.h"
#include "dynamics/topology_guard.h"
#include "geometry/triangle_mesh.h"
#include "rbf/curvature_cost.h"
#include "rbf/gaussian_field.h"

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <array>
#include <limits>
#include <memory>
#include <vector>

namespace rbfmuscle {

/// All settings of a MuscleDeformer.
struct DeformerSettings {
  QuadratureSettings quadrature;  ///< quadrature of the cost and the volume
  DescentSettings descent;        ///< descent of the free centres
  VolumeSettings volume;          ///< volume measure and correction
  TopologySettings topology;      ///< island and cavity guard (topology_guard.h)
  /// How far the surface may move per update beyond the bones' own move (surface_step_limiter.h);
  /// applies with warm_start from the second update on.
  StepLimitSettings step_limit;
  double blend_length_mm = 1.0;   ///< softening length ℓ of the blend weights (attachment.h, mm), > 0
  /// Step (mm) of the central differences giving the Jacobian det ∂P/∂x of the
  /// prediction at each volume point; ≤ 0 means "h/2".
  double jacobian_step_mm = 0.0;
  /// true: each frame's descent starts from the previous frame's corrected centres
  /// moved by the change of the prediction (ξ_prev + P_now − P_prev), with the previous
  /// weights (the guard's changes carried) and the volume search from the previous correction;
  /// false: every frame starts from the prediction and the rest weights. Either
  /// way the same sequence of transforms gives the same fields.
  bool warm_start = true;
  /// Cut-off ε on φ of the deformed field (GaussianField::setCutoff): centre k is ignored
  /// where φₖ < ε. In [0, 1). (1e-4 was measured no faster than 1e-8 on the gluteus 1000.)
  double cutoff = GaussianField::kDefaultCutoff;
};

/// One frame's result. NaN until update() ran.
struct DeformResult {
  static constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
  double volume_mm3 = kNaN;       ///< V after the correction (mm³)
  double volume_ratio = kNaN;     ///< V / V_rest
  double curvature_cost = kNaN;   ///< Σ w (κ − κ₀)² / E_ref after the descent (dimensionless)
  double descent_cost_initial = kNaN;  ///< E at the prediction
  double descent_cost_final = kNaN;    ///< E after the descent
  int iterations = 0;             ///< descent iterations
  DescentStop stop_reason = DescentStop::kIterationCap;  ///< why the descent stopped
  VolumeStop volume_stop = VolumeStop::kWithinTolerance;  ///< why the volume step stopped
  double volume_correction = kNaN;  ///< δ of the volume correction (volume_keeper.h): free weights × (1 ± δ)
  int islands_found = 0;          ///< islands and cavities the guard removed this frame (summed over its passes)
  int islands_left = 0;           ///< islands and cavities at the guard's last look (0 unless it stopped early)
  int necks_raised = 0;           ///< thinning necks the guard raised this frame (summed over its passes)
  TopologyStop topology_stop = TopologyStop::kDisabled;  ///< why the guard stopped
  double predict_ms = kNaN;       ///< wall time of the prediction (ms)
  double descent_ms = kNaN;       ///< wall time of the descent (ms)
  double volume_ms = kNaN;        ///< wall time of the volume step(s) (ms)
  double topology_ms = 0.0;       ///< wall time of the island guard (ms)
  StepLimitReport step_limit;     ///< what the step limit did (surface_step_limiter.h)
  double step_limit_ms = 0.0;     ///< wall time of the step limit, its guard pass included (ms)
};

/// Deforms one muscle's Gaussian field with its bones.
///
/// Per update, given the bone transforms T_b relative to rest in M:
///  1. prediction (motion_prediction.h): attached centres ξₖ ← T_b ξₖ⁰; free centres,
///     quadrature points and volume points ← dual-quaternion blend of the T_b with
///     their rest blend weights; the quadrature points keep their rest κ₀ (mean
///     curvature is invariant under rigid motion);
///  2. descent (curvature_descent.h) of the free centres, anchored at the prediction;
///  3. volume (volume_keeper.h): the free centres' weights scaled (δ·|λ rest|) so the volume
///     equals the rest volume; the correction is taken out before the next descent;
///  4. one piece (topology_guard.h): through the weights of free centres, crumbs that
///     came apart from the body are lowered below zero, larger pieces are joined back,
///     cavities filled and thinning necks raised; then step 3 runs again, and both repeat while the guard
///     changes something (at most 5 passes, the last one ending with the guard, so the
///     surface is one piece and its volume, measured, off by the last repair only);
///  5. step limit (surface_step_limiter.h): if a point of the surface ends further from the
///     previous frame's surface than the bones move there plus max_step_mm, steps 2–4 are taken
///     back part of the way (centres, weights and δ along the line from the previous field
///     carried by the prediction) and points still beyond are pulled back by local weight
///     edits; then the guard and the pull-back take turns (at most 3 passes, ending with the
///     guard: one piece first), and the volume is measured.
/// With warm_start (default) a frame starts from the previous frame's result carried
/// by the change of prediction, so the result depends on the sequence of transforms
/// (identical sequences give bitwise identical fields); without it each frame starts
/// from the prediction and depends on the given transforms only.
/// The steps do not allocate in steady state apart from the field's and the guard's scratch.
class MuscleDeformer {
 public:
  /// @param rest_field the fitted field in M at rest (copied)
  /// @param attachments bone of every centre (size N) and the number of bones B;
  ///   at least one centre must be attached
  /// @throws std::invalid_argument for bad settings or attachments (message names the field).
  MuscleDeformer(const GaussianField& rest_field, const Attachments& attachments,
                 const DeformerSettings& settings = {});

  /// Moves the muscle for the bone transforms `bone_motion_M` (size B; T_b maps a
  /// rest point of bone b to its current position, both in M).
  /// @throws std::invalid_argument on a wrong count or a non-finite / non-rigid transform.
  const DeformResult& update(const std::vector<Eigen::Isometry3d>& bone_motion_M);

  /// Replaces the current centres (3×N, mm), e.g. to test that the pipeline restores a
  /// disturbed field. With warm_start the next update starts from them (moved by the
  /// change of prediction); attached centres always get their bone's exact motion.
  /// @throws std::invalid_argument on a size mismatch or a non-finite centre.
  void setCurrentCentres(const Eigen::Matrix3Xd& centres_mm);

  /// Like setCurrentCentres, for a correction the following frames keep (the contact
  /// response): each free centre's move is added to its kept offset; from the next frame
  /// on the descent's anchors are prediction + offset, and the quadrature points (curvature
  /// targets, volume) move by the Gaussian-weighted mean offset of the centres around them,
  /// so neither the regulariser nor the curvature cost pulls the correction back.
  /// Limit: offsets are kept for the whole run (no relaxation), so a muscle pushed by a
  /// bone that later moves away stays pushed.
  /// @throws std::invalid_argument as setCurrentCentres.
  void applyKeptCorrection(const Eigen::Matrix3Xd& centres_mm);

  /// The current field (M, mm); the rest field before the first update.
  const GaussianField& getField() const { return field_; }
  /// The rest field.
  const GaussianField& getRestField() const { return rest_field_; }
  /// The last result.
  const DeformResult& getResult() const { return result_; }
  /// The attachments.
  const Attachments& getAttachments() const { return attachments_; }
  /// The quadrature at rest (points, weights, κ₀, cell size, box).
  const Quadrature& getQuadrature() const { return quadrature_; }
  /// The current quadrature points (3×M, mm).
  const Eigen::Matrix3Xd& getQuadraturePoints() const { return current_points_mm_; }
  /// det ∂P/∂x of the prediction P at every rest quadrature point (M), by central
  /// differences with the blend weights of the shifted points (the weights vary in space).
  const Eigen::VectorXd& getJacobians() const { return jacobians_; }
  /// V_rest (mm³).
  double getRestVolume() const { return volume_keeper_->getRestVolume(); }
  /// The last descent report.
  const DescentReport& getDescentReport() const { return descent_report_; }

  /// Box (mm, M) holding the current surface: the box of the current quadrature
  /// points (they cover {f > −β}) padded by one quadrature cell, its corners rounded
  /// outwards to the lattice cell_mm·ℤ³ of M (grids over it share nodes between frames).
  Eigen::AlignedBox3d calcCurrentBox(double cell_mm) const;
  /// The current surface {f = 0} by extractIsoSurface over calcCurrentBox(cell_mm) with spacing cell_mm.
  /// @throws std::invalid_argument if cell_mm ≤ 0.
  TriangleMesh extractSurface(double cell_mm) const;

 private:
  /// Step of the Jacobian differences (mm).
  double jacobianStep() const;
  /// After the step limit changed the field: the guard and the limiter's pull-back in turn.
  void settleStep();
  /// Runs the guard over the current box and adds its figures to result_.
  TopologyReport runGuard();
  /// Measures the volume of the field as it is into `volume` (no correction).
  void measureVolume(VolumeReport& volume) const;
  /// Moves points by the Gaussian-weighted mean of the centres' kept offsets.
  void addKeptOffsetToPoints(Eigen::Matrix3Xd& points_mm) const;

  GaussianField rest_field_;
  GaussianField field_;
  Attachments attachments_;
  DeformerSettings settings_;
  Quadrature quadrature_;
  Eigen::MatrixXd centre_weights_;  ///< B×N blend weights of the rest centres
  Eigen::MatrixXd point_weights_;   ///< B×M blend weights of the rest quadrature points
  std::unique_ptr<CurvatureCost> cost_;
  std::unique_ptr<CurvatureDescent> descent_;
  std::unique_ptr<VolumeKeeper> volume_keeper_;
  std::unique_ptr<TopologyGuard> topology_guard_;
  std::unique_ptr<SurfaceStepLimiter> step_limiter_;
  GaussianField start_field_;               ///< the previous frame's field carried by the prediction (step limit)
  Eigen::VectorXd previous_weights_;        ///< the previous frame's weights, volume correction included
  std::vector<Eigen::Isometry3d> previous_motion_M_;  ///< the bone motions of the previous update
  std::vector<Eigen::Isometry3d> bone_steps_M_;       ///< the bones' motions since the previous update (M)
  /// Whether the field is still the one the step limit last measured (its surface is reused).
  bool limited_surface_is_current_ = false;
  std::vector<DualQuaternion> transforms_;
  Eigen::Matrix3Xd predicted_centres_mm_;
  Eigen::Matrix3Xd previous_predicted_mm_;  ///< prediction of the previous frame (warm start)
  Eigen::Matrix3Xd kept_offset_mm_;         ///< kept corrections per centre (applyKeptCorrection), empty if none
  Eigen::Matrix3Xd anchors_mm_;             ///< the descent's anchors: prediction + kept_offset_mm_
  Eigen::Matrix3Xd start_centres_mm_;       ///< start of this frame's descent (warm start)
  bool has_previous_ = false;               ///< whether a frame was computed
  Eigen::Matrix3Xd current_points_mm_;
  Eigen::Matrix3Xd shifted_points_mm_;  ///< scratch for the Jacobian differences
  std::array<Eigen::Matrix3Xd, 6> shifted_rest_mm_;  ///< rest points q ± step·e_i (order +x, −x, +y, …)
  std::array<Eigen::MatrixXd, 6> shifted_weights_;   ///< B×M blend weights of shifted_rest_mm_
  std::array<Eigen::Matrix3Xd, 3> jacobian_columns_;  ///< ∂P/∂x_i at every quadrature point
  Eigen::VectorXd jacobians_;
  DeformResult result_;
  DescentReport descent_report_;
};

}  // namespace rbfmuscle
