// SPDX-License-Identifier: Apache-2.0
#pragma once
/// @file
/// Distance from points to a triangle mesh, unsigned and signed, through a bounding-volume
/// tree built once.
#include <array>
#include <limits>
#include <vector>

#include "geometry/mesh_error.h"
#include "geometry/triangle_mesh.h"

namespace rbfmuscle {

/// Result of a closest-point query.
struct ClosestPoint {
  Eigen::Vector3d point_mm = Eigen::Vector3d::Zero();  ///< closest point q on the mesh (mm).
  int triangle = -1;        ///< index of the triangle holding q.
  double distance_mm = 0;   ///< ‖p − q‖ (mm).
};

/// Result of a signed closest-point query.
struct SignedClosestPoint : ClosestPoint {
  double signed_distance_mm = 0;  ///< s(p) = ±‖p − q‖ (mm), negative inside.
};

/// Distance queries against one triangle mesh (mm). Built once in O(T log T): an
/// axis-aligned bounding-box tree over the triangles (median split on the longest axis,
/// ≤ 4 triangles per leaf) and the angle-weighted pseudo-normals of faces, edges and
/// vertices (Bærentzen & Aanæs 2005, "Signed distance computation using the angle weighted
/// pseudonormal"). A query descends the tree nearest box first and prunes boxes farther
/// than the best distance so far: O(log T) typically.
///
/// Signed distance s(p) = ±‖p − q‖ with q the closest point: negative inside, positive
/// outside. The sign is that of (p − q) · n, where n is the pseudo-normal
/// of the feature holding q — the face normal when q is inside a face, the sum of the two
/// face normals for an edge, Σ αᵢ nᵢ (αᵢ = incident angle) for a vertex — which is exact for
/// a closed, manifold mesh wound outward (validateMesh). For other meshes the sign is
/// only a guess.
/// Immutable after construction: queries are thread-safe; batch queries use OpenMP and
/// give the same results for any number of threads.
class MeshDistance {
 public:
  /// Builds the tree and, with `signs` (default), the pseudo-normals for `mesh` (copied).
  /// Without them (about half the build time) only the unsigned queries may be used.
  /// @throws MeshError if the mesh has no triangles or a non-finite vertex.
  explicit MeshDistance(TriangleMesh mesh, bool signs = true);

  /// The mesh queried (mm).
  const TriangleMesh& getMesh() const { return mesh_; }

  /// Closest point on the mesh to p_mm.
  ClosestPoint findClosestPoint(const Eigen::Vector3d& p_mm) const;
  /// Closest point and s(p) from one descent of the tree (the sign from the pseudo-normal of
  /// the feature holding the closest point, as calcSignedDistance), searched only within
  /// `max_distance_mm` of p: triangle −1 (and distances +∞) when the mesh is farther, which
  /// prunes most of the tree for far points.
  SignedClosestPoint findSignedClosestPoint(const Eigen::Vector3d& p_mm,
                                            double max_distance_mm = std::numeric_limits<double>::infinity()) const;
  /// ‖p − q‖ (mm), q the closest point.
  double calcUnsignedDistance(const Eigen::Vector3d& p_mm) const;
  /// ‖p − q‖ (mm) if at most `max_distance_mm`, else +∞ (a search pruned to that distance).
  double calcUnsignedDistanceWithin(const Eigen::Vector3d& p_mm, double max_distance_mm) const;
  /// s(p) (mm): negative inside, positive outside, 0 on the surface.
  double calcSignedDistance(const Eigen::Vector3d& p_mm) const;
  /// s(p) < 0.
  bool isInside(const Eigen::Vector3d& p_mm) const;

  /// calcUnsignedDistance for each column of the 3×N `points_mm`; N values (mm).
  Eigen::VectorXd calcUnsignedDistances(const Eigen::Matrix3Xd& points_mm) const;
  /// calcSignedDistance for each column of the 3×N `points_mm`; N values (mm).
  Eigen::VectorXd calcSignedDistances(const Eigen::Matrix3Xd& points_mm) const;
  /// isInside for each column of the 3×N `points_mm`.
  Eigen::Array<bool, Eigen::Dynamic, 1> calcInside(const Eigen::Matrix3Xd& points_mm) const;

 private:
  /// Where on a triangle the closest point lies: 0 face, 1–3 edge c−1 (corners c−1, c mod 3),
  /// 4–6 vertex c−4.
  struct Hit {
    Eigen::Vector3d point;
    double distance_sq;
    int triangle;
    int feature;
  };
  struct Node {
    Eigen::AlignedBox3d box;
    int first = 0;  ///< leaf: first slot in order_.
    int count = 0;  ///< leaf: number of triangles; 0 for an inner node.
    int left = -1, right = -1;  ///< inner node: children.
  };

  int buildNode(int begin, int end, std::vector<Eigen::Vector3d>& centroids);
  /// Closest feature within sqrt(max_distance_sq) of p (triangle −1 when none).
  Hit findHit(const Eigen::Vector3d& p, double max_distance_sq = std::numeric_limits<double>::infinity()) const;
  double signOf(const Eigen::Vector3d& p, const Hit& hit) const;

  /// Throws unless the pseudo-normals were built (signed queries).
  void requireSigns() const;

  TriangleMesh mesh_;
  bool signs_ = true;
  std::vector<int> order_;                 ///< triangle index of each tree slot.
  std::vector<std::array<Eigen::Vector3d, 3>> corners_;  ///< corners per slot (cache-friendly).
  std::vector<Node> nodes_;                ///< nodes_[0] is the root.
  Eigen::Matrix3Xd face_normals_;          ///< unit normal per triangle (0 if degenerate).
  std::vector<Eigen::Vector3d> edge_normals_;    ///< pseudo-normal per undirected edge.
  Eigen::Matrix3Xi triangle_edges_;        ///< edge id of edge c of triangle t.
  Eigen::Matrix3Xd vertex_normals_;        ///< angle-weighted pseudo-normal per vertex.
};

}  // namespace rbfmuscle
