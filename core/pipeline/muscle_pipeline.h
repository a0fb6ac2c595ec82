// SPDX-License-Identifier: Apache-2.0
#pragma once
/// @file
/// One muscle's frame: an ordered list of stages owned by the library.
#include "collision/bone_clearance.h"
#include "dynamics/attachment.h"
#include "dynamics/tissue_lattice.h"
#include "dynamics/volume_balance.h"
#include "fibres/fibre_generator.h"
#include "pipeline/descent_stage.h"
#include "pipeline/frame_stage.h"
#include "pipeline/surface_stage.h"
#include "rbf/gaussian_field.h"

#include <limits>
#include <memory>
#include <vector>

namespace rbfmuscle {

/// What a muscle is made of, at rest, in its frame M (mm).
struct MuscleDefinition {
  GaussianField rest_field;                   ///< the fitted field
  TriangleMesh rest_mesh_M;                   ///< the muscle mesh (thickness of the tissue map)
  Attachments attachments;                    ///< kernels on the origin (bone 0) and insertion (bone 1)
  Eigen::Matrix3Xd origin_area_M;             ///< where fibres start (3×K points)
  Eigen::Matrix3Xd insertion_area_M;          ///< where fibres end (3×K points)
  std::vector<ClearanceBone> bones;           ///< contact bones (empty: none)
  std::vector<Eigen::Isometry3d> rest_X_MB;   ///< their poses at rest
  std::vector<int> origin_bones;              ///< which of `bones` belong to the origin's body (the lift-off's pulley)
};

/// Every stage's settings. The defaults are the recommended settings for any muscle.
struct PipelineSettings {
  double cutoff = 1e-3;             ///< ε: a kernel is ignored where φ < ε
  int quadrature_points = 2000;     ///< points of the volume measure (a grid over the muscle and a shell)
  LatticeSettings lattice;          ///< the tissue map
  DescentSettings descent;          ///< the curvature descent
  BalanceSettings volume;           ///< the volume step
  int fibres = 100;                 ///< fibres (0: none)
  int fibre_segments = 15;          ///< segments per fibre
  /// Whether a shortened muscle lifts off its joint (tissue_lattice.h, step 5): with fibres and
  /// a joint centre only.
  bool lift_off = true;
  double surface_cell_mm = 2.0;     ///< grid cell of the rest surface that is tracked (mm)
  SurfaceSettings surface;          ///< its projection
};

/// Runs a muscle's frame (file comment): contacts (bones posed) → prediction → descent →
/// volume → fibres → surface (when asked). Each stage is a FrameStage with its own report; the pipeline times
/// each. Every frame depends on that frame's bone poses only.
///
/// Reports: the stages' tables in that order, then the wall time of each stage and of the
/// frame, form one flat list of figures (describeReports, static, so a component lists its
/// outputs before it is set up; appendReports, the last frame's values). A stage that is
/// absent (no contact bones, no fibres) or did not run this frame reports NaN.
class MusclePipeline {
 public:
  /// The stage slots, in run order.
  enum Slot { kContacts, kPrediction, kDescent, kVolume, kFibres, kSurface, kSlots };
  /// Name of a slot ("contacts", "prediction", "descent", "volume", "fibres", "surface").
  static const char* getSlotName(int slot);
  /// Every reported figure, in order.
  static std::vector<ReportField> describeReports();

  /// Builds every stage at rest. @throws std::invalid_argument (or the error of the part that
  /// failed) naming what is wrong.
  MusclePipeline(const MuscleDefinition& definition, const PipelineSettings& settings = {});

  /// Runs the frame.
  void run(const FrameInput& input);

  /// The last frame's figures, in the order of describeReports().
  void appendReports(std::vector<double>& values) const;
  /// Wall time of the last run (ms).
  double getFrameMs() const { return frame_ms_; }
  /// The state after the last run (the rest state before the first).
  const MuscleState& getState() const { return *state_; }
  /// The rest fibres (null without fibres).
  const RestFibres* getRestFibres() const;
  /// Length of each fibre in the last frame (mm; empty without fibres).
  const Eigen::VectorXd& getFibreLengths() const;
  /// The tracked rest surface.
  const TriangleMesh& getRestSurface() const;
  /// Rest volume (mm³) of the muscle outside the bones.
  double getRestVolume() const { return rest_volume_mm3_; }
  /// The blend weight w₁ beyond which the fibres' strings run when the muscle lifts off its
  /// joint (tissue_lattice.h, step 5); NaN without the lift-off.
  double getPulleyWeight() const { return pulley_weight_; }

 private:
  std::unique_ptr<MuscleState> state_;
  std::shared_ptr<TissueLattice> lattice_;
  std::vector<std::unique_ptr<FrameStage>> stages_;  ///< one per slot, null where absent
  std::vector<double> stage_ms_;
  std::vector<size_t> slot_sizes_;  ///< figures in each slot's table
  double frame_ms_ = 0.0;
  double rest_volume_mm3_ = 0.0;
  double pulley_weight_ = std::numeric_limits<double>::quiet_NaN();
  const class FibreStage* fibres_ = nullptr;
  const SurfaceStage* surface_ = nullptr;
};

}  // namespace rbfmuscle
