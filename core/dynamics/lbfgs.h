// SPDX-License-Identifier: Apache-2.0
#pragma once
/// @file
/// A small limited-memory BFGS minimiser with a backtracking line search, for the
/// few warm iterations a frame can afford.
#include <Eigen/Core>

#include <functional>
#include <string>
#include <vector>

namespace rbfmuscle {

/// Settings of LbfgsMinimiser.
struct LbfgsSettings {
  int max_iterations = 3;          ///< accepted steps at most, ≥ 0
  double cost_tolerance = 1e-3;    ///< stop when one step lowers E by less than this fraction of E
  double gradient_tolerance = 1e-3;  ///< stop when ‖∇E‖ ≤ this · ‖∇E₀‖
  double initial_step = 0.5;       ///< the first step moves the largest coordinate by this (unit of x)
  int memory = 6;                  ///< (s, y) pairs kept, ≥ 0 (0: steepest descent)
  int max_backtracks = 12;         ///< halvings of a step per iteration, ≥ 0
  double armijo = 1e-4;            ///< sufficient-decrease constant c₁ ∈ (0, 1)
};

/// Why a minimisation stopped.
enum class LbfgsStop {
  kGradientTolerance,  ///< ‖∇E‖ ≤ gradient_tolerance · ‖∇E₀‖ (or ∇E = 0)
  kCostTolerance,      ///< the last step's relative decrease was below cost_tolerance
  kIterationCap,       ///< max_iterations steps taken
  kLineSearchFailed,   ///< no halving of the step lowered E
  kNonFinite,          ///< E or ∇E at the start was not finite (x untouched)
};

/// Name of a stop reason ("gradient_tolerance", "cost_tolerance", "iteration_cap",
/// "line_search_failed", "non_finite").
std::string toString(LbfgsStop stop);

/// What a minimisation did.
struct LbfgsReport {
  int iterations = 0;          ///< accepted steps
  int evaluations = 0;         ///< objective evaluations
  double cost_initial = 0.0;   ///< E(x₀)
  double cost_final = 0.0;     ///< E at the result, ≤ cost_initial
  LbfgsStop stop = LbfgsStop::kIterationCap;
};

/// E(x) and ∇E(x) into `gradient` (resized by the caller to x's size).
using Objective = std::function<double(const Eigen::VectorXd& x, Eigen::VectorXd& gradient)>;

/// L-BFGS (two-loop recursion) with Armijo backtracking. The first step, and any step after a
/// direction that does not descend, is steepest descent scaled by initial_step. Every accepted
/// step lowers E, so E never rises; a trial with a non-finite E counts as failed (halved).
/// Deterministic. Buffers are kept between runs of the same size (no allocation then).
class LbfgsMinimiser {
 public:
  /// @throws std::invalid_argument for settings outside their ranges (names the field).
  explicit LbfgsMinimiser(const LbfgsSettings& settings = {});
  /// Minimises E from x (in place).
  LbfgsReport run(const Objective& objective, Eigen::VectorXd& x);
  /// The settings.
  const LbfgsSettings& getSettings() const { return settings_; }

 private:
  /// direction_ = −H ∇E by the two-loop recursion over the `stored` newest pairs (newest at
  /// index `newest`); the initial step length (1, or initial_step over the largest gradient
  /// coordinate when it falls back to steepest descent, which also forgets the pairs).
  double calcDirection(int& stored, int newest);
  /// Backtracks from `step` along direction_ until the Armijo condition holds; the accepted
  /// point and gradient are in x_trial_ and g_trial_. @return whether a step was accepted.
  bool searchLine(const Objective& objective, const Eigen::VectorXd& x, double cost, double step, double& trial_cost,
                  LbfgsReport& report);

  LbfgsSettings settings_;
  Eigen::VectorXd g_, x_trial_, g_trial_, direction_;
  std::vector<Eigen::VectorXd> s_, y_;
  std::vector<double> rho_, alpha_;
};

}  // namespace rbfmuscle
