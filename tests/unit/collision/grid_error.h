// SPDX-License-Identifier: Apache-2.0
#pragma once
/// Points near a mesh surface and the error of a BoneDistanceGrid against MeshDistance there;
/// shared by the grid's tests and its benchmark.
#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include "collision/bone_distance_grid.h"
#include "geometry/mesh_distance.h"

namespace rbfmuscle::test {

/// `n` points (mm) within ±`max_offset_mm` of the surface of `mesh`: a uniformly random
/// point of the surface (triangle by area, then uniform in it) moved along its triangle's
/// normal by a uniform offset in [−max_offset_mm, max_offset_mm]. Fixed `seed`.
inline Eigen::Matrix3Xd sampleNearSurface(const TriangleMesh& mesh, int n, double max_offset_mm, unsigned seed) {
  std::vector<double> area_sum(std::size_t(mesh.countTriangles()));
  double total = 0;
  for (int t = 0; t < mesh.countTriangles(); ++t) {
    total += 0.5 * (mesh.getCorner(t, 1) - mesh.getCorner(t, 0)).cross(mesh.getCorner(t, 2) - mesh.getCorner(t, 0)).norm();
    area_sum[std::size_t(t)] = total;
  }
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> unit(0.0, 1.0), offset(-max_offset_mm, max_offset_mm);
  Eigen::Matrix3Xd points(3, n);
  for (int i = 0; i < n; ++i) {
    const double pick = unit(rng) * total;
    const int t = int(std::min<std::ptrdiff_t>(std::lower_bound(area_sum.begin(), area_sum.end(), pick) - area_sum.begin(),
                                               mesh.countTriangles() - 1));
    double a = unit(rng), b = unit(rng);
    if (a + b > 1) a = 1 - a, b = 1 - b;
    const Eigen::Vector3d v0 = mesh.getCorner(t, 0), e1 = mesh.getCorner(t, 1) - v0, e2 = mesh.getCorner(t, 2) - v0;
    points.col(i) = v0 + a * e1 + b * e2 + offset(rng) * e1.cross(e2).normalized();
  }
  return points;
}

/// |value − s| (mm) of a grid against the exact s at some points, and the sign failures.
struct GridError {
  double mean_mm = 0, p99_mm = 0, max_mm = 0;
  double max_at_surface_mm = 0;  ///< largest error where |s| ≤ 0.5 mm (near the zero set).
  int not_near = 0;        ///< points answered as far.
  int wrong_sign = 0;      ///< points with |s| > the sign margin where value and s have opposite signs.
};

/// The error of `grid` at the columns of `points_mm` against its own MeshDistance; signs
/// are compared where |s| > `sign_margin_mm` (closer, the sign follows from the error).
inline GridError measureGridError(const BoneDistanceGrid& grid, const Eigen::Matrix3Xd& points_mm,
                                  double sign_margin_mm = 0.0) {
  std::vector<double> errors;
  GridError out;
  for (Eigen::Index i = 0; i < points_mm.cols(); ++i) {
    const BoneDistanceSample sample = grid.sample(points_mm.col(i));
    const double exact = grid.getMeshDistance().findSignedClosestPoint(points_mm.col(i)).signed_distance_mm;
    if (!sample.near) ++out.not_near;
    if (std::abs(exact) > sign_margin_mm && sample.value_mm * exact <= 0) ++out.wrong_sign;
    errors.push_back(std::abs(sample.value_mm - exact));
    if (std::abs(exact) <= 0.5) out.max_at_surface_mm = std::max(out.max_at_surface_mm, errors.back());
  }
  if (errors.empty()) return out;
  for (double e : errors) out.mean_mm += e / double(errors.size());
  std::sort(errors.begin(), errors.end());
  out.max_mm = errors.back();
  out.p99_mm = errors[std::min(errors.size() - 1, std::size_t(0.99 * double(errors.size())))];
  return out;
}

}  // namespace rbfmuscle::test
