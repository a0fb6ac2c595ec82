#pragma once
/// @file
/// The bones' own vertices tested against a muscle's field: a bone vertex inside the muscle
/// (f > 0) marks a penetration wherever the probes on the muscle surface have drifted away
/// (ContactResolver, "Uncovered contacts").
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "geometry/triangle_mesh.h"
#include "rbf/gaussian_field.h"
#include "rbf/spatial_grid.h"

namespace rbfmuscle {

/// A watched bone vertex inside the muscle, in the muscle frame M.
struct BoneVertexInside {
  int bone = -1;                                        ///< index of the bone
  Eigen::Vector3d vertex_M = Eigen::Vector3d::Zero();   ///< the vertex (mm)
  Eigen::Vector3d inward_M = Eigen::Vector3d::Zero();   ///< unit inward normal of the bone there
  double value = 0.0;                                   ///< f at the vertex (> 0)
};

/// Per bone, vertices of its surface mesh spread at about `spacing_mm` (the first vertex of
/// each cubic cell of that edge), outside the rest muscle (f₀ ≤ 0 at the rest pose: a bone
/// that overlaps the muscle at rest, such as the pelvis proxy, keeps that overlap, as the
/// probes' allowances do), with their unit inward normals (area-weighted mean of the faces'
/// normals, negated; the mesh outward wound).
class BoneVertexWatch {
 public:
  BoneVertexWatch() = default;
  /// @param meshes_B closed, outward-wound bone surfaces in their body frames B (mm)
  /// @param X_MB_rest rest pose of each bone in M (same count)
  /// @param rest_field the muscle's rest field f₀ in M
  /// @param spacing_mm cell edge of the vertex selection (mm, > 0)
  /// @throws std::invalid_argument on different counts or a spacing that is not > 0
  BoneVertexWatch(const std::vector<TriangleMesh>& meshes_B, const std::vector<Eigen::Isometry3d>& X_MB_rest,
                  const GaussianField& rest_field, double spacing_mm);

  /// Number of bones.
  int countBones() const { return static_cast<int>(vertices_B_.size()); }

  /// Appends to `out` the watched vertices of bone b within `radius_mm` of any of `near_B`
  /// (3×n, B) that lie inside `field` (f > 0) with the bone posed by X_MB, in vertex order.
  void findInside(int b, const Eigen::Isometry3d& X_MB, const GaussianField& field, const Eigen::Ref<const Eigen::Matrix3Xd>& near_B,
                  double radius_mm, std::vector<BoneVertexInside>& out);

 private:
  std::vector<Eigen::Matrix3Xd> vertices_B_;  ///< per bone, watched vertices (mm, B)
  std::vector<Eigen::Matrix3Xd> inward_B_;    ///< per bone, their unit inward normals (B)
  std::vector<SpatialGrid> grids_B_;          ///< per bone, the watched vertices indexed
  std::vector<int> stamp_;                    ///< per vertex, the last call that tested it
  int calls_ = 0;
  std::vector<int> found_;
  Eigen::VectorXd values_;  ///< f at the tested vertices (scratch)
};

}  // namespace rbfmuscle
