#pragma once
/// @file
/// Mesh file in, fitted and measured surface out: what `rbfmuscle fit` does,
/// as a library call so tests and the muscle component share it.
#include <functional>
#include <string>

#include "fit/fit_metrics.h"
#include "fit/greedy_fitter.h"
#include "fit/rbf_file.h"

namespace rbfmuscle {

/// A fitted surface, its figures and how the fit ended.
struct MeshFit {
  RbfSurface surface;
  FitMetrics metrics;
  int rounds = 0;
  std::string stop_reason;   ///< why the greedy loop ended (see GreedyFitResult)
  RefitReport final_refit;   ///< how the last weight refit ended
  int check_samples_added = 0;  ///< check points the fit made samples (see fitGreedy)
  int resigned_samples = 0;     ///< samples whose side the winding number decided (see SampleSet)
  double seconds = 0.0;  ///< wall time of sampling + fit (metrics excluded)
};

/// Loads the mesh with loadSolidMesh (defects repaired where safe, with a warning on
/// stderr; then validated: watertight, consistently wound — or rewound when
/// `fix_winding`), moves it to the muscle frame M (origin at the centre
/// of its bounding box), samples, fits and measures.
/// @throws MeshError for a bad mesh, std::invalid_argument for bad settings.
MeshFit fitMeshFile(const std::string& mesh_path, const FitSettings& settings, bool fix_winding,
                    const FitProgressFn& progress = {});

/// Chooses one global shape α for all centres by golden-section search on
/// log α over [α_lo, α_hi], minimising C_m (at most `evaluations` fits), and
/// returns the fit at the best α found. `report` hears each tried α and C_m.
MeshFit fitMeshFileGlobalShape(const std::string& mesh_path, FitSettings settings, bool fix_winding,
                               double alpha_lo, double alpha_hi, int evaluations,
                               const std::function<void(double alpha, double metric)>& report = {});

}  // namespace rbfmuscle
