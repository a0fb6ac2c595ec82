#include "dynamics/volume_keeper.h"

#include <cmath>
#include <stdexcept>

namespace rbfmuscle {

std::string toString(VolumeStop stop) {
  switch (stop) {
    case VolumeStop::kWithinTolerance: return "within_tolerance";
    case VolumeStop::kIterationCap: return "iteration_cap";
    case VolumeStop::kOffsetBound: return "offset_bound";
    case VolumeStop::kDisabled: return "disabled";
  }
  return "unknown";
}

VolumeKeeper::VolumeKeeper(const Eigen::Matrix3Xd& rest_points_mm, double cell_volume_mm3,
                           const GaussianField& rest_field, const VolumeSettings& settings)
    : cell_volume_mm3_(cell_volume_mm3), settings_(settings), rest_offset_(rest_field.getOffset()) {
  if (!(cell_volume_mm3 > 0.0) || !std::isfinite(cell_volume_mm3)) {
    throw std::invalid_argument("VolumeKeeper: cell volume " + std::to_string(cell_volume_mm3) + " mm³, expected > 0");
  }
  if (!(settings.tolerance > 0.0) || settings.max_iterations < 1 || !(settings.max_offset_change > 0.0) ||
      !std::isfinite(settings.heaviside_width)) {
    throw std::invalid_argument("VolumeKeeper: settings need tolerance > 0, max_iterations >= 1, "
                                "max_offset_change > 0 and a finite heaviside_width");
  }
  width_ = settings.heaviside_width > 0.0 ? settings.heaviside_width : 0.5 * std::cbrt(cell_volume_mm3);
  const Eigen::VectorXd ones = Eigen::VectorXd::Ones(rest_points_mm.cols());
  rest_volume_mm3_ = calcVolume(rest_field, rest_points_mm, ones);
  if (!(rest_volume_mm3_ > 0.0)) {
    throw std::invalid_argument("VolumeKeeper: rest volume " + std::to_string(rest_volume_mm3_) + " mm³, expected > 0");
  }
}

double VolumeKeeper::sumVolume(double offset, const Eigen::VectorXd& jacobians, double* derivative) const {
  double volume = 0.0, slope = 0.0;
  for (Eigen::Index j = 0; j < sums_.size(); ++j) {
    const double th = std::tanh((sums_(j) + offset) / width_);
    volume += jacobians(j) * 0.5 * (1.0 + th);
    slope += jacobians(j) * 0.5 * (1.0 - th * th) / width_;
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
  field.calcValues(points_mm, sums_);
  sums_.array() -= field.getOffset();
  return sumVolume(field.getOffset(), jacobians, nullptr);
}

VolumeReport VolumeKeeper::correct(GaussianField& field, const Eigen::Matrix3Xd& points_mm,
                                   const Eigen::VectorXd& jacobians) {
  VolumeReport report;
  double b = field.getOffset();
  double volume = calcVolume(field, points_mm, jacobians);
  report.volume_ratio_before = volume / rest_volume_mm3_;
  auto finish = [&](VolumeStop stop) {
    field.setOffset(b);
    report.offset = b;
    report.volume_mm3 = volume;
    report.volume_ratio = volume / rest_volume_mm3_;
    report.stop_reason = stop;
    return report;
  };
  if (!settings_.enabled) return finish(VolumeStop::kDisabled);
  const double target = rest_volume_mm3_;
  const double tol = settings_.tolerance * target;
  if (std::abs(volume - target) <= tol) return finish(VolumeStop::kWithinTolerance);
  double lo = rest_offset_ - settings_.max_offset_change;
  double hi = rest_offset_ + settings_.max_offset_change;
  const double v_lo = sumVolume(lo, jacobians, nullptr);
  const double v_hi = sumVolume(hi, jacobians, nullptr);
  if (v_hi < target - tol) {
    b = hi;
    volume = v_hi;
    return finish(VolumeStop::kOffsetBound);
  }
  if (v_lo > target + tol) {
    b = lo;
    volume = v_lo;
    return finish(VolumeStop::kOffsetBound);
  }
  if (!(b > lo && b < hi)) b = 0.5 * (lo + hi);
  for (int it = 0; it < settings_.max_iterations; ++it) {
    double slope = 0.0;
    volume = sumVolume(b, jacobians, &slope);
    ++report.iterations;
    const double g = volume - target;
    if (std::abs(g) <= tol) return finish(VolumeStop::kWithinTolerance);
    if (g < 0.0) lo = b; else hi = b;
    double next = slope > 0.0 ? b - g / slope : 0.5 * (lo + hi);
    if (!(next > lo && next < hi)) next = 0.5 * (lo + hi);
    b = next;
  }
  volume = sumVolume(b, jacobians, nullptr);
  return finish(std::abs(volume - target) <= tol ? VolumeStop::kWithinTolerance : VolumeStop::kIterationCap);
}

}  // namespace rbfmuscle
