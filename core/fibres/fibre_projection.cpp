#include "fibres/fibre_projection.h"

#include <cmath>
#include <stdexcept>
#include <string>

namespace rbfmuscle {

void checkProjectionSettings(const ProjectionSettings& s) {
  if (!(s.margin_mm > 0) || !std::isfinite(s.margin_mm))
    throw std::invalid_argument("ProjectionSettings: margin_mm must be > 0, got " + std::to_string(s.margin_mm));
  if (!(s.max_step_mm > 0) || !std::isfinite(s.max_step_mm))
    throw std::invalid_argument("ProjectionSettings: max_step_mm must be > 0, got " + std::to_string(s.max_step_mm));
  if (s.max_steps < 1)
    throw std::invalid_argument("ProjectionSettings: max_steps must be ≥ 1, got " + std::to_string(s.max_steps));
}

int projectInside(const GaussianField& field, const ProjectionSettings& settings, Eigen::Vector3d& p_mm) {
  checkProjectionSettings(settings);
  const double target = 2.0 * settings.margin_mm;
  int steps = 0;
  double f = field.calcValue(p_mm);
  while (f < settings.margin_mm && steps < settings.max_steps) {
    const Eigen::Vector3d g = field.calcGradient(p_mm);
    const double g2 = g.squaredNorm();
    if (g2 < 1e-24) break;
    Eigen::Vector3d delta = (target - f) / g2 * g;
    const double length = delta.norm();
    if (length > settings.max_step_mm) delta *= settings.max_step_mm / length;
    p_mm += delta;
    ++steps;
    f = field.calcValue(p_mm);
  }
  return steps;
}

void calcFibreLengths(const Eigen::Matrix3Xd& points_mm, int segments, Eigen::VectorXd& out) {
  if (segments < 1) throw std::invalid_argument("calcFibreLengths: segments must be ≥ 1, got " + std::to_string(segments));
  const Eigen::Index per = segments + 1;
  if (points_mm.cols() % per != 0)
    throw std::invalid_argument("calcFibreLengths: " + std::to_string(points_mm.cols()) +
                                " points is not a multiple of segments + 1 = " + std::to_string(per));
  const Eigen::Index n = points_mm.cols() / per;
  out.resize(n);
  for (Eigen::Index i = 0; i < n; ++i) {
    double length = 0;
    for (Eigen::Index j = 0; j < segments; ++j)
      length += (points_mm.col(i * per + j + 1) - points_mm.col(i * per + j)).norm();
    out(i) = length;
  }
}

}  // namespace rbfmuscle
