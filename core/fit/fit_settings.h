// SPDX-License-Identifier: Apache-2.0
#pragma once
/// @file
/// Every knob of the static fit, with its default and unit. Written into the
/// .rbf file so a fitted surface records how it was made.
#include <string>
#include <vector>

namespace rbfmuscle {

/// Settings of the greedy Gaussian fit (dissertation Alg. 2 with a joint
/// least-squares refit of the weights; see greedy_fitter.h).
struct FitSettings {
  int max_centres = 1000;          ///< centre budget N
  double tolerance_mm = 0.0;       ///< stop early when the RMS residual on surface samples ≤ this (0 = budget only)
  /// τ: target t(x) = clamp(−s(x), −τ, τ), offset b = −τ (mm). A target clamped closer to
  /// the surface builds the muscle from wide positive Gaussians carved by narrow negative
  /// ones, and a carved field tears when the motion moves the carving centres
  /// (docs/design.md, Fits).
  double clamp_mm = 10.0;
  static constexpr double kMaxClamp_mm = 1e4;  ///< largest τ the fit takes (10 m: any muscle fits in it)
  double normal_offset_mm = 1.0;   ///< d: samples ±d along the vertex normals (mm)
  int halton_samples = 30000;      ///< Halton(2,3,5) samples in the padded box
  double padding_fraction = 0.1;   ///< box padding, fraction of the largest box side on each side
  /// Check points (fitGreedy): points where the field must be on the right side of the
  /// surface, watched but not fitted until it is not. This many Halton points of the padded
  /// box within τ of the surface (the clamp band, where the surface can go astray) …
  int check_band_samples = 30000;
  /// … and, when true, points 2d, 4d, 8d, … (< τ) off every vertex along its normal, in and
  /// out: they fill the pockets of a concave surface, where the fields of centres on either
  /// side meet and the band points alone can leave a crumb.
  bool check_normal_layers = true;
  /// Checks begin once this fraction of the centre budget is placed, so that the rest can
  /// carve where they find the field wrong. Earlier the field is wrong nearly everywhere and
  /// the checks only add samples, which cost accuracy; after the last round only nothing is
  /// left to carve.
  double check_start_fraction = 0.75;
  /// A check point |t| from the surface is violated unless f lies on its side by more than
  /// check_slope·|t| (f's unit), ∈ [0, 1]; 0 asks for the right side only. Where f is flat
  /// just outside the surface (a shelf), a motion that moves f by a little makes islands of
  /// the shelf: with 0 the psoas major fell into pieces (1 mm grid) at 25 of the main job's
  /// 81 frames, with 0.5 at 2, all near the bone (docs/design.md, Fits).
  double check_slope = 0.5;
  /// Bumps of f apart from the surface, and dips inside it, that come within this of f = 0 (mm,
  /// in f's unit) are carved with the check points (near_crumbs.h): where a motion moves f by
  /// less, no island or bubble of the surface appears. Half the normal offset d: the psoas
  /// major's three bumps, 0.02–0.16 below f = 0 at rest, rose into islands in the hip scenes
  /// (docs/design.md, Fits).
  double crumb_margin_mm = 0.5;
  /// Shape set α (mm⁻²) the greedy step chooses from; σ = α^−½ from ~14 mm to ~1.4 mm.
  /// No wider shapes: a Gaussian much wider than the muscle's thickness cannot follow a bend,
  /// and it reaches more quadrature points, which slows every frame.
  std::vector<double> shapes_per_mm2 = {0.005, 0.01, 0.02, 0.05, 0.1, 0.2, 0.5};
  double regularisation_gamma = 0.9;  ///< γ of eq. 7.12: 1 = pure error, lower = prefer wide shapes near the surface
  double ridge = 1e-6;             ///< Tikhonov weight μ on ‖λ‖², relative to the mean column norm²
  int candidates_per_round = 64;   ///< samples of largest residual scored per round
  double batch_fraction = 0.1;     ///< centres added per round, as a fraction of the current count (≥ 1)
  int score_samples = 4000;        ///< neighbours per shape that score a candidate (wider shapes: every k-th)
  int refit_iterations = 40;       ///< conjugate-gradient cap per refit of λ
  int final_refit_iterations = 400;///< conjugate-gradient cap for the last refit
  double refit_tolerance = 1e-7;   ///< relative residual of the normal equations that stops a refit
  double cutoff = 1e-8;            ///< ε: a centre is ignored where φ < ε
  double metric_sigma = 0.5;       ///< σ of C_m = (1−σ)(1−Jaccard) + σ·MSE/MSE_max
  int metric_points = 200000;      ///< Halton points for the Jaccard index and MSE (≥ 1e5)
  double surface_cell_mm = 1.0;    ///< grid cell of the extracted surface (mm)
  double global_shape_per_mm2 = 0; ///< > 0: one shape α for every centre (no choice per centre)
};

/// One line `key=value key=value …` describing the settings (for files and logs).
std::string describeSettings(const FitSettings& settings);

}  // namespace rbfmuscle
