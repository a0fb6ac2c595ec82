// SPDX-License-Identifier: Apache-2.0
#include "pipeline/descent_stage.h"

#include <algorithm>
#include <stdexcept>

namespace rbfmuscle {

namespace {

LbfgsSettings toLbfgs(const DescentSettings& s) {
  if (s.max_iterations < 0 || s.points < 1) throw std::invalid_argument("DescentSettings: need max_iterations >= 0, points >= 1");
  LbfgsSettings l;
  l.max_iterations = s.max_iterations;
  l.cost_tolerance = s.cost_tolerance;
  return l;
}

}  // namespace

DescentStage::DescentStage(const DeformedField& rest, const Eigen::Matrix3Xd& quadrature_mm,
                           const Eigen::VectorXd& weights_mm3, std::vector<bool> free_mask,
                           const DescentSettings& settings)
    : settings_(settings), minimiser_(toLbfgs(settings)) {
  const int m = static_cast<int>(quadrature_mm.cols());
  const int stride = std::max(1, m / std::max(1, settings.points));
  for (int j = 0; j < m; j += stride) subset_.push_back(j);
  const int k = static_cast<int>(subset_.size());
  Eigen::Matrix3Xd points(3, k);
  Eigen::VectorXd weights(k);
  for (int i = 0; i < k; ++i) {
    points.col(i) = quadrature_mm.col(subset_[static_cast<size_t>(i)]);
    weights[i] = weights_mm3[subset_[static_cast<size_t>(i)]] * stride;
  }
  for (size_t i = 0; i < free_mask.size(); ++i)
    if (free_mask[i]) free_kernels_.push_back(static_cast<int>(i));
  NeighbourLists lists = findMaterialNeighbours(rest, points);
  Eigen::VectorXd targets = CurvatureObjective::calcCurvatures(rest, points, lists);
  objective_ = std::make_unique<CurvatureObjective>(std::move(weights), std::move(targets), std::move(lists),
                                                    std::move(free_mask), settings.regularisation);
}

void DescentStage::run(MuscleState& state, const FrameInput&) {
  points_mm_.resize(3, static_cast<Eigen::Index>(subset_.size()));
  for (size_t i = 0; i < subset_.size(); ++i) points_mm_.col(static_cast<Eigen::Index>(i)) = state.quadrature_mm.col(subset_[i]);
  centres_mm_ = state.field.getCentres();
  x_.resize(3 * static_cast<Eigen::Index>(free_kernels_.size()));
  for (size_t i = 0; i < free_kernels_.size(); ++i) x_.segment<3>(3 * static_cast<Eigen::Index>(i)) = centres_mm_.col(free_kernels_[i]);
  const Objective objective = [&](const Eigen::VectorXd& x, Eigen::VectorXd& g) {
    for (size_t i = 0; i < free_kernels_.size(); ++i) centres_mm_.col(free_kernels_[i]) = x.segment<3>(3 * static_cast<Eigen::Index>(i));
    state.field.setCentres(centres_mm_);
    const double e = objective_->evaluate(state.field, points_mm_, state.anchors_mm, &gradient_);
    g.resize(x.size());
    for (size_t i = 0; i < free_kernels_.size(); ++i) g.segment<3>(3 * static_cast<Eigen::Index>(i)) = gradient_.col(free_kernels_[i]);
    return e;
  };
  const LbfgsReport lbfgs = minimiser_.run(objective, x_);
  for (size_t i = 0; i < free_kernels_.size(); ++i) centres_mm_.col(free_kernels_[i]) = x_.segment<3>(3 * static_cast<Eigen::Index>(i));
  state.field.setCentres(centres_mm_);
  report_ = Report{lbfgs.cost_final, static_cast<double>(lbfgs.iterations), static_cast<double>(static_cast<int>(lbfgs.stop))};
}

}  // namespace rbfmuscle
