// SPDX-License-Identifier: Apache-2.0
#pragma once
/// @file
/// A cell grid over axis-aligned boxes: which boxes may contain a point, in one lookup.
#include <Eigen/Core>
#include <Eigen/Geometry>

#include <vector>

namespace rbfmuscle {

/// Uniform cells over the union of N boxes (mm, any frame); each cell lists, in ascending
/// order, the boxes that overlap it, so a point's candidates are one cell's list (a superset
/// of the boxes holding the point). Built for the bounding boxes of ellipsoidal kernels,
/// where a search by one radius over-fetches (an ellipsoid's box is tight per axis).
///
/// The cell edge is chosen by build(): the smallest power-of-two multiple of the median box
/// edge / 4 for which the lists hold at most `max_entries_per_box` · N entries, so memory is
/// O(N) whatever the mix of sizes. Queries are const and thread-safe; build() is not.
class KernelGrid {
 public:
  /// Indexes the boxes [lower_k, upper_k] (3×N each, mm). N may be 0.
  /// @throws std::invalid_argument on a size mismatch, a non-finite corner, lower > upper,
  ///   or a cap below 1.
  void build(const Eigen::Matrix3Xd& lower_mm, const Eigen::Matrix3Xd& upper_mm, int max_entries_per_box = 64);

  /// The boxes whose extent overlaps the cell holding p: `count` ascending indices from
  /// `first` (count 0 when p lies outside every box's cell range).
  void findCandidates(const Eigen::Vector3d& p_mm, const int*& first, int& count) const;

  /// Number of indexed boxes.
  int getNumBoxes() const { return num_boxes_; }
  /// Cell edge (mm); 0 before build.
  double getCellSize() const { return cell_mm_; }
  /// Entries of all lists (memory and build cost).
  long long countEntries() const { return static_cast<long long>(entries_.size()); }

 private:
  int num_boxes_ = 0;
  double cell_mm_ = 0.0;
  Eigen::Vector3d origin_mm_ = Eigen::Vector3d::Zero();
  Eigen::Vector3i dims_ = Eigen::Vector3i::Zero();
  std::vector<int> cell_start_;  ///< CSR offsets, size cells + 1
  std::vector<int> entries_;     ///< box indices, ascending within a cell
};

}  // namespace rbfmuscle
