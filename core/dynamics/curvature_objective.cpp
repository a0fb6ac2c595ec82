// SPDX-License-Identifier: Apache-2.0
#include "dynamics/curvature_objective.h"

#include <cmath>
#include <stdexcept>
#include <string>

namespace rbfmuscle {

namespace {

/// κ at p over the list, and (optionally) the active terms.
template <class Sink>
double sumCurvature(const DeformedField& field, const Eigen::Vector3d& p, const int* list, int count, Sink&& sink) {
  double laplacian = 0.0;
  field.visitActiveAmong(p, list, count, [&](int index, const DeformedKernel& k, double phi, const Eigen::Vector3d& ad) {
    const double g = 4.0 * ad.squaredNorm() - 2.0 * k.trace;
    laplacian += k.weight * phi * g;
    sink(index, phi, g, ad);
  });
  return laplacian / 3.0;
}

}  // namespace

CurvatureObjective::CurvatureObjective(Eigen::VectorXd weights_mm3, Eigen::VectorXd targets, NeighbourLists lists,
                                       std::vector<bool> free_mask, double regularisation,
                                       double regularisation_length_mm)
    : weights_mm3_(std::move(weights_mm3)),
      targets_(std::move(targets)),
      lists_(std::move(lists)),
      free_mask_(std::move(free_mask)) {
  if (weights_mm3_.size() != targets_.size() || lists_.size() != weights_mm3_.size())
    throw std::invalid_argument("CurvatureObjective: " + std::to_string(weights_mm3_.size()) + " weights, " +
                                std::to_string(targets_.size()) + " targets and " + std::to_string(lists_.size()) +
                                " neighbour lists differ");
  if (!weights_mm3_.allFinite() || (weights_mm3_.array() < 0.0).any() || !targets_.allFinite())
    throw std::invalid_argument("CurvatureObjective: weights must be finite and >= 0, targets finite");
  if (!(regularisation >= 0.0) || !std::isfinite(regularisation) || !(regularisation_length_mm > 0.0))
    throw std::invalid_argument("CurvatureObjective: need regularisation >= 0 and its length > 0");
  for (bool f : free_mask_) num_free_ += f ? 1 : 0;
  reference_ = weights_mm3_.dot(targets_.cwiseAbs2());
  if (!(reference_ > 0.0)) reference_ = std::max(weights_mm3_.sum(), 1e-300);
  anchor_weight_ = num_free_ > 0 ? regularisation / (num_free_ * regularisation_length_mm * regularisation_length_mm) : 0.0;
}

Eigen::VectorXd CurvatureObjective::calcCurvatures(const DeformedField& field, const Eigen::Matrix3Xd& points_mm,
                                                   const NeighbourLists& lists) {
  Eigen::VectorXd kappa(points_mm.cols());
  for (Eigen::Index j = 0; j < points_mm.cols(); ++j)
    kappa[j] = sumCurvature(field, points_mm.col(j), lists.begin(static_cast<int>(j)), lists.count(static_cast<int>(j)),
                            [](int, double, double, const Eigen::Vector3d&) {});
  return kappa;
}

double CurvatureObjective::evaluate(const DeformedField& field, const Eigen::Matrix3Xd& points_mm,
                                    const Eigen::Matrix3Xd& anchors_mm, Eigen::Matrix3Xd* gradient) const {
  const int n = field.getNumKernels();
  if (static_cast<int>(free_mask_.size()) != n || anchors_mm.cols() != n || points_mm.cols() != targets_.size())
    throw std::invalid_argument("CurvatureObjective::evaluate: sizes differ from the objective's");
  if (gradient) gradient->setZero(3, n);
  const std::vector<DeformedKernel>& kernels = field.getKernels();
  double curvature = 0.0;
  for (Eigen::Index j = 0; j < points_mm.cols(); ++j) {
    const int jj = static_cast<int>(j);
    terms_.clear();
    const double kappa = sumCurvature(field, points_mm.col(j), lists_.begin(jj), lists_.count(jj),
                                      [&](int k, double phi, double g, const Eigen::Vector3d& ad) {
                                        if (gradient && free_mask_[static_cast<size_t>(k)]) terms_.push_back({k, phi, g, ad});
                                      });
    const double residual = kappa - targets_[j];
    curvature += weights_mm3_[j] * residual * residual;
    if (!gradient) continue;
    const double scale = 2.0 * weights_mm3_[j] * residual / (3.0 * reference_);
    for (const Term& t : terms_) {
      const DeformedKernel& k = kernels[static_cast<size_t>(t.kernel)];
      gradient->col(t.kernel) += (scale * k.weight * t.phi) * (2.0 * t.g * t.ad - 8.0 * k.applyMetric(t.ad));
    }
  }
  double anchor = 0.0;
  for (int k = 0; k < n; ++k) {
    if (!free_mask_[static_cast<size_t>(k)]) continue;
    const Eigen::Vector3d d = field.getCentres().col(k) - anchors_mm.col(k);
    anchor += d.squaredNorm();
    if (gradient) gradient->col(k) += (2.0 * anchor_weight_) * d;
  }
  return curvature / reference_ + anchor_weight_ * anchor;
}

}  // namespace rbfmuscle
