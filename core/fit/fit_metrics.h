// SPDX-License-Identifier: Apache-2.0
#pragma once
/// @file
/// How good a fitted surface is: the dissertation's metric (Jaccard index and
/// MSE) and symmetric surface distances between the input mesh and f = 0.
#include <cstdint>
#include <string>

#include "fit/fit_settings.h"
#include "geometry/triangle_mesh.h"
#include "rbf/gaussian_field.h"

namespace rbfmuscle {

class MeshDistance;

/// Figures of one fit. Distances in mm, volumes in mm³.
struct FitMetrics {
  double jaccard = 0.0;           ///< |inside mesh ∩ f > 0| / |inside mesh ∪ f > 0| over metric points
  double mse = 0.0;               ///< mean (t − f)² over metric points (mm²)
  double mse_max = 0.0;           ///< the same for the empty field f ≡ b (normaliser)
  double metric = 0.0;            ///< C_m = (1−σ)(1−Jaccard) + σ·MSE/MSE_max
  int metric_points = 0;
  double mean_distance_mm = 0.0;  ///< mean over both vertex sets of the distance to the other surface
  double p95_distance_mm = 0.0;
  double max_distance_mm = 0.0;
  double mesh_volume_mm3 = 0.0;
  double surface_volume_mm3 = 0.0;
  double volume_ratio = 0.0;      ///< fitted / original volume
  int components = 0;             ///< connected components of the extracted surface
  int boundary_edges = 0;         ///< 0 for a closed surface without holes
  std::int64_t clipped_nodes = 0;   ///< grid nodes on the box faces where f > 0 (surface cut by the box)
  TriangleMesh surface_M;         ///< extracted f = 0 in the muscle frame M
};

/// Extracts f = 0 on a grid of `settings.surface_cell_mm` over `box_mm` (which
/// must leave f < 0 on its faces) and measures it against `mesh_M`.
FitMetrics measureFit(const GaussianField& field, const MeshDistance& mesh_distance,
                      const Eigen::AlignedBox3d& box_mm, const FitSettings& settings);

/// The figures as one JSON object (no surface), for the `fit` command's last line.
std::string formatMetricsJson(const FitMetrics& metrics, int centres, double seconds);

}  // namespace rbfmuscle
