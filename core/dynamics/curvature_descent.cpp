#include "dynamics/curvature_descent.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace rbfmuscle {

namespace {

double dot(const Eigen::Matrix3Xd& a, const Eigen::Matrix3Xd& b) { return (a.array() * b.array()).sum(); }

double maxColumnNorm(const Eigen::Matrix3Xd& d) {
  return d.cols() == 0 ? 0.0 : d.colwise().norm().maxCoeff();
}

void require(bool ok, const std::string& message) {
  if (!ok) throw std::invalid_argument("CurvatureDescent: " + message);
}

}  // namespace

std::string toString(DescentStop stop) {
  switch (stop) {
    case DescentStop::kGradientTolerance: return "gradient_tolerance";
    case DescentStop::kCostTolerance: return "cost_tolerance";
    case DescentStop::kIterationCap: return "iteration_cap";
    case DescentStop::kLineSearchFailed: return "line_search_failed";
    case DescentStop::kNonFinite: return "non_finite";
    case DescentStop::kNoFreeCentres: return "no_free_centres";
  }
  return "unknown";
}

CurvatureDescent::CurvatureDescent(const CurvatureCost& cost, std::vector<bool> free_mask,
                                   const DescentSettings& settings)
    : cost_(cost), free_mask_(std::move(free_mask)), settings_(settings) {
  const DescentSettings& s = settings_;
  require(std::isfinite(s.regularisation) && s.regularisation >= 0.0, "regularisation must be finite and >= 0");
  require(std::isfinite(s.regularisation_length_mm) && s.regularisation_length_mm > 0.0,
          "regularisation_length_mm must be > 0");
  require(s.max_iterations >= 1, "max_iterations must be >= 1");
  require(std::isfinite(s.cost_tolerance) && s.cost_tolerance >= 0.0, "cost_tolerance must be >= 0");
  require(std::isfinite(s.gradient_tolerance) && s.gradient_tolerance >= 0.0, "gradient_tolerance must be >= 0");
  require(std::isfinite(s.initial_step_mm) && s.initial_step_mm > 0.0, "initial_step_mm must be > 0");
  require(s.lbfgs_memory >= 0, "lbfgs_memory must be >= 0");
  require(s.max_backtracks >= 1, "max_backtracks must be >= 1");
  require(s.armijo > 0.0 && s.armijo < 1.0, "armijo must lie in (0, 1)");
  require(!free_mask_.empty(), "empty free mask");
  num_free_ = static_cast<int>(std::count(free_mask_.begin(), free_mask_.end(), true));
  const Eigen::VectorXd& w = cost_.getWeights();
  const Eigen::VectorXd& k0 = cost_.getTargetCurvatures();
  reference_energy_ = (w.array() * k0.array().square()).sum();
  if (!(reference_energy_ > 0.0)) reference_energy_ = w.sum();
  if (!(reference_energy_ > 0.0)) reference_energy_ = 1.0;
  const Eigen::Index N = static_cast<Eigen::Index>(free_mask_.size());
  for (Eigen::Matrix3Xd* m : {&cost_gradient_, &x_, &g_, &x_trial_, &g_trial_, &direction_}) m->setZero(3, N);
  s_hist_.assign(static_cast<size_t>(s.lbfgs_memory), Eigen::Matrix3Xd::Zero(3, N));
  y_hist_.assign(static_cast<size_t>(s.lbfgs_memory), Eigen::Matrix3Xd::Zero(3, N));
  rho_hist_.assign(static_cast<size_t>(s.lbfgs_memory), 0.0);
  alpha_hist_.assign(static_cast<size_t>(s.lbfgs_memory), 0.0);
}

double CurvatureDescent::calcObjective(const GaussianField& field, const Eigen::Matrix3Xd& anchors_mm,
                                       Eigen::Matrix3Xd& gradient) const {
  const Eigen::Index N = static_cast<Eigen::Index>(free_mask_.size());
  if (field.getNumCentres() != N || anchors_mm.cols() != N) {
    throw std::invalid_argument("CurvatureDescent: field has " + std::to_string(field.getNumCentres()) +
                                " centres and anchors " + std::to_string(anchors_mm.cols()) + ", mask " +
                                std::to_string(N));
  }
  const double curvature = cost_.calcCostAndGradient(field, cost_gradient_) / reference_energy_;
  last_curvature_cost_ = curvature;
  const double reg = num_free_ > 0 ? settings_.regularisation /
                                         (num_free_ * settings_.regularisation_length_mm * settings_.regularisation_length_mm)
                                   : 0.0;
  gradient.resize(3, N);
  double regulariser = 0.0;
  const Eigen::Matrix3Xd& xi = field.getCentres();
  for (Eigen::Index k = 0; k < N; ++k) {
    if (!free_mask_[static_cast<size_t>(k)]) {
      gradient.col(k).setZero();
      continue;
    }
    const Eigen::Vector3d delta = xi.col(k) - anchors_mm.col(k);
    regulariser += delta.squaredNorm();
    gradient.col(k) = cost_gradient_.col(k) / reference_energy_ + (2.0 * reg) * delta;
  }
  return curvature + reg * regulariser;
}

DescentReport CurvatureDescent::run(GaussianField& field, const Eigen::Matrix3Xd& anchors_mm) {
  DescentReport report;
  double energy = calcObjective(field, anchors_mm, g_);
  report.evaluations = 1;
  report.cost_initial = energy;
  report.cost_final = energy;
  report.curvature_cost_final = last_curvature_cost_;
  report.gradient_norm_initial = g_.norm();
  report.gradient_norm_final = report.gradient_norm_initial;
  if (num_free_ == 0) {
    report.stop_reason = DescentStop::kNoFreeCentres;
    return report;
  }
  if (!std::isfinite(energy) || !g_.allFinite()) {
    report.stop_reason = DescentStop::kNonFinite;
    return report;
  }
  const double g0 = report.gradient_norm_initial;
  if (g0 == 0.0) {
    report.stop_reason = DescentStop::kGradientTolerance;
    return report;
  }
  x_ = field.getCentres();
  const int memory = settings_.lbfgs_memory;
  int stored = 0, newest = -1;
  const double max_step_mm = 20.0 * settings_.initial_step_mm;
  report.stop_reason = DescentStop::kIterationCap;
  double curvature = last_curvature_cost_;
  for (int it = 0; it < settings_.max_iterations; ++it) {
    double t = 1.0;
    bool steepest = stored == 0;
    if (!steepest) {
      direction_ = g_;
      for (int i = 0; i < stored; ++i) {
        const int h = (newest - i + memory) % memory;
        alpha_hist_[h] = rho_hist_[h] * dot(s_hist_[h], direction_);
        direction_ -= alpha_hist_[h] * y_hist_[h];
      }
      const double gamma = dot(s_hist_[newest], y_hist_[newest]) / y_hist_[newest].squaredNorm();
      direction_ *= gamma;
      for (int i = stored - 1; i >= 0; --i) {
        const int h = (newest - i + memory) % memory;
        const double beta = rho_hist_[h] * dot(y_hist_[h], direction_);
        direction_ += (alpha_hist_[h] - beta) * s_hist_[h];
      }
      direction_ = -direction_;
      if (!(dot(g_, direction_) < 0.0) || !direction_.allFinite()) {
        steepest = true;
        stored = 0;
      }
    }
    if (steepest) {
      direction_ = -g_;
      t = settings_.initial_step_mm / maxColumnNorm(direction_);
    }
    const double longest = t * maxColumnNorm(direction_);
    if (longest > max_step_mm) t *= max_step_mm / longest;
    const double slope = dot(g_, direction_);
    bool accepted = false;
    double trial_energy = energy;
    for (int bt = 0; bt < settings_.max_backtracks; ++bt, t *= 0.5) {
      x_trial_ = x_ + t * direction_;
      if (!x_trial_.allFinite()) continue;
      field.setCentrePositions(x_trial_);
      trial_energy = calcObjective(field, anchors_mm, g_trial_);
      ++report.evaluations;
      if (std::isfinite(trial_energy) && g_trial_.allFinite() &&
          trial_energy <= energy + settings_.armijo * t * slope && trial_energy <= energy) {
        accepted = true;
        break;
      }
    }
    if (!accepted) {
      field.setCentrePositions(x_);
      report.stop_reason = DescentStop::kLineSearchFailed;
      break;
    }
    if (memory > 0) {
      const double sy = ((x_trial_ - x_).array() * (g_trial_ - g_).array()).sum();
      const double sn = (x_trial_ - x_).norm(), yn = (g_trial_ - g_).norm();
      if (sy > 1e-12 * sn * yn && sy > 0.0) {
        const int h = (newest + 1) % memory;
        s_hist_[h] = x_trial_ - x_;
        y_hist_[h] = g_trial_ - g_;
        rho_hist_[h] = 1.0 / sy;
        newest = h;
        stored = std::min(stored + 1, memory);
      }
    }
    const double previous = energy;
    x_.swap(x_trial_);
    g_.swap(g_trial_);
    energy = trial_energy;
    curvature = last_curvature_cost_;
    ++report.iterations;
    if (g_.norm() <= settings_.gradient_tolerance * g0) {
      report.stop_reason = DescentStop::kGradientTolerance;
      break;
    }
    if (previous - energy < settings_.cost_tolerance * previous) {
      report.stop_reason = DescentStop::kCostTolerance;
      break;
    }
  }
  report.cost_final = energy;
  report.curvature_cost_final = curvature;
  report.gradient_norm_final = g_.norm();
  return report;
}

}  // namespace rbfmuscle
