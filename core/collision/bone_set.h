// SPDX-License-Identifier: Apache-2.0
#pragma once
/// @file
/// Rigid bones for contact queries: bounding-volume hierarchies built once in each bone's
/// body frame, moved every frame by transforms only, queried with batches of probe points.
#include <memory>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "collision/collision_error.h"
#include "collision/contact_query_result.h"
#include "geometry/triangle_mesh.h"

namespace rbfmuscle {

/// Work counters of the last BoneSet::queryProbes call (for benchmarks and tests).
struct ProbeQueryStats {
  int bones_culled_by_box = 0;  ///< bones whose world AABB, inflated by r, misses the probes' AABB.
  int bones_culled_by_fcl = 0;  ///< bones culled by the FCL probe-cloud sphere test.
  long long pairs_culled_by_box = 0;  ///< (probe, bone) pairs culled by the body-frame box test.
  long long exact_queries = 0;        ///< (probe, bone) pairs given an exact closest-point query.
};

/// A set of rigid, closed bone surfaces (mm) and signed-distance queries of probe points
/// against them.
///
/// Built once per bone (addBone), in its body frame B: an FCL `BVHModel<OBBRSS>` (for the
/// world bounding box and the broad phase) and a MeshDistance (AABB tree + angle-weighted
/// pseudo-normals, for exact closest points and a sign that is exact for closed, outward
/// wound meshes). Per frame, setBoneTransforms only sets X_WB on the FCL objects and
/// recomputes their world AABBs; nothing is rebuilt.
///
/// queryProbes, for probes p_W and a query radius r (mm), culls in three stages
/// (each exact, i.e. never changes an answer):
///  1. bone world AABB (FCL computeAABB) inflated by r vs the AABB of all probes;
///  2. FCL collide of the probes' bounding sphere, inflated by r, vs the bone's BVH: no
///     contact means no bone surface point within r of any probe, and all probes lie on
///     the same side of the surface as the sphere's centre, so the bone is culled when
///     that centre is outside the bone;
///  3. per probe, the exterior distance δ from p_B = X_BW p_W to the bone's body-frame box
///     bounds s_b(p) ≥ δ, so the bone is skipped when δ > r or δ ≥ the best s so far.
/// Survivors get the exact signed distance in the body frame, from one descent of the
/// distance tree pruned at r (a point with no surface within r is outside unless it lies in
/// the bone's box, where it may be deeper inside than r: only then is the whole tree
/// searched). Results are mapped back to W.
///
/// Not thread-safe for concurrent calls (queries reuse internal buffers); each call runs
/// its probes in parallel (OpenMP) with results independent of the thread count.
class BoneSet {
 public:
  BoneSet();
  ~BoneSet();
  BoneSet(BoneSet&&) noexcept;
  BoneSet& operator=(BoneSet&&) noexcept;
  BoneSet(const BoneSet&) = delete;
  BoneSet& operator=(const BoneSet&) = delete;

  /// Adds a bone with surface `mesh_B` (body frame B, mm; closed, wound outward) and builds
  /// its BVH and distance tree once. Its transform starts as the identity.
  /// @return the bone's index (0, 1, ... in order of addition).
  /// @throws CollisionError naming the bone when the name is empty or taken, the mesh has
  ///         no triangles or a non-finite vertex or a bad index, or FCL's build fails.
  int addBone(const std::string& name, TriangleMesh mesh_B);

  /// Number of bones.
  int countBones() const;
  /// Name of bone `bone`. @throws CollisionError if the index is out of range.
  const std::string& getBoneName(int bone) const;
  /// Surface of bone `bone` in its body frame (mm).
  const TriangleMesh& getBoneMesh(int bone) const;
  /// Number of BVHs built since construction: equals countBones(), as transforms never
  /// rebuild.
  int countBvhBuilds() const;

  /// Sets every bone's pose X_WB (body frame B in world W, translation in mm), one per bone
  /// in index order; updates the FCL objects' transforms and world AABBs only.
  /// @throws CollisionError if the count differs from countBones() or a pose is not finite.
  void setBoneTransforms(const std::vector<Eigen::Isometry3d>& X_WB);
  /// Current pose X_WB of bone `bone`.
  const Eigen::Isometry3d& getBoneTransform(int bone) const;
  /// World-frame AABB of bone `bone` at its current pose, as FCL computes it (mm).
  Eigen::AlignedBox3d getBoneWorldBox(int bone) const;

  /// Enables (default) or disables all three culling stages; answers are identical either
  /// way, only the work differs (for tests and measurements).
  void setBroadPhaseEnabled(bool enabled);
  /// Whether culling is on.
  bool isBroadPhaseEnabled() const;

  /// For each column p of the 3×P `p_W` (world frame, mm), the nearest bone by signed
  /// distance among those with s_b(p) ≤ `query_radius_mm` (see ContactQueryResult).
  /// `out` is resized to P (no allocation when its capacity suffices).
  /// @throws CollisionError if the radius is negative or NaN, or a probe is not finite.
  void queryProbes(const Eigen::Matrix3Xd& p_W, double query_radius_mm,
                   std::vector<ContactQueryResult>& out);

  /// Work counters of the last queryProbes call.
  const ProbeQueryStats& getLastQueryStats() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace rbfmuscle
