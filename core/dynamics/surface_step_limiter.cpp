#include "dynamics/surface_step_limiter.h"

#include "dynamics/field_surface.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <utility>

namespace rbfmuscle {

std::string toString(StepLimitStop stop) {
  switch (stop) {
    case StepLimitStop::kWithinLimit: return "within_limit";
    case StepLimitStop::kScaled: return "scaled";
    case StepLimitStop::kHeld: return "held";
    case StepLimitStop::kOverLimit: return "over_limit";
    case StepLimitStop::kDisabled: return "disabled";
  }
  return "unknown";
}

SurfaceStepLimiter::SurfaceStepLimiter(const StepLimitSettings& settings) : settings_(settings) {
  if (!(settings.cell_mm > 0.0) || !std::isfinite(settings.cell_mm)) {
    throw std::invalid_argument("StepLimitSettings::cell_mm " + std::to_string(settings.cell_mm) + ", expected > 0");
  }
  if (settings.max_trials < 1) {
    throw std::invalid_argument("StepLimitSettings::max_trials " + std::to_string(settings.max_trials) + ", expected >= 1");
  }
  if (std::isnan(settings.max_step_mm)) throw std::invalid_argument("StepLimitSettings::max_step_mm is NaN");
}

void SurfaceStepLimiter::setPreviousSurface(const GaussianField& field, const Eigen::AlignedBox3d& box_mm) {
  last_surface_ = extractFieldSurface(field, box_mm, settings_.cell_mm);
  adoptLastSurface();
}

void SurfaceStepLimiter::adoptLastSurface() {
  previous_.reset();
  if (last_surface_.countTriangles() > 0) previous_.emplace(std::move(last_surface_), false);
  last_surface_ = TriangleMesh{};
}

double SurfaceStepLimiter::calcExcess(const GaussianField& field, const Eigen::AlignedBox3d& box_mm,
                                      const std::vector<Eigen::Isometry3d>& bone_steps_M, double cap_mm,
                                      TriangleMesh& mesh) const {
  mesh = extractFieldSurface(field, box_mm, settings_.cell_mm);
  if (!previous_) return 0.0;
  double worst = 0.0;
#pragma omp parallel for schedule(static) reduction(max : worst)
  for (int v = 0; v < mesh.countVertices(); ++v) {
    const Eigen::Vector3d y = mesh.vertices_mm.col(v);
    double bone_move_mm = 0.0;
    for (const Eigen::Isometry3d& step : bone_steps_M) bone_move_mm = std::max(bone_move_mm, (step * y - y).norm());
    const double allowed = bone_move_mm + settings_.max_step_mm;
    // Most points are within their allowance: a search pruned to it is cheap.
    if (previous_->calcUnsignedDistanceWithin(y, allowed) <= allowed) continue;
    const double d = previous_->calcUnsignedDistanceWithin(y, allowed + cap_mm);
    worst = std::max(worst, std::min(d - allowed, cap_mm));
  }
  return worst;
}

StepLimitReport SurfaceStepLimiter::run(const GaussianField& start, GaussianField& field, const Eigen::AlignedBox3d& box_mm,
                                        const std::vector<Eigen::Isometry3d>& bone_steps_M) {
  StepLimitReport report;
  if (!(settings_.max_step_mm > 0.0) || !previous_) return report;
  if (start.getNumCentres() != field.getNumCentres() || start.getShapes() != field.getShapes() ||
      start.getOffset() != field.getOffset() || start.getCutoff() != field.getCutoff()) {
    throw std::invalid_argument("SurfaceStepLimiter::run: the start and end fields differ in more than centres and weights");
  }
  if (box_mm.isEmpty()) throw std::invalid_argument("SurfaceStepLimiter::run: empty box");
  const double cap = 4.0 * settings_.max_step_mm;
  report.full_excess_mm = report.excess_mm = calcExcess(field, box_mm, bone_steps_M, cap, last_surface_);
  report.stop_reason = StepLimitStop::kWithinLimit;
  if (report.full_excess_mm <= 0.0) return report;

  const Eigen::Matrix3Xd end_centres = field.getCentres();
  const Eigen::VectorXd end_weights = field.getWeights();
  const auto setScale = [&](double t) {
    field.setCentrePositions(start.getCentres() + t * (end_centres - start.getCentres()));
    field.setWeights(start.getWeights() + t * (end_weights - start.getWeights()));
  };
  // The start first, then bisection for the largest t within the limit. While no t is within
  // it, the one of least excess is kept (the start can be worse than the end).
  double low = 0.0, high = 1.0, chosen = 1.0;
  bool within = false;
  const auto tryScale = [&](double t) {
    setScale(t);
    const double excess = calcExcess(field, box_mm, bone_steps_M, cap, trial_surface_);
    const bool ok = excess <= 0.0;
    if ((ok && (!within || t > chosen)) || (!ok && !within && excess < report.excess_mm)) {
      chosen = t;
      report.excess_mm = excess;
      std::swap(last_surface_, trial_surface_);
    }
    within = within || ok;
    return ok;
  };
  tryScale(0.0);
  for (report.trials = 1; report.trials < settings_.max_trials; ++report.trials) {
    const double t = 0.5 * (low + high);
    (tryScale(t) ? low : high) = t;
  }
  setScale(chosen);
  report.scale = chosen;
  report.stop_reason = !within ? StepLimitStop::kOverLimit : chosen > 0.0 ? StepLimitStop::kScaled : StepLimitStop::kHeld;
  return report;
}

}  // namespace rbfmuscle
