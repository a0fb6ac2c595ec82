// SPDX-License-Identifier: Apache-2.0
#pragma once
/// @file
/// A Gaussian RBF field whose kernels deform with the tissue: each kernel carries an affine
/// frame, so a kernel stretches where the muscle stretches instead of leaving a gap.
#include "rbf/gaussian_field.h"
#include "rbf/implicit_field.h"
#include "rbf/kernel_grid.h"

#include <Eigen/Core>

#include <atomic>
#include <cmath>
#include <mutex>
#include <vector>

namespace rbfmuscle {

/// Bounds on the singular values of a kernel frame F (dimensionless). A frame outside them is
/// replaced by the frame with the same rotation and its stretches clamped, so a kernel never
/// becomes infinitely thin (det F → 0 where the blend folds the tissue) or wide.
struct FrameLimits {
  double min_stretch = 0.1;   ///< σ_min(F) is raised to this; > 0
  double max_stretch = 10.0;  ///< σ_max(F) is lowered to this; ≥ min_stretch
};

/// One kernel as the evaluation loops read it: centre, weight and the metric A (symmetric).
struct DeformedKernel {
  Eigen::Vector3d centre_mm = Eigen::Vector3d::Zero();  ///< ξ (mm)
  double weight = 0.0;                                  ///< λ (field unit)
  double a_xx = 0, a_yy = 0, a_zz = 0, a_xy = 0, a_xz = 0, a_yz = 0;  ///< A (mm⁻²)
  double trace = 0.0;                                   ///< tr A (mm⁻²)

  /// A·v for a vector v (mm⁻² · unit of v).
  Eigen::Vector3d applyMetric(const Eigen::Vector3d& v) const {
    return Eigen::Vector3d(a_xx * v.x() + a_xy * v.y() + a_xz * v.z(), a_xy * v.x() + a_yy * v.y() + a_yz * v.z(),
                           a_xz * v.x() + a_yz * v.y() + a_zz * v.z());
  }
};

/// Gaussian RBF field with deformed kernels, in the muscle frame M (mm):
///   f(x) = b + Σₖ λₖ φₖ(x),  φₖ(x) = exp(−(x − ξₖ)ᵀ Aₖ (x − ξₖ)),  Aₖ = Fₖ⁻ᵀ (αₖ I) Fₖ⁻¹,
/// with the rest fit's offset b, weights λ and shapes α, and per kernel a centre ξₖ and an
/// affine frame Fₖ (the deformation gradient of the tissue at the kernel). At rest F = I and
/// the field is the fitted GaussianField. A kernel is ignored where φ < ε, i.e. outside the
/// ellipsoid (x − ξ)ᵀ A (x − ξ) ≤ ln(1/ε).
///
/// With d = x − ξ and A d (per kernel):
///   ∇φ = −2φ A d,   H φ = φ (4 A d dᵀ A − 2A),   ∇²φ = φ (4 |A d|² − 2 tr A),
///   κ(x) = ∇²f / 3 (the dissertation's mean curvature, d = 3).
///
/// Two ways to evaluate:
///  - among a candidate list (the pipeline's points carry lists fixed at rest, so nothing is
///    searched per frame): calcValueAmong / calcSampleAmong;
///  - at any point (ImplicitField): the kernels' bounding boxes in a KernelGrid, built on the
///    first such query after the kernels changed (tools, tests, points off the carried sets).
/// Both apply the same cut-off test and sum in ascending kernel order, so they give bitwise
/// the same result whenever the list holds every kernel active at the point.
/// Const calls are thread-safe; setters are not.
class DeformedField final : public ImplicitField {
 public:
  /// The rest field's kernels with F = I, its offset, and the cut-off ε ∈ (0, 1).
  /// @throws std::invalid_argument for a bad ε or limits.
  explicit DeformedField(const GaussianField& rest, double cutoff = 1e-4, const FrameLimits& limits = {});
  DeformedField(const DeformedField& other);
  DeformedField& operator=(const DeformedField& other);

  /// Sets every kernel's centre (3×N, mm) and frame (N matrices; clamped by the limits).
  /// @throws std::invalid_argument on a size mismatch or a non-finite value (names the kernel).
  void setKernels(const Eigen::Matrix3Xd& centres_mm, const std::vector<Eigen::Matrix3d>& frames);
  /// Moves the centres (3×N, mm), keeping the frames.  @throws as setKernels.
  void setCentres(const Eigen::Matrix3Xd& centres_mm);
  /// Replaces the weights λ (N).  @throws std::invalid_argument on size or non-finite.
  void setWeights(const Eigen::VectorXd& weights);

  /// Number of kernels N.
  int getNumKernels() const { return static_cast<int>(kernels_.size()); }
  /// Offset b (field unit).
  double getOffset() const { return offset_; }
  /// ln(1/ε): a kernel counts where (x − ξ)ᵀA(x − ξ) ≤ this.
  double getCutoffExponent() const { return cutoff_exponent_; }
  /// Centres ξ (3×N, mm).
  const Eigen::Matrix3Xd& getCentres() const { return centres_mm_; }
  /// Weights λ (N).
  const Eigen::VectorXd& getWeights() const { return weights_; }
  /// Rest shapes α (N, mm⁻²).
  const Eigen::VectorXd& getShapes() const { return shapes_per_mm2_; }
  /// Frames F as given (before clamping).
  const std::vector<Eigen::Matrix3d>& getFrames() const { return frames_; }
  /// Kernels whose frame the limits clamped at the last setKernels.
  int countClampedFrames() const { return clamped_frames_; }
  /// The packed kernels (centre, weight, metric) the loops read.
  const std::vector<DeformedKernel>& getKernels() const { return kernels_; }
  /// Half-extents (mm) of kernel k's cut-off ellipsoid along x, y, z: √(ln(1/ε) (A⁻¹)ᵢᵢ).
  Eigen::Vector3d calcHalfExtents(int k) const;

  /// A = α (F Fᵀ)⁻¹ with F's singular values clamped into the limits (clamped set when they were).
  static Eigen::Matrix3d calcMetric(double alpha_per_mm2, const Eigen::Matrix3d& frame, const FrameLimits& limits,
                                    bool* clamped = nullptr);

  /// Calls visit(index, kernel, φ, A d) for each listed kernel (`count` indices) active at p
  /// (φ ≥ ε), in list order, d = p − ξ: the one loop every sum over kernels runs.
  template <class Visitor>
  void visitActiveAmong(const Eigen::Vector3d& p_mm, const int* kernels, int count, Visitor&& visit) const {
    for (int i = 0; i < count; ++i) {
      const DeformedKernel& k = kernels_[static_cast<size_t>(kernels[i])];
      const Eigen::Vector3d d = p_mm - k.centre_mm;
      const Eigen::Vector3d ad = k.applyMetric(d);
      const double q = d.dot(ad);
      if (q <= cutoff_exponent_) visit(kernels[i], k, std::exp(-q), ad);
    }
  }

  /// f(p) over the listed kernels only (`count` ascending indices).
  double calcValueAmong(const Eigen::Vector3d& p_mm, const int* kernels, int count) const;
  /// f(p) and ∇f(p) over the listed kernels only.
  FieldSample calcSampleAmong(const Eigen::Vector3d& p_mm, const int* kernels, int count) const;

  double calcValue(const Eigen::Vector3d& p_mm) const override;
  Eigen::Vector3d calcGradient(const Eigen::Vector3d& p_mm) const override;
  FieldSample calcSample(const Eigen::Vector3d& p_mm) const override;
  /// κ(p) = ∇²f(p)/3 at any point (field unit / mm²).
  double calcMeanCurvature(const Eigen::Vector3d& p_mm) const;
  /// f at every column of points (3×M) into `out` (resized); parallel, thread-count independent.
  void calcValues(const Eigen::Matrix3Xd& points_mm, Eigen::VectorXd& out) const;

  /// The general search's candidates at p: kernels whose cut-off box holds p (a superset of the active ones).
  void findCandidates(const Eigen::Vector3d& p_mm, const int*& first, int& count) const;

  /// Kernels active at p (φ ≥ ε) by the general search, ascending, into `out`.
  void findActiveKernels(const Eigen::Vector3d& p_mm, std::vector<int>& out) const;

 private:
  /// Rebuilds the packed kernel k from centre, weight, shape and frame.
  void packKernel(int k);
  /// The grid of kernel boxes for general queries, built when stale (thread-safe).
  const KernelGrid& grid() const;

  double offset_ = 0.0;
  double cutoff_exponent_ = 0.0;
  FrameLimits limits_;
  Eigen::Matrix3Xd centres_mm_;
  Eigen::VectorXd weights_;
  Eigen::VectorXd shapes_per_mm2_;
  std::vector<Eigen::Matrix3d> frames_;
  std::vector<DeformedKernel> kernels_;
  int clamped_frames_ = 0;
  mutable std::mutex grid_mutex_;
  mutable std::atomic<bool> grid_valid_{false};  ///< read without the lock once built
  mutable KernelGrid grid_;
};

}  // namespace rbfmuscle
