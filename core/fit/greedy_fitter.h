// SPDX-License-Identifier: Apache-2.0
#pragma once
/// @file
/// Greedy choice of Gaussian centres and shapes (dissertation Alg. 2, §7.2,
/// regulariser eq. 7.12) with a joint ridge least-squares refit of all weights
/// after every round.
#include <functional>
#include <string>

#include "fit/design_matrix.h"
#include "fit/fit_settings.h"
#include "fit/sample_set.h"
#include "rbf/gaussian_field.h"

namespace rbfmuscle {

/// State reported after every round.
struct FitProgress {
  int round = 0;
  int centres = 0;
  int max_centres = 0;
  double rms_surface_mm = 0.0;  ///< RMS of t − f over the surface samples
  double rms_all_mm = 0.0;      ///< RMS of t − f over all samples
};
using FitProgressFn = std::function<void(const FitProgress&)>;

/// Points off the samples where the fit must hold f to the mesh's side, with their signed
/// distances s (negative inside).
struct ExtraSamples {
  Eigen::Matrix3Xd points_mm;
  Eigen::VectorXd signed_distance_mm;
};
/// Finds, in a fitted field, the peaks of bumps that come within a margin of its surface
/// (near_crumbs.h), with their signed distances.
using FindNearCrumbsFn = std::function<ExtraSamples(const GaussianField&)>;

/// The fitted field and how the fit ended.
struct GreedyFitResult {
  GaussianField field;          ///< f = −τ + Σ λₖ φₖ in the muscle frame M
  int rounds = 0;
  std::string stop_reason;      ///< "centre budget", "tolerance" or "no candidate reduces the error"
  RefitReport final_refit;      ///< how the last weight refit ended
  int check_samples_added = 0;  ///< check points made samples because the field had them on the wrong side
  int near_crumb_samples_added = 0;  ///< peaks and floors of near crumbs made samples
  int near_crumbs_left = 0;     ///< near crumbs in the returned field (0 without a finder)
  double rms_surface_mm = 0.0;
  double rms_all_mm = 0.0;
};

/// Fits f to the clamped signed-distance targets of `samples`.
///
/// Each round: the samples with the largest |t − f| (kept apart by 2d) become
/// candidate centres; every candidate is scored with every shape α by the
/// error reduction of a single Gaussian with its optimal weight,
/// g²/h (g = Σ φ·(t−f), h = Σ φ², on a fixed subset of samples); the choice
/// minimises eq. 7.12, C_r = γ (1 − score/score_best) + (1−γ)(|s_c|/s_max)(α/α_max),
/// which prefers wide shapes and centres near the surface; a candidate inside
/// the mesh may only add (λ > 0) and one outside only carve (λ < 0). The best
/// non-overlapping candidates (batch_fraction of the current count) join, and
/// all weights are refitted jointly. Stops at the centre budget, at the
/// tolerance on surface samples, or when no candidate helps — reported in
/// stop_reason.
///
/// Check points (samples.check_*) hold the field to the right side of the surface where no
/// sample does: the samples lie on the surface, 1 mm off it and in a box-wide Halton cover
/// 6–7 mm apart, but a Gaussian reaches up to 60 mm, so the field between them is free.
/// Once settings.check_start_fraction of the budget is placed, after every round's refit,
/// the check points with |t| ≥ d (the normal offset) where sign(f) ≠ sign(t) become
/// samples (kind kCheck), at most candidates_per_round of them, largest |t − f| first:
/// candidates for the next centres and terms of every later refit.
/// After the last round this repeats with the final refit, at most kMaxFinalCheckPasses
/// times. check_samples_added counts them.
///
/// Check points hold only the side, and only where they lie. A bump of f that stays just below
/// 0 apart from the surface (the psoas major's fit had four within 0.5) passes them, and the
/// least rise of f in a motion makes it an island; a bubble can lie between them (the gluteus
/// maximus fitted with 2000 centres had one of 55 mm³). So, with the check points, the peaks and
/// floors `find_near_crumbs` finds become samples (kind kNearCrumb) at their true targets, at
/// most candidates_per_round a time; near_crumbs_left counts those the returned field still has.
GreedyFitResult fitGreedy(const SampleSet& samples, const FitSettings& settings,
                          const FitProgressFn& progress = {}, const FindNearCrumbsFn& find_near_crumbs = {});

}  // namespace rbfmuscle
