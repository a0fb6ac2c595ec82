// SPDX-License-Identifier: Apache-2.0
#include "pipeline/surface_projection.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace rbfmuscle {

void checkSurfaceSettings(const SurfaceSettings& s) {
  if (s.newton_steps < 1 || s.max_exit_steps < 1 || !(s.tolerance > 0.0) || !(s.max_step_mm > 0.0))
    throw std::invalid_argument("SurfaceSettings: need newton_steps >= 1, max_exit_steps >= 1, tolerance > 0, max_step_mm > 0");
}

FieldSample projectByNewton(const ImplicitField& f, FieldSample at, Eigen::Vector3d& p, const SurfaceSettings& settings) {
  for (int step = 0; step < settings.newton_steps && std::abs(at.value) > settings.tolerance; ++step) {
    const double n2 = at.gradient.squaredNorm();
    if (!(n2 > 1e-24)) break;
    Eigen::Vector3d delta = -at.value * at.gradient / n2;
    const double length = delta.norm();
    if (length > settings.max_step_mm) delta *= settings.max_step_mm / length;
    bool lowered = false;
    for (int halving = 0; halving < 8 && !lowered; ++halving, delta *= 0.5) {
      const FieldSample trial = f.calcSample(p + delta);
      if (std::abs(trial.value) < std::abs(at.value)) {
        p += delta;
        at = trial;
        lowered = true;
      }
    }
    if (!lowered) break;
  }
  return at;
}

bool projectAlongLine(const ImplicitField& f, const Eigen::Vector3d& n, FieldSample& at, Eigen::Vector3d& p,
                      const SurfaceSettings& settings, double reach_mm) {
  const double f0 = at.value;
  if (std::abs(f0) <= settings.tolerance) return true;
  const Eigen::Vector3d direction = f0 > 0.0 ? n : Eigen::Vector3d(-n);
  const auto other_side = [&](double value) { return (value > 0.0) != (f0 > 0.0) || std::abs(value) <= settings.tolerance; };
  const auto slope = [&](const FieldSample& s) { return s.gradient.dot(direction); };
  double lo = 0.0;
  FieldSample at_lo = at;
  while (lo < reach_mm) {
    // The ray's own Newton step where f heads for 0 along it, else |f|; 0.05 mm to max_step_mm.
    const double newton = at_lo.value * slope(at_lo) < 0.0 ? -at_lo.value / slope(at_lo) : std::abs(at_lo.value);
    const double hi = std::min(reach_mm, lo + std::clamp(newton, 0.05, settings.max_step_mm));
    const FieldSample at_hi = f.calcSample(p + hi * direction);
    if (!other_side(at_hi.value)) {
      lo = hi, at_lo = at_hi;
      continue;
    }
    // Bracketed in [a, b]: Newton steps on the ray from b, bisection where one leaves the bracket.
    double a = lo, b = hi, t = hi;
    FieldSample at_t = at_hi;
    for (int round = 0; round < 60 && std::abs(at_t.value) > settings.tolerance; ++round) {
      const double step = slope(at_t) != 0.0 ? t - at_t.value / slope(at_t) : a;
      t = step > a && step < b ? step : 0.5 * (a + b);
      at_t = f.calcSample(p + t * direction);
      (other_side(at_t.value) ? b : a) = t;
    }
    p += t * direction;
    at = at_t;
    return true;
  }
  return false;
}

void exitBoneIntoMuscle(const ImplicitField& field, const Eigen::Vector3d& gradient, const ImplicitField& bones,
                        Eigen::Vector3d& p, const SurfaceSettings& settings) {
  double s = bones.calcValue(p);
  if (!(s < 0.0) || !(gradient.squaredNorm() > 1e-24)) return;
  const Eigen::Vector3d inward = gradient.normalized();
  const double reach_mm = -2.0 * s + settings.tolerance;
  double t = 0.0;
  for (int step = 0; step < settings.max_exit_steps && t <= reach_mm; ++step) {
    if (s >= -settings.tolerance) {
      const Eigen::Vector3d q = p + t * inward;
      if (field.calcValue(q) > 0.0) p = q;
      return;
    }
    t += -s + 0.5 * settings.tolerance;
    s = bones.calcValue(p + t * inward);
  }
}

FieldSample projectVertex(const ImplicitField& f, const Eigen::Vector3d& n, Eigen::Vector3d& p,
                          const SurfaceSettings& settings, double& start_value) {
  FieldSample at = f.calcSample(p);
  start_value = at.value;
  const double reach_mm = settings.newton_steps * settings.max_step_mm;  // as far as the Newton steps reach
  if (start_value > 0.0 && n.squaredNorm() > 0.0 && projectAlongLine(f, n.normalized(), at, p, settings, reach_mm))
    return at;
  return projectByNewton(f, at, p, settings);
}

}  // namespace rbfmuscle
