// SPDX-License-Identifier: Apache-2.0
#pragma once
/// @file
/// The one mesh value type of the geometry layer: an indexed triangle mesh in mm.
#include <Eigen/Core>
#include <Eigen/Geometry>

namespace rbfmuscle {

/// Indexed triangle mesh, coordinates in millimetres (double precision).
///
/// Column v of `vertices_mm` is vertex v; column t of `triangles` holds the three
/// vertex indices of triangle t in counter-clockwise order seen from outside
/// (normal n = (v1 − v0) × (v2 − v0) points outward for a correctly wound closed mesh).
struct TriangleMesh {
  Eigen::Matrix3Xd vertices_mm;  ///< 3×V vertex positions (mm).
  Eigen::Matrix3Xi triangles;    ///< 3×T vertex indices into `vertices_mm`, 0-based.

  /// Number of vertices V.
  int countVertices() const { return static_cast<int>(vertices_mm.cols()); }
  /// Number of triangles T.
  int countTriangles() const { return static_cast<int>(triangles.cols()); }
  /// Position (mm) of corner c ∈ {0,1,2} of triangle t.
  Eigen::Vector3d getCorner(int t, int c) const { return vertices_mm.col(triangles(c, t)); }
  /// Axis-aligned bounding box of all vertices (mm); empty box when there are none.
  Eigen::AlignedBox3d calcBoundingBox() const {
    Eigen::AlignedBox3d box;  // default-constructed AlignedBox is empty
    for (Eigen::Index v = 0; v < vertices_mm.cols(); ++v) box.extend(vertices_mm.col(v));
    return box;
  }
};

}  // namespace rbfmuscle
