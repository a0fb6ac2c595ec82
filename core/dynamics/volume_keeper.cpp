#include "dynamics/volume_keeper.h"

#include <cmath>
#include <stdexcept>

namespace rbfmuscle {

std::string toString(VolumeStop stop) {
  switch (stop) {
    case VolumeStop::kWithinTolerance: return "within_tolerance";
    case VolumeStop::kIterationCap: return "iteration_cap";
    case VolumeStop::kCorrectionBound: return "correction_bound";
    case VolumeStop::kDisabled: return "disabled";
  }
  return "unknown";
}

VolumeKeeper::VolumeKeeper(const Eigen::Matrix3Xd& rest_points_mm, double cell_volume_mm3,
                           const GaussianField& rest_field, const Eigen::VectorXd& correction_weights,
                           const VolumeSettings& settings)
    : cell_volume_mm3_(cell_volume_mm3), settings_(settings), correction_weights_(correction_weights),
      correction_field_(0.0, rest_field.getCutoff()) {
  if (!(cell_volume_mm3 > 0.0) || !std::isfinite(cell_volume_mm3)) {
    throw std::invalid_argument("VolumeKeeper: cell volume " + std::to_string(cell_volume_mm3) + " mm³, expected > 0");
  }
  if (!(settings.tolerance > 0.0) || settings.max_iterations < 1 || !(settings.max_correction > 0.0) ||
      !std::isfinite(settings.max_correction) || !std::isfinite(settings.heaviside_width)) {
    throw std::invalid_argument("VolumeKeeper: settings need tolerance > 0, max_iterations >= 1, "
                                "a finite max_correction > 0 and a finite heaviside_width");
  }
  if (correction_weights.size() != rest_field.getNumCentres()) {
    throw std::invalid_argument("VolumeKeeper: " + std::to_string(correction_weights.size()) +
                                " correction weights for " + std::to_string(rest_field.getNumCentres()) + " centres");
  }
  for (Eigen::Index k = 0; k < correction_weights.size(); ++k) {
    if (!(correction_weights(k) >= 0.0) || !std::isfinite(correction_weights(k))) {
      throw std::invalid_argument("VolumeKeeper: correction weight " + std::to_string(k) + " is " +
                                  std::to_string(correction_weights(k)) + ", expected finite and >= 0");
    }
    if (correction_weights(k) > 0.0) corrected_.push_back(static_cast<int>(k));
  }
  const Eigen::Index n = static_cast<Eigen::Index>(corrected_.size());
  corrected_centres_.resize(3, n);
  Eigen::VectorXd weights(n), shapes(n);
  for (Eigen::Index q = 0; q < n; ++q) {
    const int k = corrected_[static_cast<size_t>(q)];
    corrected_centres_.col(q) = rest_field.getCentres().col(k);
    weights(q) = correction_weights(k);
    shapes(q) = rest_field.getShapes()(k);
  }
  correction_field_.setCentres(corrected_centres_, weights, shapes);
  width_ = settings.heaviside_width > 0.0 ? settings.heaviside_width : 0.5 * std::cbrt(cell_volume_mm3);
  rest_volume_mm3_ = calcVolume(rest_field, rest_points_mm, Eigen::VectorXd::Ones(rest_points_mm.cols()));
  if (!(rest_volume_mm3_ > 0.0)) {
    throw std::invalid_argument("VolumeKeeper: rest volume " + std::to_string(rest_volume_mm3_) + " mm³, expected > 0");
  }
}

double VolumeKeeper::sumVolume(double delta, const Eigen::VectorXd& jacobians, double* derivative) const {
  const double shift = delta - correction_;
  double volume = 0.0, slope = 0.0;
  for (Eigen::Index j = 0; j < values_.size(); ++j) {
    const double th = std::tanh((values_(j) + shift * corrections_(j)) / width_);
    volume += jacobians(j) * 0.5 * (1.0 + th);
    slope += jacobians(j) * 0.5 * (1.0 - th * th) / width_ * corrections_(j);
  }
  if (derivative != nullptr) *derivative = slope * cell_volume_mm3_;
  return volume * cell_volume_mm3_;
}

double VolumeKeeper::calcVolume(const GaussianField& field, const Eigen::Matrix3Xd& points_mm,
                                const Eigen::VectorXd& jacobians) const {
  if (jacobians.size() != points_mm.cols()) {
    throw std::invalid_argument("VolumeKeeper: " + std::to_string(jacobians.size()) + " Jacobians for " +
                                std::to_string(points_mm.cols()) + " points");
  }
  field.calcValues(points_mm, values_);
  double volume = 0.0;
  for (Eigen::Index j = 0; j < values_.size(); ++j) volume += jacobians(j) * 0.5 * (1.0 + std::tanh(values_(j) / width_));
  return volume * cell_volume_mm3_;
}

void VolumeKeeper::shiftWeights(GaussianField& field, double d) const {
  if (d == 0.0 || corrected_.empty()) return;
  Eigen::VectorXd weights = field.getWeights();
  for (int k : corrected_) weights(k) += d * correction_weights_(k);
  field.setWeights(weights);
}

void VolumeKeeper::removeCorrection(GaussianField& field) {
  shiftWeights(field, -correction_);
  guess_ = correction_;
  correction_ = 0.0;
}

VolumeReport VolumeKeeper::correct(GaussianField& field, const Eigen::Matrix3Xd& points_mm,
                                   const Eigen::VectorXd& jacobians) {
  if (field.getNumCentres() != correction_weights_.size()) {
    throw std::invalid_argument("VolumeKeeper::correct: the field has " + std::to_string(field.getNumCentres()) +
                                " centres, expected " + std::to_string(correction_weights_.size()));
  }
  VolumeReport report;
  double delta = correction_;
  double volume = calcVolume(field, points_mm, jacobians);
  report.volume_ratio_before = volume / rest_volume_mm3_;
  auto finish = [&](VolumeStop stop) {
    shiftWeights(field, delta - correction_);
    correction_ = guess_ = delta;
    report.correction = delta;
    report.volume_mm3 = volume;
    report.volume_ratio = volume / rest_volume_mm3_;
    report.stop_reason = stop;
    return report;
  };
  if (!settings_.enabled) return finish(VolumeStop::kDisabled);
  const double target = rest_volume_mm3_;
  const double tol = settings_.tolerance * target;
  if (std::abs(volume - target) <= tol) return finish(VolumeStop::kWithinTolerance);
  for (Eigen::Index q = 0; q < corrected_centres_.cols(); ++q)
    corrected_centres_.col(q) = field.getCentres().col(corrected_[static_cast<size_t>(q)]);
  correction_field_.setCentrePositions(corrected_centres_);
  correction_field_.calcValues(points_mm, corrections_);
  double lo = -settings_.max_correction;
  double hi = settings_.max_correction;
  const double v_lo = sumVolume(lo, jacobians, nullptr);
  const double v_hi = sumVolume(hi, jacobians, nullptr);
  if (v_hi < target - tol) {
    delta = hi;
    volume = v_hi;
    return finish(VolumeStop::kCorrectionBound);
  }
  if (v_lo > target + tol) {
    delta = lo;
    volume = v_lo;
    return finish(VolumeStop::kCorrectionBound);
  }
  delta = guess_ > lo && guess_ < hi ? guess_ : 0.5 * (lo + hi);
  for (int it = 0; it < settings_.max_iterations; ++it) {
    double slope = 0.0;
    volume = sumVolume(delta, jacobians, &slope);
    ++report.iterations;
    const double g = volume - target;
    if (std::abs(g) <= tol) return finish(VolumeStop::kWithinTolerance);
    if (g < 0.0) lo = delta; else hi = delta;
    double next = slope > 0.0 ? delta - g / slope : 0.5 * (lo + hi);
    if (!(next > lo && next < hi)) next = 0.5 * (lo + hi);
    delta = next;
  }
  volume = sumVolume(delta, jacobians, nullptr);
  return finish(std::abs(volume - target) <= tol ? VolumeStop::kWithinTolerance : VolumeStop::kIterationCap);
}

}  // namespace rbfmuscle
