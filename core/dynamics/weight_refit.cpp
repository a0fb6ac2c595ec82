#include "dynamics/weight_refit.h"

#include "dynamics/quadrature.h"

#include <cmath>
#include <stdexcept>
#include <string>

namespace rbfmuscle {

WeightRefit::WeightRefit(const GaussianField& rest_field, const Attachments& attachments,
                         const RefitSettings& settings, double blend_length_mm)
    : settings_(settings) {
  if (settings.sample_count < 8) {
    throw std::invalid_argument("WeightRefit: sample_count " + std::to_string(settings.sample_count) +
                                ", expected >= 8");
  }
  if (!(settings.ridge > 0.0 && std::isfinite(settings.ridge))) {
    throw std::invalid_argument("WeightRefit: ridge " + std::to_string(settings.ridge) + ", expected finite > 0");
  }
  if (settings.max_iterations < 1) {
    throw std::invalid_argument("WeightRefit: max_iterations " + std::to_string(settings.max_iterations) +
                                ", expected >= 1");
  }
  if (!(settings.tolerance > 0.0)) {
    throw std::invalid_argument("WeightRefit: tolerance " + std::to_string(settings.tolerance) + ", expected > 0");
  }
  if (!(settings.surface_width >= 0.0)) {
    throw std::invalid_argument("WeightRefit: surface_width " + std::to_string(settings.surface_width) +
                                ", expected >= 0");
  }
  const int N = rest_field.getNumCentres();
  if (static_cast<int>(attachments.bone_of_centre.size()) != N) {
    throw std::invalid_argument("WeightRefit: attachments cover " + std::to_string(attachments.bone_of_centre.size()) +
                                " centres, the field has " + std::to_string(N));
  }
  QuadratureSettings grid;
  grid.target_count = settings.sample_count;
  grid.band_value = settings.sample_band;
  rest_samples_mm_ = makeQuadrature(rest_field, grid).points_mm;
  samples_mm_ = rest_samples_mm_;
  rest_field.calcValues(rest_samples_mm_, targets_);
  row_scales_.setOnes(targets_.size());
  if (settings.surface_width > 0.0) {
    for (Eigen::Index j = 0; j < targets_.size(); ++j) {
      const double u = targets_[j] / settings.surface_width;
      row_scales_[j] = 1.0 / std::sqrt(1.0 + u * u);
    }
  }
  sample_weights_ = calcBlendWeights(rest_samples_mm_, rest_field.getCentres(), attachments, blend_length_mm);
  column_of_centre_.assign(static_cast<size_t>(N), -1);
  for (int k = 0; k < N; ++k) {
    if (settings.refit_attached || !attachments.isAttached(k)) {
      column_of_centre_[static_cast<size_t>(k)] = static_cast<int>(refitted_.size());
      refitted_.push_back(k);
    }
  }
  active_.resize(static_cast<size_t>(rest_samples_mm_.cols()));
  rows_.resize(refitted_.size());
  values_.resize(refitted_.size());
}

WeightRefitReport WeightRefit::run(GaussianField& field, const std::vector<DualQuaternion>& transforms) {
  if (field.getNumCentres() != static_cast<int>(column_of_centre_.size())) {
    throw std::invalid_argument("WeightRefit::run: field has " + std::to_string(field.getNumCentres()) +
                                " centres, expected " + std::to_string(column_of_centre_.size()));
  }
  WeightRefitReport report;
  const int S = static_cast<int>(rest_samples_mm_.cols());
  const int R = static_cast<int>(refitted_.size());
  report.samples = S;
  report.refitted_centres = R;
  predictPoints(rest_samples_mm_, sample_weights_, transforms, samples_mm_);
#pragma omp parallel for schedule(static)
  for (int j = 0; j < S; ++j) field.findActiveCentres(samples_mm_.col(j), active_[static_cast<size_t>(j)]);
  for (int c = 0; c < R; ++c) {
    rows_[static_cast<size_t>(c)].clear();
    values_[static_cast<size_t>(c)].clear();
  }
  weights_ = field.getWeights();
  // Residual y_j = f₀(y_j) − f(z_j) with the previous λ; the rows of each column ascend with j.
  rhs_.resize(S);
  for (int j = 0; j < S; ++j) {
    const ActiveCentres& active = active_[static_cast<size_t>(j)];
    double value = field.getOffset();
    for (int n = 0; n < active.size(); ++n) {
      const int k = active.indices[static_cast<size_t>(n)];
      const double phi = active.phi[static_cast<size_t>(n)];
      value += weights_[k] * phi;
      const int c = column_of_centre_[static_cast<size_t>(k)];
      if (c >= 0) {
        rows_[static_cast<size_t>(c)].push_back(j);
        values_[static_cast<size_t>(c)].push_back(row_scales_[j] * phi);
      }
    }
    rhs_[j] = row_scales_[j] * (targets_[j] - value);
  }
  const double weight_sum = row_scales_.squaredNorm();
  report.rms_residual_before = S > 0 ? rhs_.norm() / std::sqrt(weight_sum) : 0.0;
  DesignMatrix design(S);
  for (int c = 0; c < R; ++c) design.appendColumn(rows_[static_cast<size_t>(c)], values_[static_cast<size_t>(c)]);
  report.nonzeros = design.getNumNonZeros();
  const double mean_norm = R > 0 ? design.calcColumnNormsSquared().mean() : 0.0;
  const double mu = settings_.ridge * (mean_norm > 0.0 ? mean_norm : 1.0);
  delta_.setZero(R);
  report.solve = refitWeights(design, rhs_, mu, settings_.max_iterations, settings_.tolerance, delta_);
  for (int c = 0; c < R; ++c) weights_[refitted_[static_cast<size_t>(c)]] += delta_[c];
  field.setWeights(weights_);
  design.multiply(delta_, product_);
  report.rms_residual_after = S > 0 ? (rhs_ - product_).norm() / std::sqrt(weight_sum) : 0.0;
  return report;
}

}  // namespace rbfmuscle
