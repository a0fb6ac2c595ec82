// SPDX-License-Identifier: Apache-2.0
#include "rbf/neighbour_lists.h"

#include "rbf/kernel_grid.h"

#include <cmath>
#include <stdexcept>
#include <string>

namespace rbfmuscle {

NeighbourLists findMaterialNeighbours(const DeformedField& field, const Eigen::Matrix3Xd& rest_points_mm,
                                      double radius_scale, double margin_mm) {
  if (!(radius_scale >= 1.0) || !(margin_mm >= 0.0) || !std::isfinite(radius_scale) || !std::isfinite(margin_mm))
    throw std::invalid_argument("findMaterialNeighbours: need radius_scale >= 1 and margin_mm >= 0");
  const int n = field.getNumKernels();
  Eigen::VectorXd reach(n);
  Eigen::Matrix3Xd lower(3, n), upper(3, n);
  for (int k = 0; k < n; ++k) {
    reach[k] = radius_scale * std::sqrt(field.getCutoffExponent() / field.getShapes()[k]) + margin_mm;
    lower.col(k) = field.getCentres().col(k).array() - reach[k];
    upper.col(k) = field.getCentres().col(k).array() + reach[k];
  }
  KernelGrid grid;
  grid.build(lower, upper);
  NeighbourLists lists;
  lists.start.assign(1, 0);
  for (Eigen::Index j = 0; j < rest_points_mm.cols(); ++j) {
    const Eigen::Vector3d x = rest_points_mm.col(j);
    if (!x.allFinite()) throw std::invalid_argument("findMaterialNeighbours: point " + std::to_string(j) + " is not finite");
    const int* first = nullptr;
    int count = 0;
    grid.findCandidates(x, first, count);
    for (int i = 0; i < count; ++i) {
      const int k = first[i];
      if ((x - field.getCentres().col(k)).squaredNorm() <= reach[k] * reach[k]) lists.kernels.push_back(k);
    }
    lists.start.push_back(static_cast<int>(lists.kernels.size()));
  }
  return lists;
}

}  // namespace rbfmuscle
