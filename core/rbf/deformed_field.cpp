// SPDX-License-Identifier: Apache-2.0
#include "rbf/deformed_field.h"

#include <Eigen/Eigenvalues>
#include <Eigen/LU>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace rbfmuscle {

namespace {

void checkLimits(double cutoff, const FrameLimits& limits) {
  if (!(cutoff > 0.0 && cutoff < 1.0)) throw std::invalid_argument("DeformedField: cut-off must lie in (0, 1)");
  if (!(limits.min_stretch > 0.0) || !(limits.max_stretch >= limits.min_stretch) || !std::isfinite(limits.max_stretch))
    throw std::invalid_argument("DeformedField: frame limits need 0 < min_stretch <= max_stretch < inf");
}

}  // namespace

DeformedField::DeformedField(const GaussianField& rest, double cutoff, const FrameLimits& limits)
    : offset_(rest.getOffset()),
      cutoff_exponent_(-std::log(cutoff)),
      limits_(limits),
      centres_mm_(rest.getCentres()),
      weights_(rest.getWeights()),
      shapes_per_mm2_(rest.getShapes()),
      frames_(static_cast<size_t>(rest.getNumCentres()), Eigen::Matrix3d::Identity()),
      kernels_(static_cast<size_t>(rest.getNumCentres())) {
  checkLimits(cutoff, limits);
  for (int k = 0; k < getNumKernels(); ++k) packKernel(k);
}

DeformedField::DeformedField(const DeformedField& other)
    : offset_(other.offset_),
      cutoff_exponent_(other.cutoff_exponent_),
      limits_(other.limits_),
      centres_mm_(other.centres_mm_),
      weights_(other.weights_),
      shapes_per_mm2_(other.shapes_per_mm2_),
      frames_(other.frames_),
      kernels_(other.kernels_),
      clamped_frames_(other.clamped_frames_) {}

DeformedField& DeformedField::operator=(const DeformedField& other) {
  if (this == &other) return *this;
  offset_ = other.offset_;
  cutoff_exponent_ = other.cutoff_exponent_;
  limits_ = other.limits_;
  centres_mm_ = other.centres_mm_;
  weights_ = other.weights_;
  shapes_per_mm2_ = other.shapes_per_mm2_;
  frames_ = other.frames_;
  kernels_ = other.kernels_;
  clamped_frames_ = other.clamped_frames_;
  std::lock_guard<std::mutex> lock(grid_mutex_);
  grid_valid_ = false;
  return *this;
}

Eigen::Matrix3d DeformedField::calcMetric(double alpha_per_mm2, const Eigen::Matrix3d& frame,
                                          const FrameLimits& limits, bool* clamped) {
  const Eigen::Matrix3d m = frame * frame.transpose();  // F Fᵀ: its eigenvalues are σ²
  const double trace = m.trace(), det = m.determinant();
  // Cheap bounds: σ²_max ≤ tr, σ²_min ≥ det / (tr/2)² (the other two eigenvalues' product ≤ (tr/2)²).
  const double lo2 = limits.min_stretch * limits.min_stretch, hi2 = limits.max_stretch * limits.max_stretch;
  if (clamped) *clamped = false;
  if (trace <= hi2 && det >= lo2 * 0.25 * trace * trace) return alpha_per_mm2 * m.inverse();
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eigen(m);
  Eigen::Vector3d inv = eigen.eigenvalues();
  bool changed = false;
  for (int i = 0; i < 3; ++i) {
    const double s2 = std::clamp(inv[i], lo2, hi2);
    changed = changed || s2 != inv[i];
    inv[i] = 1.0 / s2;
  }
  if (clamped) *clamped = changed;
  return alpha_per_mm2 * eigen.eigenvectors() * inv.asDiagonal() * eigen.eigenvectors().transpose();
}

void DeformedField::packKernel(int k) {
  const size_t i = static_cast<size_t>(k);
  bool clamped = false;
  const Eigen::Matrix3d a = calcMetric(shapes_per_mm2_[k], frames_[i], limits_, &clamped);
  clamped_frames_ += clamped ? 1 : 0;
  DeformedKernel& kernel = kernels_[i];
  kernel.centre_mm = centres_mm_.col(k);
  kernel.weight = weights_[k];
  kernel.a_xx = a(0, 0);
  kernel.a_yy = a(1, 1);
  kernel.a_zz = a(2, 2);
  kernel.a_xy = 0.5 * (a(0, 1) + a(1, 0));
  kernel.a_xz = 0.5 * (a(0, 2) + a(2, 0));
  kernel.a_yz = 0.5 * (a(1, 2) + a(2, 1));
  kernel.trace = kernel.a_xx + kernel.a_yy + kernel.a_zz;
}

void DeformedField::setKernels(const Eigen::Matrix3Xd& centres_mm, const std::vector<Eigen::Matrix3d>& frames) {
  if (centres_mm.cols() != getNumKernels() || static_cast<int>(frames.size()) != getNumKernels())
    throw std::invalid_argument("DeformedField::setKernels: " + std::to_string(centres_mm.cols()) + " centres and " +
                                std::to_string(frames.size()) + " frames for " + std::to_string(getNumKernels()) +
                                " kernels");
  for (int k = 0; k < getNumKernels(); ++k)
    if (!centres_mm.col(k).allFinite() || !frames[static_cast<size_t>(k)].allFinite())
      throw std::invalid_argument("DeformedField::setKernels: kernel " + std::to_string(k) +
                                  " has a non-finite centre or frame");
  centres_mm_ = centres_mm;
  frames_ = frames;
  clamped_frames_ = 0;
  for (int k = 0; k < getNumKernels(); ++k) packKernel(k);
  grid_valid_ = false;
}

void DeformedField::setCentres(const Eigen::Matrix3Xd& centres_mm) {
  if (centres_mm.cols() != getNumKernels())
    throw std::invalid_argument("DeformedField::setCentres: " + std::to_string(centres_mm.cols()) + " centres for " +
                                std::to_string(getNumKernels()) + " kernels");
  for (int k = 0; k < getNumKernels(); ++k)
    if (!centres_mm.col(k).allFinite())
      throw std::invalid_argument("DeformedField::setCentres: centre " + std::to_string(k) + " is not finite");
  centres_mm_ = centres_mm;
  for (int k = 0; k < getNumKernels(); ++k) kernels_[static_cast<size_t>(k)].centre_mm = centres_mm_.col(k);
  grid_valid_ = false;
}

void DeformedField::setWeights(const Eigen::VectorXd& weights) {
  if (weights.size() != getNumKernels() || !weights.allFinite())
    throw std::invalid_argument("DeformedField::setWeights: expected " + std::to_string(getNumKernels()) +
                                " finite weights, got " + std::to_string(weights.size()));
  weights_ = weights;
  for (int k = 0; k < getNumKernels(); ++k) kernels_[static_cast<size_t>(k)].weight = weights_[k];
}

Eigen::Vector3d DeformedField::calcHalfExtents(int k) const {
  const DeformedKernel& kernel = kernels_.at(static_cast<size_t>(k));
  Eigen::Matrix3d a;
  a << kernel.a_xx, kernel.a_xy, kernel.a_xz, kernel.a_xy, kernel.a_yy, kernel.a_yz, kernel.a_xz, kernel.a_yz,
      kernel.a_zz;
  return (cutoff_exponent_ * a.inverse().diagonal().array()).sqrt();
}

double DeformedField::calcValueAmong(const Eigen::Vector3d& p_mm, const int* kernels, int count) const {
  double sum = 0.0;
  visitActiveAmong(p_mm, kernels, count,
                   [&](int, const DeformedKernel& k, double phi, const Eigen::Vector3d&) { sum += k.weight * phi; });
  return offset_ + sum;
}

FieldSample DeformedField::calcSampleAmong(const Eigen::Vector3d& p_mm, const int* kernels, int count) const {
  double sum = 0.0;
  Eigen::Vector3d gradient = Eigen::Vector3d::Zero();
  visitActiveAmong(p_mm, kernels, count, [&](int, const DeformedKernel& k, double phi, const Eigen::Vector3d& ad) {
    const double lphi = k.weight * phi;
    sum += lphi;
    gradient -= (2.0 * lphi) * ad;
  });
  return FieldSample{offset_ + sum, gradient};
}

const KernelGrid& DeformedField::grid() const {
  if (grid_valid_.load(std::memory_order_acquire)) return grid_;
  std::lock_guard<std::mutex> lock(grid_mutex_);
  if (!grid_valid_.load(std::memory_order_relaxed)) {
    Eigen::Matrix3Xd lower(3, getNumKernels()), upper(3, getNumKernels());
    for (int k = 0; k < getNumKernels(); ++k) {
      const Eigen::Vector3d h = calcHalfExtents(k);
      lower.col(k) = centres_mm_.col(k) - h;
      upper.col(k) = centres_mm_.col(k) + h;
    }
    grid_.build(lower, upper);
    grid_valid_.store(true, std::memory_order_release);
  }
  return grid_;
}

double DeformedField::calcValue(const Eigen::Vector3d& p_mm) const {
  const int* first = nullptr;
  int count = 0;
  grid().findCandidates(p_mm, first, count);
  return calcValueAmong(p_mm, first, count);
}

Eigen::Vector3d DeformedField::calcGradient(const Eigen::Vector3d& p_mm) const { return calcSample(p_mm).gradient; }

FieldSample DeformedField::calcSample(const Eigen::Vector3d& p_mm) const {
  const int* first = nullptr;
  int count = 0;
  grid().findCandidates(p_mm, first, count);
  return calcSampleAmong(p_mm, first, count);
}

double DeformedField::calcMeanCurvature(const Eigen::Vector3d& p_mm) const {
  const int* first = nullptr;
  int count = 0;
  grid().findCandidates(p_mm, first, count);
  double laplacian = 0.0;
  visitActiveAmong(p_mm, first, count, [&](int, const DeformedKernel& k, double phi, const Eigen::Vector3d& ad) {
    laplacian += k.weight * phi * (4.0 * ad.squaredNorm() - 2.0 * k.trace);
  });
  return laplacian / 3.0;
}

void DeformedField::calcValues(const Eigen::Matrix3Xd& points_mm, Eigen::VectorXd& out) const {
  out.resize(points_mm.cols());
  grid();  // build once before the parallel loop
#pragma omp parallel for schedule(static)
  for (Eigen::Index j = 0; j < points_mm.cols(); ++j) out[j] = calcValue(points_mm.col(j));
}

void DeformedField::findCandidates(const Eigen::Vector3d& p_mm, const int*& first, int& count) const {
  grid().findCandidates(p_mm, first, count);
}

void DeformedField::findActiveKernels(const Eigen::Vector3d& p_mm, std::vector<int>& out) const {
  out.clear();
  const int* first = nullptr;
  int count = 0;
  grid().findCandidates(p_mm, first, count);
  visitActiveAmong(p_mm, first, count,
                   [&](int index, const DeformedKernel&, double, const Eigen::Vector3d&) { out.push_back(index); });
}

}  // namespace rbfmuscle
