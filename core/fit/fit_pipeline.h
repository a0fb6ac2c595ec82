// SPDX-License-Identifier: Apache-2.0
#pragma once
/// @file
/// Mesh file in, fitted and measured surface out: what `rbfmuscle fit` does,
/// as a library call so tests and the muscle component share it.
#include <functional>
#include <string>
#include <vector>

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
  int near_crumb_samples_added = 0;  ///< peaks and floors of near crumbs the fit made samples (see fitGreedy)
  int near_crumbs_left = 0;     ///< near crumbs the surface still has (settings.crumb_margin_mm)
  int resigned_samples = 0;     ///< samples whose side the winding number decided (see SampleSet)
  double seconds = 0.0;  ///< wall time of sampling + fit (metrics excluded)
  int mesh_components = 0;  ///< connected pieces of the fitted mesh (as loaded and repaired)
  /// What makes the surface suspect, one sentence each naming the mesh and the figures
  /// (describeSuspectFit); empty for a fit that came out as one closed piece per mesh piece.
  /// The `fit` command and loadOrFitSurface print them as warnings.
  std::vector<std::string> warnings;
};

/// The fit refuses a mesh that spans fewer than this many cells of the extracted surface
/// (FitSettings::surface_cell_mm): its surface could not be measured.
constexpr double kMinCellsAcrossMesh = 4.0;

/// Self-intersecting triangle pairs counted at most before the fit's warning (the search
/// stops there).
constexpr int kMaxReportedSelfIntersections = 1000;

/// Warnings about a fitted surface (mm): more pieces than the mesh has (`mesh_components`),
/// or a surface that runs into the extraction box (clipped nodes: positive field on the box
/// faces). Either means the field is positive where it should not be: where no sample holds
/// it down, or between centres too narrow for the budget. Each names
/// `mesh_path` and the figures (pieces, clipped nodes, Jaccard, mean / p95 / max distance,
/// volume ratio). Empty when neither holds.
std::vector<std::string> describeSuspectFit(const FitMetrics& metrics, int mesh_components,
                                            const std::string& mesh_path);

/// Changes a loaded mesh (in its file's frame, mm) before it is fitted: moveOutOfSolids for a
/// muscle that overlaps its bones.
using MeshAdjustFn = std::function<void(TriangleMesh& mesh)>;

/// Loads the mesh with loadSolidMesh (defects repaired where safe, with a warning on
/// stderr; then validated: watertight, consistently wound — or rewound when
/// `fix_winding`), applies `adjust` (when given), moves it to the muscle frame M (origin at
/// the centre of its bounding box), samples, fits and measures. The surface names the mesh
/// file by its hash (source_hash), adjusted or not. A mesh of several separate pieces, or one
/// whose triangles cross (self_intersection.h), is fitted with a warning (printMeshWarning):
/// the result is poor without being invalid.
/// @throws MeshError for a bad mesh, for one spanning fewer than kMinCellsAcrossMesh cells
///   of the extracted surface, and when the fitted surface is empty (no f > 0 found: the
///   options do not suit the mesh's size); std::invalid_argument for bad settings.
MeshFit fitMeshFile(const std::string& mesh_path, const FitSettings& settings, bool fix_winding,
                    const FitProgressFn& progress = {}, const MeshAdjustFn& adjust = {});

/// Chooses one global shape α for all centres by golden-section search on
/// log α over [α_lo, α_hi], minimising C_m (at most `evaluations` fits), and
/// returns the fit at the best α found. `report` hears each tried α and C_m.
MeshFit fitMeshFileGlobalShape(const std::string& mesh_path, FitSettings settings, bool fix_winding,
                               double alpha_lo, double alpha_hi, int evaluations,
                               const std::function<void(double alpha, double metric)>& report = {},
                               const MeshAdjustFn& adjust = {});

}  // namespace rbfmuscle
