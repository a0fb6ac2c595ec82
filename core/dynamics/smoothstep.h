// SPDX-License-Identifier: Apache-2.0
#pragma once
/// @file
/// The C¹ step that every fade of the tissue map uses.
#include <algorithm>

namespace rbfmuscle {

/// 3u² − 2u³ of u clamped to [0, 1]: 0 at u ≤ 0, 1 at u ≥ 1, flat at both ends.
inline double calcSmoothstep(double u) {
  u = std::clamp(u, 0.0, 1.0);
  return u * u * (3.0 - 2.0 * u);
}

}  // namespace rbfmuscle
