// SPDX-License-Identifier: Apache-2.0
#include "pipeline/tissue_fold.h"

namespace rbfmuscle {

FieldSample foldOutOfBones(const DeformedField& field, const BoneClearance& bones, const Eigen::Vector3d& y_mm,
                           const FieldSample& f) {
  FieldSample best = f;
  bones.visitFolds(y_mm, f.value, [&](const Eigen::Vector3d& mirror, const Eigen::Vector3d& foot, const Eigen::Vector3d& n,
                             double cap_mm, const Eigen::Vector3d& cap_gradient) {
    if (!(cap_mm > best.value)) return;  // the fold is at most the cap
    const FieldSample at_mirror = field.calcSample(mirror);
    if (!(at_mirror.value > best.value)) return;
    const FieldSample at_foot = field.calcSample(foot);
    if (!(at_foot.value > best.value)) return;
    // min(f(m), f(q), cap) with the gradient of its smallest term: d m/dy = I − 2nnᵀ, d q/dy = I − nnᵀ.
    if (cap_mm <= at_mirror.value && cap_mm <= at_foot.value) {
      best = FieldSample{cap_mm, cap_gradient};
    } else if (at_mirror.value <= at_foot.value) {
      best = FieldSample{at_mirror.value, at_mirror.gradient - 2.0 * n.dot(at_mirror.gradient) * n};
    } else {
      best = FieldSample{at_foot.value, at_foot.gradient - n.dot(at_foot.gradient) * n};
    }
  });
  return best;
}

}  // namespace rbfmuscle
