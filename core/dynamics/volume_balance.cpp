// SPDX-License-Identifier: Apache-2.0
#include "dynamics/volume_balance.h"

#include "rbf/parallel_blocks.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace rbfmuscle {

std::string toString(BalanceStop stop) {
  switch (stop) {
    case BalanceStop::kWithinTolerance: return "within_tolerance";
    case BalanceStop::kIterationCap: return "iteration_cap";
    case BalanceStop::kCorrectionBound: return "correction_bound";
    case BalanceStop::kDisabled: return "disabled";
  }
  return "unknown";
}


VolumeBalance::VolumeBalance(const Eigen::VectorXd& rest_weights, const std::vector<bool>& free_mask,
                             double cell_volume_mm3, double cell_mm, const BalanceSettings& settings)
    : rest_weights_(rest_weights), cell_volume_mm3_(cell_volume_mm3), settings_(settings) {
  if (static_cast<Eigen::Index>(free_mask.size()) != rest_weights.size())
    throw std::invalid_argument("VolumeBalance: free mask and weights differ in size");
  if (!(cell_volume_mm3 > 0.0) || !(cell_mm > 0.0)) throw std::invalid_argument("VolumeBalance: cell must be > 0");
  if (!(settings.tolerance > 0.0) || settings.max_iterations < 1 || !(settings.max_correction > 0.0))
    throw std::invalid_argument("VolumeBalance: tolerance, max_iterations and max_correction must be > 0");
  width_ = settings.step_width > 0.0 ? settings.step_width : 0.5 * cell_mm;
  correction_weights_ = Eigen::VectorXd::Zero(rest_weights.size());
  for (Eigen::Index k = 0; k < rest_weights.size(); ++k)
    if (free_mask[static_cast<size_t>(k)]) correction_weights_[k] = std::abs(rest_weights[k]);
}

void VolumeBalance::sumValues(const DeformedField& field, const Eigen::Matrix3Xd& points, const NeighbourLists& lists,
                              const Eigen::VectorXd& clearance_mm, const FoldFinder& folds) {
  const Eigen::VectorXd& c = correction_weights_;
  const auto sum_among = [&](const Eigen::Vector3d& p, const int* kernels, int count, double& f, double& g) {
    f = field.getOffset();
    g = 0.0;
    field.visitActiveAmong(p, kernels, count, [&](int index, const DeformedKernel& k, double phi, const Eigen::Vector3d&) {
      f += k.weight * phi;
      g += c[index] * phi;
    });
  };
  const auto sum_all = [&](const Eigen::Vector3d& p, double& f, double& g) {  // the general search
    const int* kernels = nullptr;
    int count = 0;
    field.findCandidates(p, kernels, count);
    sum_among(p, kernels, count, f, g);
  };
  // Only folds that can win for some |δ| ≤ max_correction are kept (f + δ g ≥ f − max_correction g).
  // A fold lies up to twice the bones' band away, beyond the point's list: the whole field there.
  const double bound = settings_.enabled ? settings_.max_correction : 0.0;
  const long count = static_cast<long>(points.cols());
  values_.resize(count);
  corrections_.resize(count);
  std::vector<std::vector<FoldLines>> block_folds(static_cast<size_t>((count + kBlock - 1) / kBlock));
  forEachBlock(count, kBlock, [&](long begin, long end) {
    std::vector<FoldLines>& found = block_folds[static_cast<size_t>(begin / kBlock)];
    for (long j = begin; j < end; ++j) {
      const int i = static_cast<int>(j);
      sum_among(points.col(j), lists.begin(i), lists.count(i), values_[j], corrections_[j]);
      const double lowest = values_[j] - bound * corrections_[j];
      if (!folds || !(clearance_mm[j] > 0.0) || !(lowest < clearance_mm[j])) continue;  // s always wins
      folds(points.col(j), lowest, [&](const Eigen::Vector3d& mirror, const Eigen::Vector3d& foot, double cap_mm) {
        if (!(cap_mm > lowest)) return;
        FoldLines lines{i, 0.0, 0.0, 0.0, 0.0, cap_mm};
        sum_all(mirror, lines.mirror_value, lines.mirror_correction);
        if (!(lines.mirror_value + bound * lines.mirror_correction > lowest)) return;
        sum_all(foot, lines.foot_value, lines.foot_correction);
        if (lines.foot_value + bound * lines.foot_correction > lowest) found.push_back(lines);
      });
    }
  });
  folds_.clear();
  for (const std::vector<FoldLines>& found : block_folds) folds_.insert(folds_.end(), found.begin(), found.end());
}

double VolumeBalance::sum(double delta, const Eigen::VectorXd& volume_changes, const Eigen::VectorXd& clearance_mm,
                          double* derivative) const {
  double volume = 0.0, slope = 0.0;
  size_t e = 0;
  for (Eigen::Index j = 0; j < values_.size(); ++j) {
    double f = values_[j] + delta * corrections_[j], rate = corrections_[j];
    for (; e < folds_.size() && folds_[e].point == j; ++e) {  // max(f, min(mirror, foot, cap)), lines in δ
      const FoldLines& fold = folds_[e];
      const double mirror = fold.mirror_value + delta * fold.mirror_correction;
      const double foot = fold.foot_value + delta * fold.foot_correction;
      const double folded = std::min({mirror, foot, fold.cap_mm});
      if (!(folded > f)) continue;
      f = folded;
      rate = folded == fold.cap_mm ? 0.0 : folded == mirror ? fold.mirror_correction : fold.foot_correction;
    }
    const double w = cell_volume_mm3_ * volume_changes[j];
    if (f < clearance_mm[j]) {
      const double t = std::tanh(f / width_);
      volume += w * 0.5 * (1.0 + t);
      slope += w * 0.5 * (1.0 - t * t) * rate / width_;
    } else {
      volume += w * 0.5 * (1.0 + std::tanh(clearance_mm[j] / width_));
    }
  }
  if (derivative) *derivative = slope;
  return volume;
}

void VolumeBalance::setRest(const DeformedField& rest_field, const Eigen::Matrix3Xd& points_mm,
                            const NeighbourLists& lists, const Eigen::VectorXd& clearance_mm,
                            const FoldFinder& folds) {
  if (clearance_mm.size() != points_mm.cols()) throw std::invalid_argument("VolumeBalance::setRest: sizes differ");
  sumValues(rest_field, points_mm, lists, clearance_mm, folds);
  rest_volume_mm3_ = sum(0.0, Eigen::VectorXd::Ones(points_mm.cols()), clearance_mm, nullptr);
  if (!(rest_volume_mm3_ > 0.0)) throw std::invalid_argument("VolumeBalance: the rest volume is not positive");
}

BalanceReport VolumeBalance::balance(DeformedField& field, const Eigen::Matrix3Xd& points_mm,
                                    const NeighbourLists& lists, const Eigen::VectorXd& volume_changes,
                                    const Eigen::VectorXd& clearance_mm, const FoldFinder& folds) {
  if (volume_changes.size() != points_mm.cols() || clearance_mm.size() != points_mm.cols())
    throw std::invalid_argument("VolumeBalance::balance: sizes differ");
  sumValues(field, points_mm, lists, clearance_mm, folds);
  BalanceReport report;
  double slope = 0.0;
  double volume = sum(0.0, volume_changes, clearance_mm, &slope);
  report.ratio_before = volume / rest_volume_mm3_;
  double delta = 0.0;
  report.stop = settings_.enabled ? BalanceStop::kIterationCap : BalanceStop::kDisabled;
  if (settings_.enabled) {
    double lo = -settings_.max_correction, hi = settings_.max_correction;
    for (int it = 0; it < settings_.max_iterations; ++it) {
      const double error = volume / rest_volume_mm3_ - 1.0;
      if (std::abs(error) <= settings_.tolerance) {
        report.stop = BalanceStop::kWithinTolerance;
        break;
      }
      (error < 0.0 ? lo : hi) = delta;
      if ((error < 0.0 && delta >= settings_.max_correction) || (error > 0.0 && delta <= -settings_.max_correction)) {
        report.stop = BalanceStop::kCorrectionBound;
        break;
      }
      double next = slope > 0.0 ? delta - (volume - rest_volume_mm3_) / slope : 0.5 * (lo + hi);
      if (!(next > lo && next < hi)) next = 0.5 * (lo + hi);  // bisection when Newton leaves the bracket
      delta = next;
      volume = sum(delta, volume_changes, clearance_mm, &slope);
      ++report.iterations;
    }
    field.setWeights(rest_weights_ + delta * correction_weights_);
  }
  report.correction = delta;
  report.volume_mm3 = volume;
  report.ratio = volume / rest_volume_mm3_;
  return report;
}

}  // namespace rbfmuscle
