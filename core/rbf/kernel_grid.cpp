// SPDX-License-Identifier: Apache-2.0
#include "rbf/kernel_grid.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace rbfmuscle {

namespace {

/// Cells per axis of [lo, hi] with edge `cell` from `origin`, as inclusive index range.
void cellRange(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi, const Eigen::Vector3d& origin, double cell,
               const Eigen::Vector3i& dims, Eigen::Vector3i& first, Eigen::Vector3i& last) {
  for (int i = 0; i < 3; ++i) {
    first[i] = std::clamp(static_cast<int>(std::floor((lo[i] - origin[i]) / cell)), 0, dims[i] - 1);
    last[i] = std::clamp(static_cast<int>(std::floor((hi[i] - origin[i]) / cell)), 0, dims[i] - 1);
  }
}

long long countCells(const Eigen::Vector3i& first, const Eigen::Vector3i& last) {
  return static_cast<long long>(last[0] - first[0] + 1) * (last[1] - first[1] + 1) * (last[2] - first[2] + 1);
}

}  // namespace

void KernelGrid::build(const Eigen::Matrix3Xd& lower_mm, const Eigen::Matrix3Xd& upper_mm, int max_entries_per_box) {
  if (lower_mm.cols() != upper_mm.cols())
    throw std::invalid_argument("KernelGrid: " + std::to_string(lower_mm.cols()) + " lower and " +
                                std::to_string(upper_mm.cols()) + " upper corners");
  if (max_entries_per_box < 1) throw std::invalid_argument("KernelGrid: max_entries_per_box must be >= 1");
  const Eigen::Index n = lower_mm.cols();
  for (Eigen::Index k = 0; k < n; ++k)
    if (!lower_mm.col(k).allFinite() || !upper_mm.col(k).allFinite() ||
        (lower_mm.col(k).array() > upper_mm.col(k).array()).any())
      throw std::invalid_argument("KernelGrid: box " + std::to_string(k) + " is not finite or has lower > upper");
  num_boxes_ = static_cast<int>(n);
  entries_.clear();
  cell_start_.assign(2, 0);
  dims_ = Eigen::Vector3i::Ones();
  origin_mm_.setZero();
  cell_mm_ = 1.0;
  if (n == 0) return;

  origin_mm_ = lower_mm.rowwise().minCoeff();
  const Eigen::Vector3d extent = upper_mm.rowwise().maxCoeff() - origin_mm_;
  std::vector<double> edges(static_cast<size_t>(n));
  for (Eigen::Index k = 0; k < n; ++k) edges[static_cast<size_t>(k)] = (upper_mm.col(k) - lower_mm.col(k)).maxCoeff();
  std::nth_element(edges.begin(), edges.begin() + n / 2, edges.end());
  cell_mm_ = std::max(edges[static_cast<size_t>(n / 2)] / 4.0, 1e-3 * std::max(extent.maxCoeff(), 1e-9));
  Eigen::Vector3i first, last;
  for (int attempt = 0;; ++attempt) {  // doubling ends: one cell holds everything after ≤ ~60 doublings
    for (int i = 0; i < 3; ++i) dims_[i] = std::max(1, static_cast<int>(std::ceil(extent[i] / cell_mm_)) + 1);
    long long entries = 0;
    for (Eigen::Index k = 0; k < n; ++k) {
      cellRange(lower_mm.col(k), upper_mm.col(k), origin_mm_, cell_mm_, dims_, first, last);
      entries += countCells(first, last);
    }
    const long long cells = static_cast<long long>(dims_[0]) * dims_[1] * dims_[2];
    if ((entries <= static_cast<long long>(max_entries_per_box) * n && cells <= 64LL * n + 4096) || attempt > 80) break;
    cell_mm_ *= 2.0;
  }
  const size_t cells = static_cast<size_t>(dims_[0]) * dims_[1] * dims_[2];
  cell_start_.assign(cells + 1, 0);
  for (Eigen::Index k = 0; k < n; ++k) {  // counting pass
    cellRange(lower_mm.col(k), upper_mm.col(k), origin_mm_, cell_mm_, dims_, first, last);
    for (int z = first[2]; z <= last[2]; ++z)
      for (int y = first[1]; y <= last[1]; ++y)
        for (int x = first[0]; x <= last[0]; ++x)
          ++cell_start_[static_cast<size_t>((z * dims_[1] + y) * dims_[0] + x) + 1];
  }
  for (size_t c = 0; c < cells; ++c) cell_start_[c + 1] += cell_start_[c];
  entries_.resize(static_cast<size_t>(cell_start_[cells]));
  std::vector<int> fill(cell_start_.begin(), cell_start_.end() - 1);
  for (Eigen::Index k = 0; k < n; ++k) {  // boxes in ascending order, so every list is ascending
    cellRange(lower_mm.col(k), upper_mm.col(k), origin_mm_, cell_mm_, dims_, first, last);
    for (int z = first[2]; z <= last[2]; ++z)
      for (int y = first[1]; y <= last[1]; ++y)
        for (int x = first[0]; x <= last[0]; ++x)
          entries_[static_cast<size_t>(fill[static_cast<size_t>((z * dims_[1] + y) * dims_[0] + x)]++)] =
              static_cast<int>(k);
  }
}

void KernelGrid::findCandidates(const Eigen::Vector3d& p_mm, const int*& first, int& count) const {
  first = entries_.data();
  count = 0;
  if (num_boxes_ == 0) return;
  int cell[3];
  for (int i = 0; i < 3; ++i) {
    const double u = std::floor((p_mm[i] - origin_mm_[i]) / cell_mm_);
    if (!(u >= 0.0) || u >= dims_[i]) return;
    cell[i] = static_cast<int>(u);
  }
  const size_t c = static_cast<size_t>((cell[2] * dims_[1] + cell[1]) * dims_[0] + cell[0]);
  first = entries_.data() + cell_start_[c];
  count = cell_start_[c + 1] - cell_start_[c];
}

}  // namespace rbfmuscle
