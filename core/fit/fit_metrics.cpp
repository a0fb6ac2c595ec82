// SPDX-License-Identifier: Apache-2.0
#include "fit/fit_metrics.h"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "fit/halton.h"
#include "fit/sample_set.h"
#include "geometry/iso_surface.h"
#include "geometry/mesh_check.h"
#include "geometry/mesh_distance.h"
#include "geometry/mesh_measures.h"
#include "geometry/winding_number.h"

namespace rbfmuscle {
namespace {

/// Metric points use a stretch of the Halton sequence far from the one the
/// fitting samples use, so the fit is not scored on its own samples.
constexpr std::uint64_t kMetricHaltonStart = 10'000'000;

double calcPercentile(std::vector<double> values, double fraction) {
  if (values.empty()) return 0.0;
  const std::size_t k = std::min(values.size() - 1, static_cast<std::size_t>(fraction * values.size()));
  std::nth_element(values.begin(), values.begin() + k, values.end());
  return values[k];
}

}  // namespace

FitMetrics measureFit(const GaussianField& field, const MeshDistance& mesh_distance,
                      const Eigen::AlignedBox3d& box_mm, const FitSettings& settings) {
  FitMetrics m;
  const Eigen::Matrix3Xd points = makeHaltonPoints(box_mm, settings.metric_points, kMetricHaltonStart);
  const Eigen::VectorXd s =
      calcSolidSignedDistances(mesh_distance, WindingNumber(mesh_distance.getMesh()), points);
  Eigen::VectorXd f;
  field.calcValues(points, f);
  const double tau = settings.clamp_mm;
  long long both = 0, either = 0;
  double sq = 0.0, sq_empty = 0.0;
  for (Eigen::Index i = 0; i < points.cols(); ++i) {
    const bool in_mesh = s[i] < 0, in_field = f[i] > 0;
    both += in_mesh && in_field;
    either += in_mesh || in_field;
    const double t = std::clamp(-s[i], -tau, tau);
    sq += (t - f[i]) * (t - f[i]);
    sq_empty += (t + tau) * (t + tau);
  }
  m.metric_points = static_cast<int>(points.cols());
  m.jaccard = either ? static_cast<double>(both) / static_cast<double>(either) : 1.0;
  m.mse = sq / static_cast<double>(points.cols());
  m.mse_max = sq_empty / static_cast<double>(points.cols());
  m.metric = (1.0 - settings.metric_sigma) * (1.0 - m.jaccard) +
             settings.metric_sigma * (m.mse_max > 0 ? m.mse / m.mse_max : 0.0);

  m.surface_M = extractIsoSurface(
      [&field](const Eigen::Matrix3Xd& p, Eigen::VectorXd& values) { field.calcValues(p, values); },
      box_mm, settings.surface_cell_mm, &m.clipped_nodes);
  m.mesh_volume_mm3 = calcVolume(mesh_distance.getMesh());
  if (m.surface_M.triangles.cols() == 0) {
    m.mean_distance_mm = m.p95_distance_mm = m.max_distance_mm = std::numeric_limits<double>::infinity();
    return m;
  }
  m.surface_volume_mm3 = calcVolume(m.surface_M);
  m.volume_ratio = m.surface_volume_mm3 / m.mesh_volume_mm3;
  const MeshReport report = checkMesh(m.surface_M);
  m.components = report.components;
  m.boundary_edges = report.boundary_edges;

  const MeshDistance surface_distance(m.surface_M);
  const Eigen::VectorXd to_mesh = mesh_distance.calcUnsignedDistances(m.surface_M.vertices_mm);
  const Eigen::VectorXd to_surface = surface_distance.calcUnsignedDistances(mesh_distance.getMesh().vertices_mm);
  std::vector<double> all(to_mesh.data(), to_mesh.data() + to_mesh.size());
  all.insert(all.end(), to_surface.data(), to_surface.data() + to_surface.size());
  double sum = 0.0;
  for (double d : all) sum += d;
  m.mean_distance_mm = sum / static_cast<double>(all.size());
  m.p95_distance_mm = calcPercentile(all, 0.95);
  m.max_distance_mm = *std::max_element(all.begin(), all.end());
  return m;
}

std::string formatMetricsJson(const FitMetrics& m, int centres, double seconds) {
  std::ostringstream out;
  out.precision(6);
  bool first = true;
  // JSON has no NaN or infinity: a figure that could not be measured is null.
  auto field = [&](const char* key, double value) {
    out << (first ? "{" : ", ") << '"' << key << "\": ";
    first = false;
    if (std::isfinite(value)) out << value; else out << "null";
  };
  field("jaccard", m.jaccard);
  field("mean_distance_mm", m.mean_distance_mm);
  field("p95_distance_mm", m.p95_distance_mm);
  field("max_distance_mm", m.max_distance_mm);
  field("volume_ratio", m.volume_ratio);
  field("centres", centres);
  field("seconds", seconds);
  field("metric", m.metric);
  field("mse_mm2", m.mse);
  field("components", m.components);
  field("boundary_edges", m.boundary_edges);
  field("clipped_nodes", static_cast<double>(m.clipped_nodes));
  field("mesh_volume_mm3", m.mesh_volume_mm3);
  field("surface_volume_mm3", m.surface_volume_mm3);
  field("metric_points", m.metric_points);
  out << "}";
  return out.str();
}

}  // namespace rbfmuscle
