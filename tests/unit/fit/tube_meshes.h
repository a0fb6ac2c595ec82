// SPDX-License-Identifier: Apache-2.0
#pragma once
/// Closed tubes for the fit tests: a straight capsule and tubes bent along an arc, with
/// hemispherical caps, wound outward.
#include <Eigen/Geometry>

#include <cmath>
#include <vector>

#include "geometry/mesh_measures.h"
#include "geometry/triangle_mesh.h"

namespace rbfmuscle::test {

/// A tube of `radius_mm` swept along the centreline `points_mm` (≥ 2 points, no sharp
/// turns), `around` vertices per ring, closed by hemispherical caps of `cap_rings` rings.
inline TriangleMesh makeSweptTube(const std::vector<Eigen::Vector3d>& points_mm, double radius_mm,
                                  int around = 32, int cap_rings = 8) {
  const int m = static_cast<int>(points_mm.size());
  std::vector<Eigen::Vector3d> tangents(m);
  for (int i = 0; i < m; ++i)
    tangents[i] = (points_mm[std::min(i + 1, m - 1)] - points_mm[std::max(i - 1, 0)]).normalized();
  // Parallel transport of a normal along the centreline.
  std::vector<Eigen::Vector3d> normals(m);
  normals[0] = tangents[0].unitOrthogonal();
  for (int i = 1; i < m; ++i) {
    const Eigen::Vector3d n = normals[i - 1] - normals[i - 1].dot(tangents[i]) * tangents[i];
    normals[i] = n.normalized();
  }
  std::vector<Eigen::Vector3d> vertices;
  auto addRing = [&](const Eigen::Vector3d& centre, const Eigen::Vector3d& t, const Eigen::Vector3d& n, double r) {
    const Eigen::Vector3d b = t.cross(n);
    for (int k = 0; k < around; ++k) {
      const double a = 2.0 * M_PI * k / around;
      vertices.push_back(centre + r * (std::cos(a) * n + std::sin(a) * b));
    }
  };
  // Start cap (from near the pole to the first body ring), body, end cap.
  for (int c = cap_rings - 1; c >= 1; --c) {
    const double phi = 0.5 * M_PI * c / cap_rings;
    addRing(points_mm[0] - radius_mm * std::sin(phi) * tangents[0], tangents[0], normals[0], radius_mm * std::cos(phi));
  }
  for (int i = 0; i < m; ++i) addRing(points_mm[i], tangents[i], normals[i], radius_mm);
  for (int c = 1; c < cap_rings; ++c) {
    const double phi = 0.5 * M_PI * c / cap_rings;
    addRing(points_mm[m - 1] + radius_mm * std::sin(phi) * tangents[m - 1], tangents[m - 1], normals[m - 1],
            radius_mm * std::cos(phi));
  }
  const int rings = static_cast<int>(vertices.size()) / around;
  const int pole_start = static_cast<int>(vertices.size());
  vertices.push_back(points_mm[0] - radius_mm * tangents[0]);
  const int pole_end = static_cast<int>(vertices.size());
  vertices.push_back(points_mm[m - 1] + radius_mm * tangents[m - 1]);

  std::vector<Eigen::Vector3i> triangles;
  for (int r = 0; r + 1 < rings; ++r)
    for (int k = 0; k < around; ++k) {
      const int a = r * around + k, b = r * around + (k + 1) % around;
      const int c = a + around, d = b + around;
      triangles.emplace_back(a, b, d);
      triangles.emplace_back(a, d, c);
    }
  for (int k = 0; k < around; ++k) {
    triangles.emplace_back(pole_start, (k + 1) % around, k);
    const int last = (rings - 1) * around;
    triangles.emplace_back(pole_end, last + k, last + (k + 1) % around);
  }
  TriangleMesh mesh;
  mesh.vertices_mm.resize(3, static_cast<Eigen::Index>(vertices.size()));
  for (std::size_t v = 0; v < vertices.size(); ++v) mesh.vertices_mm.col(static_cast<Eigen::Index>(v)) = vertices[v];
  mesh.triangles.resize(3, static_cast<Eigen::Index>(triangles.size()));
  for (std::size_t t = 0; t < triangles.size(); ++t) mesh.triangles.col(static_cast<Eigen::Index>(t)) = triangles[t];
  if (calcVolume(mesh) < 0)  // wind outward
    for (Eigen::Index t = 0; t < mesh.triangles.cols(); ++t) std::swap(mesh.triangles(1, t), mesh.triangles(2, t));
  return mesh;
}

/// A straight capsule along z: cylinder `length_mm` long between the cap centres.
inline TriangleMesh makeCapsule(double length_mm, double radius_mm) {
  std::vector<Eigen::Vector3d> points;
  const int steps = static_cast<int>(std::ceil(length_mm / 2.0));
  for (int i = 0; i <= steps; ++i) points.emplace_back(0.0, 0.0, -0.5 * length_mm + length_mm * i / steps);
  return makeSweptTube(points, radius_mm);
}

/// A tube bent along an arc of `bend_radius_mm` through `angle_rad` in the xy plane.
inline TriangleMesh makeBentTube(double bend_radius_mm, double angle_rad, double radius_mm) {
  std::vector<Eigen::Vector3d> points;
  const int steps = static_cast<int>(std::ceil(bend_radius_mm * angle_rad / 2.0));
  for (int i = 0; i <= steps; ++i) {
    const double a = angle_rad * i / steps;
    points.emplace_back(bend_radius_mm * std::cos(a), bend_radius_mm * std::sin(a), 0.0);
  }
  return makeSweptTube(points, radius_mm);
}

}  // namespace rbfmuscle::test
