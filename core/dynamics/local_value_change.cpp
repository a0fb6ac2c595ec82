#include "dynamics/local_value_change.h"

#include <algorithm>
#include <cmath>

namespace rbfmuscle {

int changeValueAt(const GaussianField& field, const Eigen::Vector3d& x_mm, double change,
                  const WeightEditLimits& limits, Eigen::VectorXd& weights, ActiveCentres& active,
                  bool attached_too) {
  field.findActiveCentres(x_mm, active);
  for (const bool free_only : {true, false}) {
    if (!free_only && !attached_too) break;
    double norm = 0.0;  // Σ |λ| φ²
    for (int a = 0; a < active.size(); ++a) {
      const int k = active.indices[static_cast<size_t>(a)];
      const double phi = active.phi[static_cast<size_t>(a)];
      if (!free_only || limits.free_mask[static_cast<size_t>(k)]) norm += std::abs(weights(k)) * phi * phi;
    }
    if (!(norm > 0.0)) continue;
    int changed = 0;
    for (int a = 0; a < active.size(); ++a) {
      const int k = active.indices[static_cast<size_t>(a)];
      if (free_only && !limits.free_mask[static_cast<size_t>(k)]) continue;
      // Far centres alone would need huge weights: at most |λ| per call and never beyond the limit.
      const double step = std::clamp(change * active.phi[static_cast<size_t>(a)] / norm, -1.0, 1.0);
      const double updated = weights(k) + step * std::abs(weights(k));
      const double limit = limits.max_abs_weights(k);
      const double clamped = weights(k) > 0.0 ? std::clamp(updated, 0.0, limit) : std::clamp(updated, -limit, 0.0);
      if (clamped != weights(k)) {
        weights(k) = clamped;
        ++changed;
      }
    }
    return changed;
  }
  return 0;
}

}  // namespace rbfmuscle
