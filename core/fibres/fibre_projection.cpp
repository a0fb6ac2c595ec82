// SPDX-License-Identifier: Apache-2.0
#include "fibres/fibre_projection.h"

#include <algorithm>
#include <cmath>
#include <optional>
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
  if (s.max_halvings < 0)
    throw std::invalid_argument("ProjectionSettings: max_halvings must be ≥ 0, got " + std::to_string(s.max_halvings));
  if (!(s.end_max_move_mm >= 0) || !std::isfinite(s.end_max_move_mm))
    throw std::invalid_argument("ProjectionSettings: end_max_move_mm must be ≥ 0, got " +
                                std::to_string(s.end_max_move_mm));
}

ProjectionResult projectInside(const ImplicitField& field, const ProjectionSettings& settings, Eigen::Vector3d& p_mm,
                               double max_move_mm) {
  checkProjectionSettings(settings);
  if (!(max_move_mm >= 0))
    throw std::invalid_argument("projectInside: max_move_mm must be ≥ 0, got " + std::to_string(max_move_mm));
  const double target = 1.02 * settings.margin_mm;  // just above the margin: ProjectionSettings::margin_mm
  ProjectionResult result;
  result.value = field.calcValue(p_mm);
  if (result.value >= settings.margin_mm) return result;
  while (result.steps < settings.max_steps) {
    const double step_cap = std::min(settings.max_step_mm, max_move_mm - result.moved_mm);
    if (step_cap <= 1e-12) {
      result.stop = ProjectionStop::kMoveCap;
      return result;
    }
    const Eigen::Vector3d g = field.calcGradient(p_mm);
    const double g2 = g.squaredNorm();
    if (g2 < 1e-24) {
      result.stop = ProjectionStop::kNoAscent;
      return result;
    }
    Eigen::Vector3d delta = (target - result.value) / g2 * g;
    const double length = delta.norm();
    if (length > step_cap) delta *= step_cap / length;
    // Backtracking: halve the step until f rises.
    bool rose = false;
    for (int h = 0; h <= settings.max_halvings && !rose; ++h, delta *= 0.5) {
      const double f = field.calcValue(p_mm + delta);
      if (f > result.value) {
        p_mm += delta;
        result.moved_mm += delta.norm();
        result.value = f;
        rose = true;
      }
    }
    if (!rose) {
      result.stop = ProjectionStop::kNoAscent;
      return result;
    }
    ++result.steps;
    if (result.value >= settings.margin_mm) {
      result.stop = ProjectionStop::kReached;
      return result;
    }
  }
  result.stop = ProjectionStop::kStepCap;
  return result;
}

double placeBetweenInsideNeighbours(const ImplicitField& field, const ProjectionSettings& settings,
                                    const Eigen::Vector3d& a_mm, const Eigen::Vector3d& b_mm, double t,
                                    Eigen::Vector3d& p_mm, int samples) {
  const double fa = field.calcValue(a_mm), fb = field.calcValue(b_mm);
  if (!(fa > 0) || !(fb > 0))
    throw std::invalid_argument("placeBetweenInsideNeighbours: the neighbours must be inside (f > 0), got f(a) = " +
                                std::to_string(fa) + ", f(b) = " + std::to_string(fb));
  if (!(t > 0 && t < 1))
    throw std::invalid_argument("placeBetweenInsideNeighbours: t must be in (0, 1), got " + std::to_string(t));
  if (samples < 1)
    throw std::invalid_argument("placeBetweenInsideNeighbours: samples must be ≥ 1, got " + std::to_string(samples));
  const Eigen::Vector3d q = a_mm + t * (b_mm - a_mm);
  Eigen::Vector3d best = q;
  double best_f = field.calcValue(q);
  if (best_f <= 0) {
    const Eigen::Vector3d& end = t <= 0.5 ? a_mm : b_mm;
    for (int k = 1; k <= samples; ++k) {
      const Eigen::Vector3d s = q + (static_cast<double>(k) / samples) * (end - q);
      const double f = field.calcValue(s);
      if (f > best_f) {
        best = s;
        best_f = f;
      }
      if (f >= settings.margin_mm) break;
    }
  }
  p_mm = best;
  return projectInside(field, settings, p_mm).value;
}

double climbByPatternSearch(const ImplicitField& field, const ProjectionSettings& settings, Eigen::Vector3d& p_mm) {
  checkProjectionSettings(settings);
  const Eigen::Vector3d start = p_mm;
  double f = field.calcValue(p_mm), step = settings.max_step_mm;
  for (int moves = 0, halvings = 0; f <= 0.0 && moves < settings.max_steps && halvings <= settings.max_halvings;) {
    Eigen::Vector3d best = p_mm;
    double best_f = f;
    for (int x = -1; x <= 1; ++x)
      for (int y = -1; y <= 1; ++y)
        for (int z = -1; z <= 1; ++z) {
          if (x == 0 && y == 0 && z == 0) continue;
          const Eigen::Vector3d candidate = p_mm + step * Eigen::Vector3d(x, y, z).normalized();
          const double value = field.calcValue(candidate);
          if (value > best_f) best = candidate, best_f = value;
        }
    if (best_f > f) {
      p_mm = best, f = best_f, ++moves;
    } else {
      step /= 2, ++halvings;
    }
  }
  if (!(f > 0.0)) {
    p_mm = start;
    return field.calcValue(start);
  }
  return projectInside(field, settings, p_mm).value;
}

Eigen::Vector3d advanceInside(const ImplicitField& field, const ProjectionSettings& settings,
                              const Eigen::Vector3d& from_mm, const Eigen::Vector3d& to_mm) {
  checkProjectionSettings(settings);
  const Eigen::Vector3d step = to_mm - from_mm;
  const int samples = std::max(1, static_cast<int>(std::ceil(step.norm() / settings.max_step_mm)));
  // A sample at or above the margin lies above any start's level, so f(from) is needed only once
  // a sample falls below the margin: most moves cost one evaluation per sample.
  std::optional<double> level;
  double inside = 0.0;  // fraction of the step known inside
  for (int k = 1; k <= samples; ++k) {
    const double t = static_cast<double>(k) / samples;
    const double value = field.calcValue(from_mm + t * step);
    if (value >= settings.margin_mm) {
      inside = t;
      continue;
    }
    if (!level) {
      // Stay above the start's own level where it lies below the margin, so a point just below
      // the margin moves as one just above it does.
      const double start = field.calcValue(from_mm);
      if (!(start > 0.0)) return from_mm;
      level = std::min(start, settings.margin_mm);
    }
    if (value < *level) {
      double outside = t;
      for (int h = 0; h < settings.max_halvings; ++h) {
        const double middle = 0.5 * (inside + outside);
        (field.calcValue(from_mm + middle * step) >= *level ? inside : outside) = middle;
      }
      return from_mm + inside * step;
    }
    inside = t;
  }
  return to_mm;
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

void calcFibreLengths(const Eigen::Matrix3Xd& points_mm, int segments, const Eigen::Matrix3Xd& attachments_mm,
                      Eigen::VectorXd& out) {
  calcFibreLengths(points_mm, segments, out);
  if (attachments_mm.cols() != 2 * out.size())
    throw std::invalid_argument("calcFibreLengths: " + std::to_string(attachments_mm.cols()) + " attachments for " +
                                std::to_string(out.size()) + " fibres (2 each)");
  const Eigen::Index per = segments + 1;
  for (Eigen::Index i = 0; i < out.size(); ++i)
    out(i) += (points_mm.col(i * per) - attachments_mm.col(2 * i)).norm() +
              (points_mm.col(i * per + segments) - attachments_mm.col(2 * i + 1)).norm();
}

}  // namespace rbfmuscle
