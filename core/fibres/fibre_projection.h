#pragma once
/// @file
/// Moving a point back inside a muscle field, and fibre lengths.
#include "rbf/gaussian_field.h"

#include <Eigen/Core>

namespace rbfmuscle {

/// How points are pushed inside {f ≥ margin}.
struct ProjectionSettings {
  /// A point is inside enough when f ≥ margin (field unit ≈ mm of depth, the fit's
  /// clamped signed distance); > 0.
  double margin_mm = 0.5;
  /// Largest move of one step (mm), > 0: bounds the Newton step where ∇f is small.
  double max_step_mm = 1.0;
  /// Step cap per point, ≥ 1.
  int max_steps = 30;
};

/// Pushes p along ∇f until f(p) ≥ margin: Newton steps on f = 2·margin,
/// δ = (2·margin − f) ∇f / ‖∇f‖², each shortened to max_step_mm, at most max_steps
/// (stops early if ‖∇f‖ < 1e-12). Returns the number of steps taken (0 when p was inside
/// enough); `p_mm` is left where the last step put it. Check f(p) ≥ margin afterwards.
/// @throws std::invalid_argument on bad settings.
int projectInside(const GaussianField& field, const ProjectionSettings& settings, Eigen::Vector3d& p_mm);

/// Checks the settings. @throws std::invalid_argument naming the bad value.
void checkProjectionSettings(const ProjectionSettings& settings);

/// Length of every fibre: fibre i is the polyline of columns i·(S+1) … i·(S+1)+S of
/// `points_mm` (3×N(S+1)); L_i = Σ_j ‖p_{j+1} − p_j‖ (mm). `out` is resized to N.
/// @throws std::invalid_argument if the column count is not a multiple of S+1 or S < 1.
void calcFibreLengths(const Eigen::Matrix3Xd& points_mm, int segments, Eigen::VectorXd& out);

}  // namespace rbfmuscle
