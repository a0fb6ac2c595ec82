// SPDX-License-Identifier: Apache-2.0
#include "fit/fit_settings.h"

#include <sstream>

namespace rbfmuscle {

std::string describeSettings(const FitSettings& s) {
  std::ostringstream out;
  out.precision(10);
  out << "max_centres=" << s.max_centres << " tolerance_mm=" << s.tolerance_mm
      << " clamp_mm=" << s.clamp_mm << " normal_offset_mm=" << s.normal_offset_mm
      << " halton_samples=" << s.halton_samples << " padding_fraction=" << s.padding_fraction
      << " check_band_samples=" << s.check_band_samples << " check_normal_layers=" << s.check_normal_layers
      << " check_start_fraction=" << s.check_start_fraction << " check_slope=" << s.check_slope
      << " crumb_margin_mm=" << s.crumb_margin_mm
      << " shapes_per_mm2=";
  for (std::size_t k = 0; k < s.shapes_per_mm2.size(); ++k) out << (k ? "," : "") << s.shapes_per_mm2[k];
  out << " regularisation_gamma=" << s.regularisation_gamma << " ridge=" << s.ridge
      << " candidates_per_round=" << s.candidates_per_round << " batch_fraction=" << s.batch_fraction
      << " score_samples=" << s.score_samples << " refit_iterations=" << s.refit_iterations
      << " final_refit_iterations=" << s.final_refit_iterations
      << " refit_tolerance=" << s.refit_tolerance << " cutoff=" << s.cutoff
      << " metric_sigma=" << s.metric_sigma << " metric_points=" << s.metric_points
      << " surface_cell_mm=" << s.surface_cell_mm << " global_shape_per_mm2=" << s.global_shape_per_mm2;
  return out.str();
}

}  // namespace rbfmuscle
