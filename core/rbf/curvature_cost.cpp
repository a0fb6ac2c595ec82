#include "rbf/curvature_cost.h"

#include "rbf/gaussian_terms.h"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>

namespace rbfmuscle {

namespace {

/// Blocks per evaluation (at most) and points per block (at least): enough
/// blocks for load balance, few enough that the per-block gradient buffers
/// (3 × N each) stay small.
constexpr Eigen::Index kMaxBlocks = 64;
constexpr Eigen::Index kMinBlockSize = 128;

void checkPoints(const Eigen::Matrix3Xd& points_mm) {
  for (Eigen::Index q = 0; q < points_mm.cols(); ++q)
    if (!points_mm.col(q).allFinite()) {
      std::ostringstream s;
      s << "CurvatureCost: quadrature point " << q << " = (" << points_mm.col(q).transpose()
        << ") mm, expected finite coordinates";
      throw std::invalid_argument(s.str());
    }
}

void checkTargets(const Eigen::VectorXd& targets, Eigen::Index m) {
  if (targets.size() != m) {
    std::ostringstream s;
    s << "CurvatureCost: " << targets.size() << " target curvatures, expected " << m;
    throw std::invalid_argument(s.str());
  }
  for (Eigen::Index q = 0; q < m; ++q)
    if (!std::isfinite(targets[q])) {
      std::ostringstream s;
      s << "CurvatureCost: target curvature " << q << " = " << targets[q]
        << ", expected a finite value";
      throw std::invalid_argument(s.str());
    }
}

}  // namespace

CurvatureCost::CurvatureCost(const Eigen::Matrix3Xd& points_mm,
                             const Eigen::VectorXd& weights_mm3,
                             const Eigen::VectorXd& target_curvatures) {
  if (weights_mm3.size() != points_mm.cols()) {
    std::ostringstream s;
    s << "CurvatureCost: " << points_mm.cols() << " quadrature points but "
      << weights_mm3.size() << " weights, expected equal counts";
    throw std::invalid_argument(s.str());
  }
  checkPoints(points_mm);
  for (Eigen::Index q = 0; q < weights_mm3.size(); ++q)
    if (!(std::isfinite(weights_mm3[q]) && weights_mm3[q] >= 0.0)) {
      std::ostringstream s;
      s << "CurvatureCost: quadrature weight " << q << " = " << weights_mm3[q]
        << " mm^3, expected a finite value >= 0";
      throw std::invalid_argument(s.str());
    }
  checkTargets(target_curvatures, points_mm.cols());
  points_mm_ = points_mm;
  weights_mm3_ = weights_mm3;
  target_curvatures_ = target_curvatures;
}

CurvatureCost CurvatureCost::fromField(const GaussianField& field,
                                       const Eigen::Matrix3Xd& points_mm,
                                       const Eigen::VectorXd& weights_mm3) {
  return CurvatureCost(points_mm, weights_mm3, calcTargetCurvatures(field, points_mm));
}

Eigen::VectorXd CurvatureCost::calcTargetCurvatures(const GaussianField& field,
                                                    const Eigen::Matrix3Xd& points_mm) {
  Eigen::VectorXd kappa;
  field.calcMeanCurvatures(points_mm, kappa);
  return kappa;
}

void CurvatureCost::setPoints(const Eigen::Matrix3Xd& points_mm) {
  if (points_mm.cols() != points_mm_.cols()) {
    std::ostringstream s;
    s << "CurvatureCost::setPoints: " << points_mm.cols() << " points, expected "
      << points_mm_.cols();
    throw std::invalid_argument(s.str());
  }
  checkPoints(points_mm);
  points_mm_ = points_mm;
  lists_built_ = false;
}

void CurvatureCost::setTargetCurvatures(const Eigen::VectorXd& target_curvatures) {
  checkTargets(target_curvatures, points_mm_.cols());
  target_curvatures_ = target_curvatures;
}

Eigen::Index CurvatureCost::findBlockSize() const {
  const Eigen::Index m = points_mm_.cols();
  return std::max(kMinBlockSize, (m + kMaxBlocks - 1) / kMaxBlocks);
}

bool CurvatureCost::listsAreValid(const GaussianField& field) const {
  if (!lists_built_ || listed_centres_mm_.cols() != field.getNumCentres() || listed_shapes_ != field.getShapes() ||
      listed_cutoff_ != field.getCutoff())
    return false;
  const double skin2 = kNeighbourSkinMm * kNeighbourSkinMm;
  const Eigen::Matrix3Xd& centres = field.getCentres();
  for (Eigen::Index k = 0; k < centres.cols(); ++k)
    if ((centres.col(k) - listed_centres_mm_.col(k)).squaredNorm() > skin2) return false;
  return true;
}

void CurvatureCost::accumulateBlocks(const GaussianField& field, bool with_gradient) const {
  const Eigen::Index m = points_mm_.cols();
  const Eigen::Index n = field.getNumCentres();
  const Eigen::Index block_size = findBlockSize();
  const Eigen::Index blocks = (m + block_size - 1) / block_size;
  block_cost_.setZero(blocks);
  if (with_gradient) block_gradients_.setZero(3, n * blocks);
  const Eigen::Matrix3Xd& centres = field.getCentres();
  const Eigen::VectorXd& weights = field.getWeights();
  const Eigen::VectorXd& shapes = field.getShapes();
  const bool rebuild = !listsAreValid(field);
  if (rebuild) {
    near_.resize(static_cast<size_t>(blocks));
    near_start_.resize(static_cast<size_t>(blocks));
    listed_centres_mm_ = centres;
    listed_shapes_ = shapes;
    listed_cutoff_ = field.getCutoff();
    lists_built_ = true;
  }

#pragma omp parallel for schedule(dynamic, 1)
  for (Eigen::Index b = 0; b < blocks; ++b) {
    thread_local ActiveCentres active;
    thread_local std::vector<int> found;
    const Eigen::Index begin = b * block_size, end = std::min(m, (b + 1) * block_size);
    std::vector<int>& near = near_[static_cast<size_t>(b)];
    std::vector<int>& start = near_start_[static_cast<size_t>(b)];
    if (rebuild) {
      near.clear();
      start.assign(1, 0);
      for (Eigen::Index q = begin; q < end; ++q) {
        field.findNearCentres(points_mm_.col(q), kNeighbourSkinMm, found);
        near.insert(near.end(), found.begin(), found.end());
        start.push_back(static_cast<int>(near.size()));
      }
    }
    double cost = 0.0;
    for (Eigen::Index q = begin; q < end; ++q) {
      const Eigen::Vector3d p = points_mm_.col(q);
      const size_t i = static_cast<size_t>(q - begin);
      field.findActiveCentresAmong(p, near.data() + start[i], start[i + 1] - start[i], active);
      // κ(q), summed exactly as GaussianField::calcMeanCurvature does.
      double kappa = 0.0;
      for (int j = 0; j < active.size(); ++j) {
        const auto jj = static_cast<std::size_t>(j);
        const int k = active.indices[jj];
        kappa += gaussian::calcMeanCurvatureTerm(shapes[k], weights[k], active.phi[jj],
                                                 active.r2_mm2[jj]);
      }
      const double residual = kappa - target_curvatures_[q];
      cost += weights_mm3_[q] * residual * residual;
      if (!with_gradient) continue;
      const double scale = 2.0 * weights_mm3_[q] * residual;
      for (int j = 0; j < active.size(); ++j) {
        const auto jj = static_cast<std::size_t>(j);
        const int k = active.indices[jj];
        const Eigen::Vector3d d = p - centres.col(k);
        block_gradients_.col(b * n + k) +=
            scale * gaussian::calcMeanCurvatureDerivativeWrtCentre(
                        shapes[k], weights[k], active.phi[jj], d, active.r2_mm2[jj]);
      }
    }
    block_cost_[b] = cost;
  }
}

double CurvatureCost::calcCost(const GaussianField& field) const {
  accumulateBlocks(field, false);
  double cost = 0.0;
  for (Eigen::Index b = 0; b < block_cost_.size(); ++b) cost += block_cost_[b];
  return cost;
}

double CurvatureCost::calcCostAndGradient(const GaussianField& field,
                                          Eigen::Matrix3Xd& grad_wrt_centres) const {
  accumulateBlocks(field, true);
  const Eigen::Index n = field.getNumCentres();
  const Eigen::Index blocks = block_cost_.size();
  grad_wrt_centres.setZero(3, n);
#pragma omp parallel for schedule(static)
  for (Eigen::Index k = 0; k < n; ++k)
    for (Eigen::Index b = 0; b < blocks; ++b)
      grad_wrt_centres.col(k) += block_gradients_.col(b * n + k);
  double cost = 0.0;
  for (Eigen::Index b = 0; b < blocks; ++b) cost += block_cost_[b];
  return cost;
}

}  // namespace rbfmuscle
