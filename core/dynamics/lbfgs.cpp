// SPDX-License-Identifier: Apache-2.0
#include "dynamics/lbfgs.h"

#include <cmath>
#include <stdexcept>

namespace rbfmuscle {

std::string toString(LbfgsStop stop) {
  switch (stop) {
    case LbfgsStop::kGradientTolerance: return "gradient_tolerance";
    case LbfgsStop::kCostTolerance: return "cost_tolerance";
    case LbfgsStop::kIterationCap: return "iteration_cap";
    case LbfgsStop::kLineSearchFailed: return "line_search_failed";
    case LbfgsStop::kNonFinite: return "non_finite";
  }
  return "unknown";
}

LbfgsMinimiser::LbfgsMinimiser(const LbfgsSettings& settings) : settings_(settings) {
  const LbfgsSettings& s = settings_;
  if (s.max_iterations < 0) throw std::invalid_argument("LbfgsSettings::max_iterations must be >= 0");
  if (!(s.cost_tolerance >= 0.0)) throw std::invalid_argument("LbfgsSettings::cost_tolerance must be >= 0");
  if (!(s.gradient_tolerance >= 0.0)) throw std::invalid_argument("LbfgsSettings::gradient_tolerance must be >= 0");
  if (!(s.initial_step > 0.0) || !std::isfinite(s.initial_step))
    throw std::invalid_argument("LbfgsSettings::initial_step must be > 0");
  if (s.memory < 0) throw std::invalid_argument("LbfgsSettings::memory must be >= 0");
  if (s.max_backtracks < 0) throw std::invalid_argument("LbfgsSettings::max_backtracks must be >= 0");
  if (!(s.armijo > 0.0 && s.armijo < 1.0)) throw std::invalid_argument("LbfgsSettings::armijo must lie in (0, 1)");
}

double LbfgsMinimiser::calcDirection(int& stored, int newest) {
  direction_ = -g_;
  for (int i = 0; i < stored; ++i) {
    const int m = (newest - i + settings_.memory) % settings_.memory;
    alpha_[static_cast<size_t>(m)] = rho_[static_cast<size_t>(m)] * s_[static_cast<size_t>(m)].dot(direction_);
    direction_ -= alpha_[static_cast<size_t>(m)] * y_[static_cast<size_t>(m)];
  }
  if (stored > 0) {
    const size_t m = static_cast<size_t>(newest);
    direction_ *= s_[m].dot(y_[m]) / y_[m].squaredNorm();
    for (int i = stored - 1; i >= 0; --i) {
      const size_t k = static_cast<size_t>((newest - i + settings_.memory) % settings_.memory);
      const double beta = rho_[k] * y_[k].dot(direction_);
      direction_ += (alpha_[k] - beta) * s_[k];
    }
  }
  if (stored > 0 && g_.dot(direction_) < 0.0) return 1.0;
  direction_ = -g_;  // steepest descent, largest coordinate moved by initial_step
  stored = 0;
  return settings_.initial_step / g_.cwiseAbs().maxCoeff();
}

bool LbfgsMinimiser::searchLine(const Objective& objective, const Eigen::VectorXd& x, double cost, double step,
                                double& trial_cost, LbfgsReport& report) {
  const double slope = g_.dot(direction_);
  for (int b = 0; b <= settings_.max_backtracks; ++b, step *= 0.5) {
    x_trial_ = x + step * direction_;
    trial_cost = objective(x_trial_, g_trial_);
    ++report.evaluations;
    if (std::isfinite(trial_cost) && g_trial_.allFinite() && trial_cost <= cost + settings_.armijo * step * slope)
      return true;
  }
  return false;
}

LbfgsReport LbfgsMinimiser::run(const Objective& objective, Eigen::VectorXd& x) {
  LbfgsReport report;
  const Eigen::Index n = x.size();
  g_.resize(n);
  g_trial_.resize(n);
  double cost = objective(x, g_);
  report.evaluations = 1;
  report.cost_initial = report.cost_final = cost;
  if (!std::isfinite(cost) || !g_.allFinite()) {
    report.stop = LbfgsStop::kNonFinite;
    return report;
  }
  const double g0 = g_.norm();
  s_.resize(static_cast<size_t>(settings_.memory));
  y_.resize(static_cast<size_t>(settings_.memory));
  rho_.assign(static_cast<size_t>(settings_.memory), 0.0);
  alpha_.assign(static_cast<size_t>(settings_.memory), 0.0);
  int stored = 0, newest = -1;
  report.stop = LbfgsStop::kIterationCap;
  for (int it = 0; it < settings_.max_iterations; ++it) {
    const double gnorm = g_.norm();
    if (gnorm == 0.0 || gnorm <= settings_.gradient_tolerance * g0) {
      report.stop = LbfgsStop::kGradientTolerance;
      break;
    }
    const double step = calcDirection(stored, newest);
    double trial_cost = cost;
    const bool accepted = searchLine(objective, x, cost, step, trial_cost, report);
    if (!accepted) {
      report.stop = LbfgsStop::kLineSearchFailed;
      break;
    }
    if (settings_.memory > 0) {
      newest = (newest + 1) % settings_.memory;
      const size_t m = static_cast<size_t>(newest);
      s_[m] = x_trial_ - x;
      y_[m] = g_trial_ - g_;
      const double sy = s_[m].dot(y_[m]);
      if (sy > 1e-300) {
        rho_[m] = 1.0 / sy;
        stored = std::min(stored + 1, settings_.memory);
      } else {  // curvature condition fails: forget the history
        stored = 0;
      }
    }
    const double decrease = cost - trial_cost;
    x.swap(x_trial_);
    g_.swap(g_trial_);
    cost = trial_cost;
    ++report.iterations;
    report.cost_final = cost;
    if (decrease < settings_.cost_tolerance * std::abs(cost)) {
      report.stop = LbfgsStop::kCostTolerance;
      break;
    }
  }
  return report;
}

}  // namespace rbfmuscle
