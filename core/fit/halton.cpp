// SPDX-License-Identifier: Apache-2.0
#include "fit/halton.h"

namespace rbfmuscle {

double calcRadicalInverse(std::uint64_t index, int base) {
  double result = 0.0;
  double digit_scale = 1.0 / base;
  while (index > 0) {
    result += static_cast<double>(index % base) * digit_scale;
    index /= base;
    digit_scale /= base;
  }
  return result;
}

Eigen::Matrix3Xd makeHaltonPoints(const Eigen::AlignedBox3d& box_mm, int count,
                                  std::uint64_t first_index) {
  Eigen::Matrix3Xd points(3, count);
  const Eigen::Vector3d sizes = box_mm.sizes();
  for (int k = 0; k < count; ++k) {
    const std::uint64_t index = first_index + static_cast<std::uint64_t>(k) + 1;
    const Eigen::Vector3d unit(calcRadicalInverse(index, 2), calcRadicalInverse(index, 3),
                               calcRadicalInverse(index, 5));
    points.col(k) = box_mm.min() + unit.cwiseProduct(sizes);
  }
  return points;
}

}  // namespace rbfmuscle
