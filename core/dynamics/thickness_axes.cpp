// SPDX-License-Identifier: Apache-2.0
#include "dynamics/thickness_axes.h"

#include "geometry/winding_number.h"

#include <cmath>
#include <stdexcept>
#include <string>

namespace rbfmuscle {

namespace {

/// Inward unit normal of triangle t.
Eigen::Vector3d inwardNormal(const TriangleMesh& mesh, int t) {
  const Eigen::Vector3d a = mesh.vertices_mm.col(mesh.triangles(0, t));
  const Eigen::Vector3d b = mesh.vertices_mm.col(mesh.triangles(1, t));
  const Eigen::Vector3d c = mesh.vertices_mm.col(mesh.triangles(2, t));
  return -(b - a).cross(c - a).normalized();
}

}  // namespace

ThicknessAxes calcThicknessAxes(const MeshDistance& muscle_surface, const Eigen::Matrix3Xd& points_mm) {
  const TriangleMesh& mesh = muscle_surface.getMesh();
  // Inside by the winding number: a fold of a segmented mesh turns the pseudo-normal's sign over
  // in a whole cone behind it (three folds of the psoas major do).
  const WindingNumber winding(mesh);
  const double max_chord_mm = (mesh.vertices_mm.rowwise().maxCoeff() - mesh.vertices_mm.rowwise().minCoeff()).norm();
  ThicknessAxes result;
  result.axes.resize(3, points_mm.cols());
  result.offsets_mm.resize(points_mm.cols());
  result.half_chords_mm.resize(points_mm.cols());
  for (Eigen::Index j = 0; j < points_mm.cols(); ++j)
    if (!points_mm.col(j).allFinite())
      throw std::invalid_argument("calcThicknessAxes: point " + std::to_string(j) + " is not finite");
#pragma omp parallel for schedule(dynamic, 16)
  for (Eigen::Index j = 0; j < points_mm.cols(); ++j) {
    const Eigen::Vector3d x = points_mm.col(j);
    const ClosestPoint q = muscle_surface.findClosestPoint(x);
    Eigen::Vector3d n = winding.isInside(x) ? Eigen::Vector3d(x - q.point_mm) : Eigen::Vector3d(q.point_mm - x);
    n = n.norm() > 1e-9 ? Eigen::Vector3d(n.normalized()) : inwardNormal(mesh, q.triangle);
    // March from q along n until the ray leaves the muscle, then bisect the exit.
    double inside = 0.0, outside = 1.0;
    while (outside < max_chord_mm && winding.isInside(q.point_mm + outside * n)) {
      inside = outside;
      outside += 1.0;
    }
    for (int i = 0; i < 7; ++i) {  // 1 mm / 2⁷ < 0.01 mm
      const double mid = 0.5 * (inside + outside);
      (winding.isInside(q.point_mm + mid * n) ? inside : outside) = mid;
    }
    const double half_chord = 0.25 * (inside + outside);
    const Eigen::Vector3d m = q.point_mm + half_chord * n;
    result.axes.col(j) = n;
    result.offsets_mm[j] = (x - m).dot(n);
    result.half_chords_mm[j] = half_chord;
  }
  return result;
}

}  // namespace rbfmuscle
