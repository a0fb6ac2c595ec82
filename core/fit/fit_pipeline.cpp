// SPDX-License-Identifier: Apache-2.0
#include "fit/fit_pipeline.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <sstream>
#include <stdexcept>

#include "fit/near_crumbs.h"
#include "fit/sample_set.h"
#include "geometry/iso_surface.h"
#include "geometry/mesh_check.h"
#include "geometry/mesh_distance.h"
#include "geometry/mesh_io.h"
#include "geometry/self_intersection.h"
#include "geometry/mesh_measures.h"
#include "geometry/solid_mesh.h"
#include "geometry/winding_number.h"
#include "io/format_number.h"

namespace rbfmuscle {
namespace {

std::string getFileName(const std::string& path) {
  const std::size_t slash = path.find_last_of('/');
  return slash == std::string::npos ? path : path.substr(slash + 1);
}

/// The validated mesh in the muscle frame and what fitting needs of it.
struct PreparedMesh {
  TriangleMesh mesh_M;
  Eigen::Vector3d offset_mm;
  std::string hash;
  int components = 0;
};

/// Warns about what makes a closed mesh a poor target without making it invalid: several
/// separate pieces, or triangles crossing each other.
void warnAboutShape(const TriangleMesh& mesh, const std::string& mesh_path, const MeshWarningFn& warn) {
  if (!warn) return;
  const int pieces = checkMesh(mesh).components;
  if (pieces > 1)
    warn(mesh_path + ": the mesh has " + std::to_string(pieces) +
         " separate pieces; they are fitted as one surface with one box and one set of centres, "
         "which fits none of them well (fit each piece on its own)");
  const SelfIntersections crossings = findSelfIntersections(mesh, kMaxReportedSelfIntersections);
  if (crossings.pairs > 0) {
    std::ostringstream text;
    text << mesh_path << ": the mesh crosses itself: " << (crossings.capped ? "at least " : "") << crossings.pairs
         << " pairs of triangles intersect (e.g. triangles";
    for (std::size_t k = 0; k < crossings.examples.size(); ++k)
      text << (k ? ", " : " ") << crossings.examples[k].first << " and " << crossings.examples[k].second;
    text << "); its inside is ambiguous and the fit will follow neither sheet well";
    warn(text.str());
  }
}

PreparedMesh prepareMesh(const std::string& mesh_path, bool fix_winding, const FitSettings& settings,
                         const MeshAdjustFn& adjust = {}) {
  PreparedMesh prepared;
  prepared.mesh_M = loadSolidMesh(mesh_path, SolidMeshOptions{fix_winding});
  if (adjust) adjust(prepared.mesh_M);
  warnAboutShape(prepared.mesh_M, mesh_path, printMeshWarning);
  const Eigen::AlignedBox3d box(prepared.mesh_M.vertices_mm.rowwise().minCoeff(),
                                prepared.mesh_M.vertices_mm.rowwise().maxCoeff());
  prepared.offset_mm = box.center();
  prepared.mesh_M.vertices_mm.colwise() -= prepared.offset_mm;
  const double extent_mm = box.sizes().maxCoeff();
  if (extent_mm < kMinCellsAcrossMesh * settings.surface_cell_mm) {
    std::ostringstream text;
    text << mesh_path << ": the mesh spans " << extent_mm << " mm, less than " << kMinCellsAcrossMesh
         << " cells of the extracted surface (cell " << settings.surface_cell_mm
         << " mm): the fit could not be measured; scale the fit options to the mesh (cell, clamp, normal "
            "offset, shapes; scripts/fit_table.sh fits a 1 mm tetrahedron so) or check its units";
    throw MeshError(text.str());
  }
  // The fit is measured on a surface extracted over the padded box: refuse a cell too fine for
  // that before the fit rather than after it.
  try {
    checkIsoSurfaceGrid(calcPaddedBox(prepared.mesh_M, settings.padding_fraction), settings.surface_cell_mm);
  } catch (const std::invalid_argument& e) {
    throw MeshError(mesh_path + ": " + e.what());
  }
  prepared.hash = hashFile(mesh_path);
  prepared.components = countComponents(prepared.mesh_M);
  return prepared;
}

MeshFit fitPrepared(const PreparedMesh& prepared, const std::string& mesh_path,
                    const FitSettings& settings, const FitProgressFn& progress) {
  const auto start = std::chrono::steady_clock::now();
  const MeshDistance distance(prepared.mesh_M);
  const WindingNumber winding(prepared.mesh_M);
  const SampleSet samples = buildSamples(prepared.mesh_M, distance, winding, settings);
  const FindNearCrumbsFn find_near_crumbs = [&](const GaussianField& field) {
    ExtraSamples found;
    found.points_mm = findNearCrumbs(field, samples.box_mm, settings.surface_cell_mm, settings.crumb_margin_mm);
    found.signed_distance_mm = calcSolidSignedDistances(distance, winding, found.points_mm);
    return found;
  };
  GreedyFitResult fit = fitGreedy(samples, settings, progress, find_near_crumbs);
  MeshFit result;
  result.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  result.rounds = fit.rounds;
  result.stop_reason = fit.stop_reason;
  result.final_refit = fit.final_refit;
  result.check_samples_added = fit.check_samples_added;
  result.near_crumb_samples_added = fit.near_crumb_samples_added;
  result.near_crumbs_left = fit.near_crumbs_left;
  result.resigned_samples = samples.resigned_samples;
  result.metrics = measureFit(fit.field, distance, samples.box_mm, settings);
  if (result.metrics.surface_M.countTriangles() == 0 || !(result.metrics.surface_volume_mm3 > 0)) {
    std::ostringstream text;
    text << mesh_path << ": the fit failed: its surface f = 0 is empty (Jaccard " << result.metrics.jaccard
         << ", mesh volume " << result.metrics.mesh_volume_mm3 << " mm^3, " << fit.field.getNumCentres()
         << " centres); the fit options (shapes, clamp, cell) do not suit a mesh of this size";
    throw MeshError(text.str());
  }
  result.mesh_components = prepared.components;
  result.warnings = describeSuspectFit(result.metrics, prepared.components, mesh_path);
  if (fit.near_crumbs_left > 0 && result.warnings.empty())  // a surface in pieces has them as its pieces
    result.warnings.push_back(mesh_path + ": the fitted field keeps " + std::to_string(fit.near_crumbs_left) +
                              " bumps apart from its surface that come within " + io::formatNumber(settings.crumb_margin_mm) +
                              " of f = 0 (crumb margin): a motion that raises f there makes islands (more centres help)");
  result.surface.field = std::move(fit.field);
  result.surface.frame_offset_mm = prepared.offset_mm;
  result.surface.source_mesh = getFileName(mesh_path);
  result.surface.source_hash = prepared.hash;
  result.surface.settings = describeSettings(settings);
  result.surface.metrics_json =
      formatMetricsJson(result.metrics, result.surface.field.getNumCentres(), result.seconds);
  return result;
}

}  // namespace

std::vector<std::string> describeSuspectFit(const FitMetrics& m, int mesh_components, const std::string& mesh_path) {
  const bool pieces = m.components > std::max(mesh_components, 1);
  const bool clipped = m.clipped_nodes > 0;
  if (!pieces && !clipped) return {};
  std::ostringstream text;
  text.precision(3);
  text << mesh_path << ": the fitted surface ";
  if (pieces)
    text << "comes out in " << m.components << " pieces where the mesh has " << mesh_components;
  if (pieces && clipped) text << " and ";
  if (clipped) text << "runs into the fitting box (" << m.clipped_nodes << " grid nodes inside on its faces)";
  text << ": Jaccard " << m.jaccard << ", mean / p95 / max distance " << m.mean_distance_mm << " / "
       << m.p95_distance_mm << " / " << m.max_distance_mm << " mm, volume ratio " << m.volume_ratio
       << "; this surface is not the mesh's shape (check the mesh for folds and slivers, the centre"
          " budget and the shapes)";
  return {text.str()};
}

MeshFit fitMeshFile(const std::string& mesh_path, const FitSettings& settings, bool fix_winding,
                    const FitProgressFn& progress, const MeshAdjustFn& adjust) {
  return fitPrepared(prepareMesh(mesh_path, fix_winding, settings, adjust), mesh_path, settings, progress);
}

MeshFit fitMeshFileGlobalShape(const std::string& mesh_path, FitSettings settings, bool fix_winding,
                               double alpha_lo, double alpha_hi, int evaluations,
                               const std::function<void(double, double)>& report, const MeshAdjustFn& adjust) {
  if (!(alpha_lo > 0 && alpha_hi > alpha_lo))
    throw std::invalid_argument("global shape search needs 0 < alpha_lo < alpha_hi");
  const PreparedMesh prepared = prepareMesh(mesh_path, fix_winding, settings, adjust);
  auto fitAt = [&](double log_alpha) {
    settings.global_shape_per_mm2 = std::exp(log_alpha);
    MeshFit fit = fitPrepared(prepared, mesh_path, settings, {});
    if (report) report(settings.global_shape_per_mm2, fit.metrics.metric);
    return fit;
  };
  // Golden-section search on log α: C_m is unimodal enough in α for the
  // bracket to close on the best shape; each evaluation is one full fit.
  const double ratio = (std::sqrt(5.0) - 1.0) / 2.0;
  double a = std::log(alpha_lo), b = std::log(alpha_hi);
  double c = b - ratio * (b - a), d = a + ratio * (b - a);
  MeshFit fit_c = fitAt(c), fit_d = fitAt(d);
  for (int used = 2; used < evaluations; ++used) {
    if (fit_c.metrics.metric <= fit_d.metrics.metric) {
      b = d;
      d = c;
      fit_d = std::move(fit_c);
      c = b - ratio * (b - a);
      fit_c = fitAt(c);
    } else {
      a = c;
      c = d;
      fit_c = std::move(fit_d);
      d = a + ratio * (b - a);
      fit_d = fitAt(d);
    }
  }
  return fit_c.metrics.metric <= fit_d.metrics.metric ? std::move(fit_c) : std::move(fit_d);
}

}  // namespace rbfmuscle
