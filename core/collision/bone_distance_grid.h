// SPDX-License-Identifier: Apache-2.0
#pragma once
/// @file
/// Narrow-band sampled signed distance s(x) of one rigid bone surface in its body frame B:
/// exact MeshDistance values on a lattice, filled lazily brick by brick, trilinearly
/// interpolated.
#include <array>
#include <atomic>
#include <memory>
#include <mutex>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "collision/collision_error.h"
#include "geometry/triangle_mesh.h"

namespace rbfmuscle {

class MeshDistance;

/// Settings of a BoneDistanceGrid.
struct BoneDistanceGridSettings {
  double spacing_mm = 1.0;  ///< node spacing h (mm), finite and > 0.
  double band_mm = 6.0;     ///< band half-width (mm), finite and > 0: where |s| ≥ band only "far" is reported.
  int brick_cells = 8;      ///< cells per brick edge, 1..64; a brick stores (brick_cells + 1)³ nodes.
};

/// One query of a BoneDistanceGrid at p_B (see BoneDistanceGrid for what is returned where).
struct BoneDistanceSample {
  double value_mm = 0;  ///< s̃(p) (mm): the interpolated signed distance, or a bound of s when far.
  Eigen::Vector3d gradient_B = Eigen::Vector3d::Zero();  ///< ∇s̃(p) in frame B (mm/mm); zero when far.
  bool near = false;    ///< true: |value_mm| < band and value_mm is the interpolant.
};

/// Work done by a BoneDistanceGrid since construction (for tests and benchmarks).
struct BoneDistanceGridStats {
  long long brick_slots = 0;       ///< size of the brick index (one pointer each).
  long long bricks_near = 0;       ///< bricks whose nodes were evaluated and are stored.
  long long bricks_far = 0;        ///< bricks classified far from one centre query, no nodes.
  long long nodes_stored = 0;      ///< node values held: bricks_near · (brick_cells + 1)³.
  long long distance_queries = 0;  ///< MeshDistance searches made (brick centres and nodes).
};

/// Signed distance s(x) (mm; negative inside, positive outside) to a closed, outward-wound
/// triangle mesh, sampled in the mesh's own frame B on a lattice of spacing h and
/// interpolated trilinearly, near the surface only.
///
/// Layout. The brick index covers the mesh's bounding box padded by the band on each side,
/// rounded outward to whole bricks of brick_cells³ cells (the "grid box", getGridBox). A
/// brick is classified the first time a query falls in it (never before), from one exact
/// query at its centre c: if |s(c)| − r ≥ band, with r its half-diagonal, then |s| ≥ band
/// in the whole brick (s is 1-Lipschitz) and the brick is "far" (outside or inside by the
/// sign of s(c)), storing nothing. Otherwise all its (brick_cells + 1)³ nodes get the exact
/// MeshDistance::findSignedClosestPoint value (sign from the angle-weighted pseudo-normals),
/// clamped as told below.
/// Nodes on a face shared by two bricks are stored in both, with equal values; the memory
/// is one pointer per brick slot plus the near bricks' nodes, i.e. it grows with the surface
/// area near which queries fall, not with the box's volume.
///
/// What sample(p_B) returns, with t the interpolant of the 8 nodes of p's cell:
///  - p in a near brick, |t| < band: value t, gradient ∇t, near = true;
///  - p in a near brick, |t| ≥ band: value ±band (sign of t), gradient 0, near = false;
///    then |s(p)| ≥ band up to the interpolation error;
///  - p in a far brick: value +band (outside) or −band (inside), gradient 0, near = false;
///    then s(p) ≥ band, resp. s(p) ≤ −band;
///  - p outside the grid box: value band + (distance from p to the grid box), gradient 0,
///    near = false; a lower bound of s(p), as the grid box holds the mesh's box padded by
///    the band.
/// So value = clamp(t, −band, band) in the grid box, which is continuous everywhere
/// (the nodes of a far brick's faces all have |s| ≥ band with one sign), and a caller may
/// skip the bone whenever near is false. The gradient of a trilinear interpolant is
/// continuous inside a cell and jumps across cell faces, by O(h · curvature) where s is
/// smooth and by O(1) where s has a kink. No smoother scheme (e.g. tricubic) is used: it
/// would need 64 nodes a query instead of 8 and overshoots at kinks, while trilinear is
/// exact for planes and keeps the zero set (where the caller's min(f, s) cares) within the
/// errors below.
///
/// Node values are s clamped to ±(band + √3 h): a node beyond that makes every point of
/// every cell holding it have |s| > band with one sign, so those cells answer ±band either
/// way, and such nodes need only a short search (each node's search is bounded by its
/// scan-order neighbour's |s| + h, a bound that changes no result of the search). The
/// answers are bitwise those of unclamped nodes, only cheaper to fill.
///
/// Accuracy, |value − s| against MeshDistance at 100 000 points uniform on the surface and
/// moved along the normal by U(−3, 3) mm (band 6 mm, brick 8 cells;
/// benchmarks/bone_distance_grid_bench.cpp, BM_Accuracy), in mm:
///
///     mesh                          h     mean     p99     max   max where |s| ≤ 0.5
///     icosphere r 20 (5120 tri)     1    0.008   0.022   0.029   0.029
///     cube 40, tilted (12 tri)      1    0.008   0.20    0.41    0.35
///     femur_r.ply (42 456 tri)      1    0.009   0.054   0.39    0.39
///     icosphere / cube / femur     0.5   0.002 / 0.002 / 0.003  max 0.015 / 0.21 / 0.18
///     icosphere / cube / femur      2    0.033 / 0.034 / 0.029  max 0.069 / 0.82 / 0.83
///
/// Where s is smooth the error is about h²/8 · Σᵢ|∂²s/∂xᵢ²| (zero for a plane; ~0.01–0.03 mm
/// for a sphere of 20 mm at h = 1). Where s has a kink (the medial surface: inside the bone
/// near a sharp edge or corner, and reaching the surface at the edge itself) it is O(h):
/// 3h/8 for min(x, y, z) at a cube corner, and never more than √3 h/2 for any 1-Lipschitz s.
/// Signs are right wherever |s| exceeds the error.
///
/// Cost (Release, one core of the 2-core machine): filling a near brick of 9³ nodes takes
/// about 730 MeshDistance searches, 1.3–1.4 ms on the femur and the sphere (0.2 ms on the
/// 12-triangle cube); a far brick one search. The femur's whole grid box (band 6 mm): 10 556
/// slots, 3132 near and 7424 far bricks, 17 MiB of nodes, 3.4 s on one thread, 1.7 s on two
/// (buildAllBricks). A warm sample takes 35–41 ns, against 0.3–2.1 µs for an exact query.
///
/// Thread safety: sample is const and may be called from any number of threads at once.
/// A brick is built once, under one of a few striped mutexes (so bricks build in parallel),
/// and published through an atomic pointer (double-checked). Its content depends only on
/// which brick it is, not on the thread that builds it or on when, and each node's value
/// only on the node's integer position (nodes shared by two bricks agree), so every answer
/// is bitwise the same for any thread count and order of queries, lazy or after
/// buildAllBricks.
class BoneDistanceGrid {
 public:
  /// A grid over the mesh of `mesh_distance` (frame B, mm), which must have been built with
  /// signs (MeshDistance's default). Nothing is sampled yet.
  /// @throws CollisionError if `mesh_distance` is null or has no signs, or the settings are
  ///         bad (h or band ≤ 0 or not finite, brick_cells outside 1..64, a brick index of
  ///         more than 2²⁴ slots).
  explicit BoneDistanceGrid(std::shared_ptr<const MeshDistance> mesh_distance,
                            const BoneDistanceGridSettings& settings = {});
  /// A grid over `mesh_B` (frame B, mm; closed, wound outward), building its MeshDistance.
  /// @throws CollisionError also if the mesh has no triangles, a non-finite vertex or a bad index.
  explicit BoneDistanceGrid(TriangleMesh mesh_B, const BoneDistanceGridSettings& settings = {});
  ~BoneDistanceGrid();
  BoneDistanceGrid(const BoneDistanceGrid&) = delete;
  BoneDistanceGrid& operator=(const BoneDistanceGrid&) = delete;

  /// s̃ and ∇s̃ at p_B (frame B, mm) as described in the class comment; builds the brick of
  /// p_B if it is the first query there. Thread-safe.
  /// @throws CollisionError if p_B is not finite.
  BoneDistanceSample sample(const Eigen::Vector3d& p_B) const;

  /// Classifies and fills every brick of the grid box not built yet (in parallel with
  /// OpenMP; safe alongside sample calls), to pay the whole cost at once instead of at the
  /// first query near each part of the surface. The answers are the same either way.
  void buildAllBricks() const;

  /// The settings in use.
  const BoneDistanceGridSettings& getSettings() const { return settings_; }
  /// The box covered by the brick index (frame B, mm): the mesh box padded by the band,
  /// rounded outward to whole bricks.
  Eigen::AlignedBox3d getGridBox() const;
  /// The exact distance queried for the nodes.
  const MeshDistance& getMeshDistance() const { return *mesh_distance_; }
  /// Work done so far.
  BoneDistanceGridStats getStats() const;

 private:
  struct Brick;
  static constexpr int kMutexStripes = 64;

  void validate() const;
  /// The brick at integer brick position `b` (slot `slot`), classified and filled if new.
  const Brick* buildBrick(const Eigen::Vector3i& b, long long slot) const;
  /// The (brick_cells + 1)³ node values of brick `b`, x fastest, clamped to ±calcNodeClamp().
  void fillNodes(const Eigen::Vector3i& b, std::vector<double>& nodes_mm) const;
  /// band + √3 h (mm): a node with |s| beyond it makes every cell holding it far.
  double calcNodeClamp() const;

  std::shared_ptr<const MeshDistance> mesh_distance_;
  BoneDistanceGridSettings settings_;
  Eigen::Vector3d origin_mm_ = Eigen::Vector3d::Zero();  ///< lowest corner of the grid box (B, mm).
  Eigen::Vector3i brick_counts_ = Eigen::Vector3i::Zero();  ///< bricks per axis.
  std::unique_ptr<std::atomic<const Brick*>[]> slots_;  ///< x fastest; null until built.
  std::unique_ptr<const Brick> far_outside_, far_inside_;  ///< shared by all far bricks.
  mutable std::array<std::mutex, kMutexStripes> build_mutexes_;
  mutable std::atomic<long long> bricks_near_{0}, bricks_far_{0}, distance_queries_{0};
};

}  // namespace rbfmuscle
