#include "dynamics/muscle_deformer.h"

#include "dynamics/field_surface.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <stdexcept>
#include <string>

namespace rbfmuscle {

namespace {

double msSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
}

}  // namespace

MuscleDeformer::MuscleDeformer(const GaussianField& rest_field, const Attachments& attachments,
                               const DeformerSettings& settings)
    : rest_field_(rest_field),
      field_(rest_field),
      attachments_(attachments),
      settings_(settings) {
  if (!(settings.cutoff >= 0.0 && settings.cutoff < 1.0)) {
    throw std::invalid_argument("MuscleDeformer: cutoff " + std::to_string(settings.cutoff) + ", expected [0, 1)");
  }
  rest_field_.setCutoff(settings.cutoff);
  field_.setCutoff(settings.cutoff);
  const int N = rest_field.getNumCentres();
  if (static_cast<int>(attachments.bone_of_centre.size()) != N) {
    throw std::invalid_argument("MuscleDeformer: attachments cover " + std::to_string(attachments.bone_of_centre.size()) +
                                " centres, the field has " + std::to_string(N));
  }
  if (attachments.num_bones < 1 || attachments.countAttached() < 1) {
    throw std::invalid_argument("MuscleDeformer: need at least one bone and one attached centre (bones " +
                                std::to_string(attachments.num_bones) + ", attached " +
                                std::to_string(attachments.countAttached()) + ")");
  }
  for (int b : attachments.bone_of_centre) {
    if (b >= attachments.num_bones) {
      throw std::invalid_argument("MuscleDeformer: a centre is attached to bone " + std::to_string(b) + " of " +
                                  std::to_string(attachments.num_bones));
    }
  }
  quadrature_ = makeQuadrature(rest_field_, settings.quadrature);
  const Eigen::Matrix3Xd& rest_centres = rest_field_.getCentres();
  centre_weights_ = calcBlendWeights(rest_centres, rest_centres, attachments, settings.blend_length_mm);
  point_weights_ = calcBlendWeights(quadrature_.points_mm, rest_centres, attachments, settings.blend_length_mm);
  cost_ = std::make_unique<CurvatureCost>(quadrature_.points_mm, quadrature_.weights_mm3, quadrature_.target_curvatures);
  std::vector<bool> free_mask(static_cast<size_t>(N));
  for (int k = 0; k < N; ++k) free_mask[static_cast<size_t>(k)] = !attachments.isAttached(k);
  descent_ = std::make_unique<CurvatureDescent>(*cost_, free_mask, settings.descent);
  const double h = quadrature_.cell_mm;
  // The volume is kept through the free centres, in proportion to their rest |λ|
  // (volume_keeper.h: a global offset inflated the attachments into their bones).
  const Eigen::VectorXd rest_abs = rest_field_.getWeights().cwiseAbs();
  Eigen::VectorXd correction_weights = rest_abs;
  for (int k = 0; k < N; ++k)
    if (attachments.isAttached(k)) correction_weights(k) = 0.0;
  volume_keeper_ =
      std::make_unique<VolumeKeeper>(quadrature_.points_mm, h * h * h, rest_field_, correction_weights, settings.volume);
  // Weight limits of the guard: twice the rest weight plus the mean rest weight, so a
  // near-zero weight can still help fill a cavity but no weight grows without bound.
  const Eigen::VectorXd limits = (2.0 * rest_abs.array() + rest_abs.mean()).matrix();
  topology_guard_ = std::make_unique<TopologyGuard>(free_mask, limits, settings.topology);
  step_limiter_ = std::make_unique<SurfaceStepLimiter>(settings.step_limit, WeightEditLimits{free_mask, limits});
  transforms_.assign(static_cast<size_t>(attachments.num_bones), DualQuaternion{});
  predicted_centres_mm_ = rest_centres;
  current_points_mm_ = quadrature_.points_mm;
  // The rest points shifted by ±step along each axis, and their blend weights: the
  // weights vary with the point, so the Jacobian of the prediction needs them. Both are
  // fixed, so they are made once here rather than every frame.
  const double step = jacobianStep();
  for (int i = 0; i < 3; ++i) {
    for (int side = 0; side < 2; ++side) {
      Eigen::Matrix3Xd& shifted = shifted_rest_mm_[static_cast<size_t>(2 * i + side)];
      shifted = quadrature_.points_mm;
      shifted.row(i).array() += side == 0 ? step : -step;
      shifted_weights_[static_cast<size_t>(2 * i + side)] =
          calcBlendWeights(shifted, rest_centres, attachments, settings.blend_length_mm);
    }
  }
  jacobians_ = Eigen::VectorXd::Ones(quadrature_.points_mm.cols());
  bone_steps_M_.assign(static_cast<size_t>(attachments.num_bones), Eigen::Isometry3d::Identity());
}

const DeformResult& MuscleDeformer::update(const std::vector<Eigen::Isometry3d>& bone_motion_M) {
  if (static_cast<int>(bone_motion_M.size()) != attachments_.num_bones) {
    throw std::invalid_argument("MuscleDeformer::update: " + std::to_string(bone_motion_M.size()) +
                                " bone transforms, expected " + std::to_string(attachments_.num_bones));
  }
  for (size_t b = 0; b < bone_motion_M.size(); ++b) {
    const Eigen::Matrix3d r = bone_motion_M[b].linear();
    if (!bone_motion_M[b].matrix().allFinite() ||
        (r.transpose() * r - Eigen::Matrix3d::Identity()).norm() > 1e-6 || r.determinant() < 0.0) {
      throw std::invalid_argument("MuscleDeformer::update: transform of bone " + std::to_string(b) +
                                  " is not a finite rigid motion");
    }
    transforms_[b] = toDualQuaternion(bone_motion_M[b]);
  }
  auto start = std::chrono::steady_clock::now();
  const bool limit_step = settings_.warm_start && has_previous_ && settings_.step_limit.max_step_mm > 0.0;
  const double previous_correction = volume_keeper_->getCorrection();
  if (limit_step) {
    previous_weights_ = field_.getWeights();
    if (limited_surface_is_current_)
      step_limiter_->adoptLastSurface();
    else
      step_limiter_->setPreviousSurface(field_, calcCurrentBox(settings_.step_limit.cell_mm));
    for (size_t b = 0; b < bone_motion_M.size(); ++b) bone_steps_M_[b] = bone_motion_M[b] * previous_motion_M_[b].inverse();
  }
  previous_motion_M_ = bone_motion_M;
  // The descent compares κ of the field without the volume correction with κ₀.
  volume_keeper_->removeCorrection(field_);
  predictCentres(rest_field_.getCentres(), attachments_, centre_weights_, transforms_, predicted_centres_mm_);
  if (settings_.warm_start && has_previous_) {
    // Previous corrected centres carried by the change of the prediction; attached
    // centres get their exact prediction (their correction is zero).
    start_centres_mm_ = field_.getCentres() + (predicted_centres_mm_ - previous_predicted_mm_);
    for (int k = 0; k < static_cast<int>(attachments_.bone_of_centre.size()); ++k)
      if (attachments_.isAttached(k)) start_centres_mm_.col(k) = predicted_centres_mm_.col(k);
    field_.setCentrePositions(start_centres_mm_);
  } else {
    // With warm start the weights (the guard's changes) are carried like the centres: a
    // piece it joined stays joined in the next frame instead of being rejoined (or not)
    // from the rest weights, which made the surface jump by up to 19 mm between 1° frames.
    // The weight limits bound what can pile up.
    field_.setCentrePositions(predicted_centres_mm_);
    field_.setWeights(rest_field_.getWeights());
    volume_keeper_->forgetCorrection();
  }
  previous_predicted_mm_ = predicted_centres_mm_;
  has_previous_ = true;
  predictPoints(quadrature_.points_mm, point_weights_, transforms_, current_points_mm_);
  if (kept_offset_mm_.cols() > 0) addKeptOffsetToPoints(current_points_mm_);
  cost_->setPoints(current_points_mm_);
  // det ∂P/∂x by central differences of the prediction (weights of the shifted points).
  const double step = jacobianStep();
  for (int i = 0; i < 3; ++i) {
    const size_t plus = static_cast<size_t>(2 * i), minus = plus + 1;
    predictPoints(shifted_rest_mm_[plus], shifted_weights_[plus], transforms_, jacobian_columns_[static_cast<size_t>(i)]);
    predictPoints(shifted_rest_mm_[minus], shifted_weights_[minus], transforms_, shifted_points_mm_);
    jacobian_columns_[static_cast<size_t>(i)] -= shifted_points_mm_;
    jacobian_columns_[static_cast<size_t>(i)] /= 2.0 * step;
  }
  for (Eigen::Index j = 0; j < jacobians_.size(); ++j) {
    Eigen::Matrix3d jac;
    for (int i = 0; i < 3; ++i) jac.col(i) = jacobian_columns_[static_cast<size_t>(i)].col(j);
    jacobians_(j) = jac.determinant();
  }
  result_.predict_ms = msSince(start);

  start = std::chrono::steady_clock::now();
  anchors_mm_ = predicted_centres_mm_;
  if (kept_offset_mm_.cols() > 0) anchors_mm_ += kept_offset_mm_;
  descent_report_ = descent_->run(field_, anchors_mm_);
  result_.descent_ms = msSince(start);

  start = std::chrono::steady_clock::now();
  VolumeReport volume = volume_keeper_->correct(field_, current_points_mm_, jacobians_);
  result_.volume_ms = msSince(start);

  // Islands, then the volume again (lowering them loses volume, and moving b to restore
  // it can bring a lowered island back above zero or split a bridge), at most kGuardPasses
  // times. The last pass ends with the guard, whose own rounds stop at one piece: the
  // surface handed on is then whole, and its volume, measured, is off only by what that
  // last repair moved (a bridge or a crumb, tens of mm³).
  constexpr int kGuardPasses = 5;
  result_.topology_ms = 0.0;
  result_.islands_found = 0;
  result_.necks_raised = 0;
  for (int pass = 0;; ++pass) {
    start = std::chrono::steady_clock::now();
    const TopologyReport topology = runGuard();
    result_.topology_ms += msSince(start);
    if (topology.weights_changed == 0) break;
    start = std::chrono::steady_clock::now();
    if (pass + 1 == kGuardPasses) {
      measureVolume(volume);
      result_.volume_ms += msSince(start);
      break;
    }
    volume = volume_keeper_->correct(field_, current_points_mm_, jacobians_);
    result_.volume_ms += msSince(start);
  }

  result_.step_limit = StepLimitReport{};
  result_.step_limit_ms = 0.0;
  if (limit_step) {
    start = std::chrono::steady_clock::now();
    start_field_ = field_;  // same shapes, offset and cut-off
    start_field_.setCentrePositions(start_centres_mm_);
    start_field_.setWeights(previous_weights_);
    const double end_correction = volume_keeper_->getCorrection();
    result_.step_limit =
        step_limiter_->run(start_field_, field_, calcCurrentBox(settings_.step_limit.cell_mm), bone_steps_M_);
    const double t = result_.step_limit.scale;
    limited_surface_is_current_ = true;
    if (t < 1.0 || result_.step_limit.pull_edits > 0) {
      // The weights went back along the line, δ c with them.
      volume_keeper_->setAppliedCorrection(previous_correction + t * (end_correction - previous_correction));
      settleStep();
      measureVolume(volume);
    }
    result_.step_limit_ms = msSince(start);
  }

  result_.volume_mm3 = volume.volume_mm3;
  result_.volume_ratio = volume.volume_ratio;
  result_.volume_stop = volume.stop_reason;
  result_.volume_correction = volume_keeper_->getCorrection();
  result_.curvature_cost = descent_report_.curvature_cost_final;
  result_.descent_cost_initial = descent_report_.cost_initial;
  result_.descent_cost_final = descent_report_.cost_final;
  result_.iterations = descent_report_.iterations;
  result_.stop_reason = descent_report_.stop_reason;
  return result_;
}

void MuscleDeformer::settleStep() {
  // The limited field may have split a piece off or opened a cavity (the scaling refuses that,
  // a pull-back can do it): the guard repairs it, and its repair may in turn move points beyond
  // the limit (a bridge where there was none). In turn, at most kSettlePasses times, ending with
  // the guard: one piece comes first (step_limit.excess_mm is the pull-back's last measure).
  constexpr int kSettlePasses = 3;
  for (int pass = 0;; ++pass) {
    limited_surface_is_current_ = runGuard().weights_changed == 0;
    if (limited_surface_is_current_ || pass == kSettlePasses) return;
    const StepLimitReport again =
        step_limiter_->pullBack(field_, calcCurrentBox(settings_.step_limit.cell_mm), bone_steps_M_);
    result_.step_limit.pull_rounds += again.pull_rounds;
    result_.step_limit.pull_edits += again.pull_edits;
    result_.step_limit.excess_mm = again.excess_mm;
    limited_surface_is_current_ = true;
    if (again.pull_edits == 0) return;
  }
}

TopologyReport MuscleDeformer::runGuard() {
  const TopologyReport topology = topology_guard_->run(field_, calcCurrentBox(topology_guard_->getSettings().cell_mm));
  result_.islands_found += topology.islands_found + topology.cavities_found;
  result_.necks_raised += topology.necks_raised;
  result_.islands_left = topology.defects_left;
  result_.topology_stop = topology.stop_reason;
  return topology;
}

void MuscleDeformer::measureVolume(VolumeReport& volume) const {
  volume.volume_mm3 = volume_keeper_->calcVolume(field_, current_points_mm_, jacobians_);
  volume.volume_ratio = volume.volume_mm3 / volume_keeper_->getRestVolume();
}

void MuscleDeformer::setCurrentCentres(const Eigen::Matrix3Xd& centres_mm) {
  if (centres_mm.cols() != field_.getNumCentres()) {
    throw std::invalid_argument("MuscleDeformer::setCurrentCentres: " + std::to_string(centres_mm.cols()) +
                                " centres, expected " + std::to_string(field_.getNumCentres()));
  }
  field_.setCentrePositions(centres_mm);
  limited_surface_is_current_ = false;
}

void MuscleDeformer::applyKeptCorrection(const Eigen::Matrix3Xd& centres_mm) {
  const Eigen::Matrix3Xd before = field_.getCentres();
  setCurrentCentres(centres_mm);
  if (kept_offset_mm_.cols() == 0) kept_offset_mm_ = Eigen::Matrix3Xd::Zero(3, field_.getNumCentres());
  for (int k = 0; k < field_.getNumCentres(); ++k)
    if (!attachments_.isAttached(k)) kept_offset_mm_.col(k) += field_.getCentres().col(k) - before.col(k);
}

void MuscleDeformer::addKeptOffsetToPoints(Eigen::Matrix3Xd& points_mm) const {
  // Σ φₖ(p) δₖ / Σ φₖ(p) over the current centres and shapes (the field's cut-off), one
  // neighbour search per point; each point on its own, so the result is thread-independent.
#pragma omp parallel for schedule(static)
  for (Eigen::Index j = 0; j < points_mm.cols(); ++j) {
    thread_local ActiveCentres active;
    field_.findActiveCentres(points_mm.col(j), active);
    double sum = 0.0;
    Eigen::Vector3d moved = Eigen::Vector3d::Zero();
    for (int q = 0; q < active.size(); ++q) {
      sum += active.phi[static_cast<size_t>(q)];
      moved += active.phi[static_cast<size_t>(q)] * kept_offset_mm_.col(active.indices[static_cast<size_t>(q)]);
    }
    points_mm.col(j) += moved / std::max(sum, 1e-12);
  }
}

double MuscleDeformer::jacobianStep() const {
  return settings_.jacobian_step_mm > 0.0 ? settings_.jacobian_step_mm : 0.5 * quadrature_.cell_mm;
}

Eigen::AlignedBox3d MuscleDeformer::calcCurrentBox(double cell_mm) const {
  Eigen::AlignedBox3d box;
  for (Eigen::Index j = 0; j < current_points_mm_.cols(); ++j) box.extend(current_points_mm_.col(j));
  const Eigen::Vector3d pad = Eigen::Vector3d::Constant(quadrature_.cell_mm);
  // Corners on the lattice cell_mm·ℤ³ of M, so consecutive frames sample the field at the
  // same nodes: with a box that slid with the motion, the guard saw a thin part on other
  // nodes every frame and the extracted surface moved where the field had not (gluteus
  // at 1° steps: largest jump beyond the femur's move 3.3 → 2.1 mm, iliacus 1.8 → 0.4 mm).
  const Eigen::Vector3d low = ((box.min() - pad) / cell_mm).array().floor() * cell_mm;
  const Eigen::Vector3d high = ((box.max() + pad) / cell_mm).array().ceil() * cell_mm;
  return Eigen::AlignedBox3d(low, high);
}

TriangleMesh MuscleDeformer::extractSurface(double cell_mm) const {
  if (!(cell_mm > 0.0)) throw std::invalid_argument("MuscleDeformer::extractSurface: cell " + std::to_string(cell_mm) + " mm, expected > 0");
  return extractFieldSurface(field_, calcCurrentBox(cell_mm), cell_mm);
}

}  // namespace rbfmuscle
