// SPDX-License-Identifier: Apache-2.0
#include "rbf/gaussian_field.h"

#include "rbf/ascending_indices.h"
#include "rbf/gaussian_terms.h"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>
#include <string>

namespace rbfmuscle {

namespace {

/// Relative padding of a class's query radius, so that rounding in the
/// distance test of the grid never drops a centre the cut-off test keeps.
constexpr double kQueryRadiusPadding = 1e-9;
/// Grid cell edge of a class with radii in [2^(e−1), 2^e): 2^(e + offset) mm.
constexpr int kCellExponentOffset = -1;

[[noreturn]] void throwInvalid(const std::string& what) {
  throw std::invalid_argument("GaussianField: " + what);
}

void checkFinitePoint(const Eigen::Vector3d& p_mm) {
  if (!p_mm.allFinite()) {
    std::ostringstream s;
    s << "query point (" << p_mm.transpose() << ") mm, expected finite coordinates";
    throwInvalid(s.str());
  }
}

void checkFinitePoints(const Eigen::Matrix3Xd& points_mm, const char* what) {
  for (Eigen::Index i = 0; i < points_mm.cols(); ++i)
    if (!points_mm.col(i).allFinite()) {
      std::ostringstream s;
      s << what << " " << i << " = (" << points_mm.col(i).transpose()
        << ") mm, expected finite coordinates";
      throwInvalid(s.str());
    }
}

void checkCentre(Eigen::Index k, const Eigen::Vector3d& centre_mm, double weight, double shape) {
  std::ostringstream s;
  if (!centre_mm.allFinite())
    s << "centre " << k << " = (" << centre_mm.transpose() << ") mm, expected finite coordinates";
  else if (!std::isfinite(weight))
    s << "centre " << k << " weight " << weight << ", expected a finite value";
  else if (!(std::isfinite(shape) && shape > 0.0))
    s << "centre " << k << " shape " << shape << " mm^-2, expected a finite value > 0";
  else
    return;
  throwInvalid(s.str());
}

}  // namespace

GaussianField::GaussianField(double offset_value, double cutoff) : offset_(offset_value) {
  setCutoff(cutoff);
}

GaussianField::GaussianField(double offset_value, const Eigen::Matrix3Xd& centres_mm,
                             const Eigen::VectorXd& weights,
                             const Eigen::VectorXd& shapes_per_mm2, double cutoff)
    : offset_(offset_value) {
  setCutoff(cutoff);
  setCentres(centres_mm, weights, shapes_per_mm2);
}

void GaussianField::setCentres(const Eigen::Matrix3Xd& centres_mm,
                               const Eigen::VectorXd& weights,
                               const Eigen::VectorXd& shapes_per_mm2) {
  if (weights.size() != centres_mm.cols() || shapes_per_mm2.size() != centres_mm.cols()) {
    std::ostringstream s;
    s << "setCentres: " << centres_mm.cols() << " centres, " << weights.size() << " weights, "
      << shapes_per_mm2.size() << " shapes, expected equal counts";
    throwInvalid(s.str());
  }
  for (Eigen::Index k = 0; k < centres_mm.cols(); ++k)
    checkCentre(k, centres_mm.col(k), weights[k], shapes_per_mm2[k]);
  centres_mm_ = centres_mm;
  weights_ = weights;
  shapes_per_mm2_ = shapes_per_mm2;
  rebuildClasses();
}

int GaussianField::addCentre(const Eigen::Vector3d& centre_mm, double weight,
                             double shape_per_mm2) {
  const Eigen::Index k = centres_mm_.cols();
  checkCentre(k, centre_mm, weight, shape_per_mm2);
  centres_mm_.conservativeResize(3, k + 1);
  centres_mm_.col(k) = centre_mm;
  weights_.conservativeResize(k + 1);
  weights_[k] = weight;
  shapes_per_mm2_.conservativeResize(k + 1);
  shapes_per_mm2_[k] = shape_per_mm2;
  if (cutoff_ > 0.0) {
    const int e = findExponent(static_cast<int>(k));
    auto it = std::lower_bound(classes_.begin(), classes_.end(), e,
                               [](const RadiusClass& rc, int x) { return rc.exponent < x; });
    if (it == classes_.end() || it->exponent != e) {
      it = classes_.insert(it, RadiusClass{});
      it->exponent = e;
    }
    it->members.push_back(static_cast<int>(k));
    rebuildClass(*it);
  }
  return static_cast<int>(k);
}

void GaussianField::setCentrePositions(const Eigen::Matrix3Xd& centres_mm) {
  if (centres_mm.cols() != centres_mm_.cols()) {
    std::ostringstream s;
    s << "setCentrePositions: " << centres_mm.cols() << " centres, expected "
      << centres_mm_.cols();
    throwInvalid(s.str());
  }
  checkFinitePoints(centres_mm, "setCentrePositions: centre");
  centres_mm_ = centres_mm;
  for (RadiusClass& rc : classes_) {
    for (std::size_t j = 0; j < rc.members.size(); ++j)
      rc.positions_mm.col(static_cast<Eigen::Index>(j)) = centres_mm_.col(rc.members[j]);
    rc.grid.update(rc.positions_mm);
  }
}

void GaussianField::setWeights(const Eigen::VectorXd& weights) {
  if (weights.size() != centres_mm_.cols()) {
    std::ostringstream s;
    s << "setWeights: " << weights.size() << " weights, expected " << centres_mm_.cols();
    throwInvalid(s.str());
  }
  for (Eigen::Index k = 0; k < weights.size(); ++k)
    checkCentre(k, centres_mm_.col(k), weights[k], shapes_per_mm2_[k]);
  weights_ = weights;
}

void GaussianField::setCutoff(double cutoff) {
  if (!(cutoff >= 0.0 && cutoff < 1.0)) {
    std::ostringstream s;
    s << "cut-off epsilon " << cutoff << ", expected a value in [0, 1)";
    throwInvalid(s.str());
  }
  cutoff_ = cutoff;
  log_inv_cutoff_ = -std::log(cutoff);  // +inf for cutoff = 0
  rebuildClasses();
}

double GaussianField::getCutoffRadius(int k) const {
  checkIndex(k);
  return gaussian::calcCutoffRadius(shapes_per_mm2_[k], cutoff_);
}

void GaussianField::checkIndex(int k) const {
  if (k < 0 || k >= centres_mm_.cols()) {
    std::ostringstream s;
    s << "GaussianField: centre index " << k << ", expected 0 <= k < " << centres_mm_.cols();
    throw std::out_of_range(s.str());
  }
}

int GaussianField::findExponent(int k) const {
  int e = 0;
  std::frexp(gaussian::calcCutoffRadius(shapes_per_mm2_[k], cutoff_), &e);
  return e;
}

void GaussianField::rebuildClasses() {
  classes_.clear();
  if (cutoff_ <= 0.0) return;
  for (int k = 0; k < centres_mm_.cols(); ++k) {
    const int e = findExponent(k);
    auto it = std::lower_bound(classes_.begin(), classes_.end(), e,
                               [](const RadiusClass& rc, int x) { return rc.exponent < x; });
    if (it == classes_.end() || it->exponent != e) {
      it = classes_.insert(it, RadiusClass{});
      it->exponent = e;
    }
    it->members.push_back(k);
  }
  for (RadiusClass& rc : classes_) rebuildClass(rc);
}

void GaussianField::rebuildClass(RadiusClass& rc) {
  const auto n = static_cast<Eigen::Index>(rc.members.size());
  rc.positions_mm.resize(3, n);
  double radius = 0.0;
  for (Eigen::Index j = 0; j < n; ++j) {
    const int k = rc.members[static_cast<std::size_t>(j)];
    rc.positions_mm.col(j) = centres_mm_.col(k);
    radius = std::max(radius, gaussian::calcCutoffRadius(shapes_per_mm2_[k], cutoff_));
  }
  rc.query_radius_mm = radius * (1.0 + kQueryRadiusPadding);
  rc.grid.build(rc.positions_mm, std::ldexp(1.0, rc.exponent + kCellExponentOffset));
}

template <class Visitor>
void GaussianField::visitActive(const Eigen::Vector3d& p_mm, Visitor&& visit) const {
  checkFinitePoint(p_mm);
  // The single cut-off test shared by both paths: αₖ rₖ² ≤ ln(1/ε) ⇔ φₖ ≥ ε.
  const auto consider = [&](int k) {
    const Eigen::Vector3d d = p_mm - centres_mm_.col(k);
    const double r2 = d.squaredNorm();
    const double alpha = shapes_per_mm2_[k];
    if (alpha * r2 <= log_inv_cutoff_) visit(k, gaussian::calcPhi(alpha, r2), d, r2);
  };
  if (!use_grid_ || classes_.empty()) {
    for (int k = 0; k < centres_mm_.cols(); ++k) consider(k);
    return;
  }
  // Grid path: the same cut-off test on the grid's copy of the centres (the
  // same doubles, so the same r²), collecting active centres, then visiting
  // them in ascending order.
  thread_local std::vector<int> active;
  active.clear();
  for (const RadiusClass& rc : classes_)
    rc.grid.visitCandidates(p_mm, rc.query_radius_mm, [&](int j, const auto& centre) {
      const int k = rc.members[static_cast<std::size_t>(j)];
      const Eigen::Vector3d d = p_mm - centre;
      if (shapes_per_mm2_[k] * d.squaredNorm() <= log_inv_cutoff_) active.push_back(k);
    });
  sortAscendingIndices(active, static_cast<int>(centres_mm_.cols()));
  for (int k : active) {
    const Eigen::Vector3d d = p_mm - centres_mm_.col(k);
    const double r2 = d.squaredNorm();
    visit(k, gaussian::calcPhi(shapes_per_mm2_[k], r2), d, r2);
  }
}

void GaussianField::findActiveCentres(const Eigen::Vector3d& p_mm, ActiveCentres& out) const {
  out.clear();
  visitActive(p_mm, [&](int k, double phi, const Eigen::Vector3d&, double r2) {
    out.indices.push_back(k);
    out.phi.push_back(phi);
    out.r2_mm2.push_back(r2);
  });
}

double GaussianField::calcValue(const Eigen::Vector3d& p_mm) const {
  double sum = 0.0;
  visitActive(p_mm, [&](int k, double phi, const Eigen::Vector3d&, double) {
    sum += weights_[k] * phi;
  });
  return offset_ + sum;
}

Eigen::Vector3d GaussianField::calcGradient(const Eigen::Vector3d& p_mm) const {
  Eigen::Vector3d gradient = Eigen::Vector3d::Zero();
  visitActive(p_mm, [&](int k, double phi, const Eigen::Vector3d& d, double) {
    gradient -= gaussian::calcValueDerivativeWrtCentre(shapes_per_mm2_[k], weights_[k], phi, d);
  });
  return gradient;
}

FieldEvaluation GaussianField::calcEvaluation(const Eigen::Vector3d& p_mm) const {
  double sum = 0.0;
  Eigen::Vector3d gradient = Eigen::Vector3d::Zero();
  Eigen::Matrix3d hessian = Eigen::Matrix3d::Zero();
  visitActive(p_mm, [&](int k, double phi, const Eigen::Vector3d& d, double) {
    const double alpha = shapes_per_mm2_[k];
    const double c = alpha * weights_[k] * phi;  // αλφ
    sum += weights_[k] * phi;
    gradient -= gaussian::calcValueDerivativeWrtCentre(alpha, weights_[k], phi, d);
    // Upper triangle only, mirrored below: H is exactly symmetric.
    const double s = 4.0 * alpha * c;
    for (int j = 0; j < 3; ++j) {
      for (int i = 0; i < j; ++i) hessian(i, j) += s * (d[i] * d[j]);
      hessian(j, j) += s * (d[j] * d[j]) - 2.0 * c;
    }
  });
  hessian.triangularView<Eigen::StrictlyLower>() = hessian.transpose();
  FieldEvaluation result;
  result.value = offset_ + sum;
  result.gradient = gradient;
  result.hessian = hessian;
  return result;
}

double GaussianField::calcMeanCurvature(const Eigen::Vector3d& p_mm) const {
  double kappa = 0.0;
  visitActive(p_mm, [&](int k, double phi, const Eigen::Vector3d&, double r2) {
    kappa += gaussian::calcMeanCurvatureTerm(shapes_per_mm2_[k], weights_[k], phi, r2);
  });
  return kappa;
}

Eigen::Vector3d GaussianField::calcMeanCurvatureGradient(const Eigen::Vector3d& p_mm) const {
  Eigen::Vector3d gradient = Eigen::Vector3d::Zero();
  visitActive(p_mm, [&](int k, double phi, const Eigen::Vector3d& d, double r2) {
    gradient -= gaussian::calcMeanCurvatureDerivativeWrtCentre(shapes_per_mm2_[k], weights_[k],
                                                               phi, d, r2);
  });
  return gradient;
}

void GaussianField::calcValues(const Eigen::Matrix3Xd& points_mm, Eigen::VectorXd& out) const {
  checkFinitePoints(points_mm, "calcValues: point");
  out.resize(points_mm.cols());
  const Eigen::Index n = points_mm.cols();
#pragma omp parallel for schedule(static)
  for (Eigen::Index i = 0; i < n; ++i) out[i] = calcValue(points_mm.col(i));
}

void GaussianField::calcMeanCurvatures(const Eigen::Matrix3Xd& points_mm,
                                       Eigen::VectorXd& out) const {
  checkFinitePoints(points_mm, "calcMeanCurvatures: point");
  out.resize(points_mm.cols());
  const Eigen::Index n = points_mm.cols();
#pragma omp parallel for schedule(static)
  for (Eigen::Index i = 0; i < n; ++i) out[i] = calcMeanCurvature(points_mm.col(i));
}

double GaussianField::findPhi(const Eigen::Vector3d& p_mm, int k, Eigen::Vector3d& d,
                              double& r2) const {
  checkIndex(k);
  checkFinitePoint(p_mm);
  d = p_mm - centres_mm_.col(k);
  r2 = d.squaredNorm();
  const double alpha = shapes_per_mm2_[k];
  return alpha * r2 <= log_inv_cutoff_ ? gaussian::calcPhi(alpha, r2) : 0.0;
}

Eigen::Vector3d GaussianField::calcValueDerivativeWrtCentre(const Eigen::Vector3d& p_mm,
                                                            int k) const {
  Eigen::Vector3d d;
  double r2 = 0.0;
  const double phi = findPhi(p_mm, k, d, r2);
  return gaussian::calcValueDerivativeWrtCentre(shapes_per_mm2_[k], weights_[k], phi, d);
}

Eigen::Vector3d GaussianField::calcMeanCurvatureDerivativeWrtCentre(
    const Eigen::Vector3d& p_mm, int k) const {
  Eigen::Vector3d d;
  double r2 = 0.0;
  const double phi = findPhi(p_mm, k, d, r2);
  return gaussian::calcMeanCurvatureDerivativeWrtCentre(shapes_per_mm2_[k], weights_[k], phi, d,
                                                        r2);
}

double GaussianField::calcMeanCurvatureDerivativeWrtWeight(const Eigen::Vector3d& p_mm,
                                                           int k) const {
  Eigen::Vector3d d;
  double r2 = 0.0;
  const double phi = findPhi(p_mm, k, d, r2);
  return gaussian::calcMeanCurvatureDerivativeWrtWeight(shapes_per_mm2_[k], phi, r2);
}

}  // namespace rbfmuscle
