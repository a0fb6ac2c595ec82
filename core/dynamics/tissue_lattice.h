// SPDX-License-Identifier: Apache-2.0
#pragma once
/// @file
/// The map that carries a muscle's tissue with its bones: a lattice of rest nodes moved by
/// the bone blend and thinned to keep the tissue's volume, interpolated everywhere else.
///
/// 1. Blend: node x moves to Φ(x), the dual-quaternion blend of the bone motions with the
///    blend weights of x (attachment.h: inverse squared distances to each bone's attachment,
///    or, given the joint's centre, angles about it).
/// 2. Incompressibility: Φ stretches the tissue between bones turning apart without thinning
///    it (a flexed gluteus maximus grew by 40 %), and lowering the field to restore the volume
///    breaks thin parts first. So each node scales about its anchor by the factor t = J^(−1/k):
///    J = det DΦ (differences of neighbouring nodes) and k the number of directions in which
///    the mid-set is thin (1 for a sheet, 2 for a spindle, from the divergence of the rest
///    mid-surface vectors v = m − x, thickness_axes.h). The anchor is the mid-surface point m,
///    moved along the chord towards each of its ends that lies on a bone at rest
///    (calcOnBoneWeight), so that tissue on a bone thickens and thins away from it; with
///    a = anchor − x at rest,
///      y = Φ(x) − (t − 1) DΦ a.
///    A sheet then scales across its thickness by 1/J, a spindle across its section by 1/√J.
/// 3. Everything else the map carries (kernel centres and frames, fibre points, surface
///    vertices) is bound at rest to its lattice cell and moves by trilinear interpolation of
///    the cell's eight nodes; a kernel's frame F is the interpolant's gradient. So kernels,
///    quadrature points and surfaces move by one and the same map, and the volume measured
///    over the carried lattice matches the field's.
/// Points tied to a bone (attached kernels, fibre ends) move rigidly with it instead.
/// A common rigid motion of all bones moves every node, and so every point, rigidly.
/// 4. Taut map (for the fibres, two bones): the blend turns tissue between the bones about
///    their joint, so a fibre keeps its distance from the joint like a string wound on a drum.
///    A stretched muscle is taut and takes the chord instead: its stretch is the mean of
///    |DΦ u| over the nodes, u = ∇w₁/|∇w₁| the way the blend weight runs from bone 0 to bone 1
///    (weighted by |∇w₁|, where the blend bends the tissue); the taut fraction
///    λ = smoothstep((stretch − 1) / taut_stretch) ∈ [0, 1]; and the taut nodes are
///    y + λ (Σ_b w_b T_b x − Φ(x)), part of the way to the linear blend, whose points lie on
///    the chords between their places on the two bones. A shortened muscle (λ = 0) keeps the
///    map. The volume follows the map; only the fibres move towards the taut nodes
///    (fibre_stage.h), as far as the muscle allows.
/// 5. Lift-off (two bones, a joint centre, guides set): a shortened muscle is taut too, and
///    lifts off the joint as a string lifts off a drum (joint_lift_off.h). Its lift fraction is
///    the mirror of step 4's, λ = smoothstep((1 − stretch) / taut_stretch). The guides are the
///    rest fibres carried by the map. Each one is held where it leaves its origin bone at rest,
///    as fascia binds the iliacus to its fossa and the inguinal ligament the psoas to the brim:
///    its string runs from its last point whose blend weight w₁ is at most the pulley weight
///    (the median, over the fibres lying on the origin bone, of w₁ at their last point on it)
///    to its insertion, through the points as the map carries them. Each string point rises by
///    s − s₀ about the joint's turn axis; each node takes the mean rise
///    of the guide points in its cells, the rises are smoothed by lift_passes Laplacian passes
///    (so they fade at the muscle's edge and over its thin parts alike), and every node rises
///    by λ times its own, after the thinning, except where it turns with one bone to second
///    order (the blend ramp's quadratic ends, attachment.h): across those the rise fades to 0,
///    as a string's does at its held ends. The volume, the surface and the fibres all move
///    with the risen nodes.
#include "dynamics/attachment.h"
#include "dynamics/motion_prediction.h"

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <array>
#include <optional>
#include <vector>

namespace rbfmuscle {

/// Rest points bound to the lattice.
struct LatticeBinding {
  std::vector<std::array<int, 8>> corners;  ///< the 8 nodes of each point's cell (corner c at +x if c&1, +y if c&2, +z if c&4)
  Eigen::Matrix3Xd local;          ///< (u, v, w) ∈ [0, 1]³ of each point in its cell
  std::vector<int> rigid_bone;     ///< bone a point is tied to, −1 when carried by the lattice
  Eigen::Matrix3Xd rest_mm;        ///< rest positions (3×P, M)
  int size() const { return static_cast<int>(rest_mm.cols()); }
};

/// A joint's turn: its centre (M, mm) and the unit axis it turns about.
struct JointTurn {
  Eigen::Vector3d centre_mm;
  Eigen::Vector3d axis;
};

/// Settings of TissueLattice.
struct LatticeSettings {
  double blend_length_mm = 1.0;  ///< ℓ of the blend weights (mm), > 0
  double blend_power = 2.0;      ///< p of the blend weights (attachment.h, calcBlendWeights), > 0
  bool incompressible = true;    ///< step 2 of the file comment (false: the blend alone)
  double max_thinning = 4.0;     ///< t is clamped to [1/max, max], ≥ 1
  /// Laplacian passes over the rest mid-surface and anchor vectors at a cell of
  /// smoothing_cell_mm, ≥ 0. A finer cell takes more passes, round(passes · (smoothing_cell_mm /
  /// cell)²), so the smoothing spans the same length: at the same 3 passes, 8000 quadrature
  /// points (a cell 0.63 times the 2000 points') made the gluteus maximus's fibres step by 4 %
  /// between 1° frames of the main job, against 0.77 % with 2000.
  int smoothing_passes = 3;
  double smoothing_cell_mm = 0.0;  ///< cell at which smoothing_passes apply (mm); 0: the lattice's own
  /// The centre of the joint between the two bones (M, mm): blend weights by angle about it
  /// (calcJointAngleBlendWeights); none: by distance (calcBlendWeights, blend_length_mm, blend_power).
  std::optional<Eigen::Vector3d> joint_centre_mm;
  /// Stretch beyond rest over which the taut fraction rises from 0 to 1 (step 4), > 0: 10 %;
  /// 5 % or 20 % change the gluteus maximus's flexion moment arms by at most 1 mm (docs/moment_arms.md).
  double taut_stretch = 0.1;
  /// Laplacian passes that spread the lift-off's rises over the lattice (step 5), at the cell of
  /// smoothing_cell_mm like smoothing_passes, ≥ 0.
  int lift_passes = 8;
};

/// How much a muscle surface point with rest bone clearance s (mm) lies on the bone, for a
/// chord of half-thickness h (mm): 1 at s ≤ 0, 0 at s ≥ h (or s = +∞), smoothstep between.
double calcOnBoneWeight(double clearance_mm, double half_thickness_mm);

/// The carrying map (file comment). Rest set-up is expensive; update() and carry() are cheap.
class TissueLattice {
 public:
  /// @param rest_centres_mm the kernels' rest centres (3×N, M) with `attachments` (blend weights)
  /// @param origin_mm a lattice node (M, rest); @param cell_mm spacing h > 0
  /// @param cover_mm every point to be bound later must lie in a cell of these points' cells
  ///   or their neighbours (3×P: kernel centres, quadrature nodes, fibre points, surface vertices)
  /// @param muscle_surface the rest muscle mesh (M), whose chords give the nodes' thickness
  ///   axes and mid-surface (thickness_axes.h); null: no incompressibility
  /// @param rest_clearance the bones' signed distance s at rest (M, mm; +∞ far from them):
  ///   the tissue scales away from a side of its chord that lies on a bone (calcOnBoneWeight);
  ///   null: about the mid-surface everywhere
  /// @throws std::invalid_argument for bad settings, sizes or non-finite input.
  TissueLattice(const Eigen::Matrix3Xd& rest_centres_mm, const Attachments& attachments,
                const Eigen::Vector3d& origin_mm, double cell_mm, const Eigen::Matrix3Xd& cover_mm,
                const class MeshDistance* muscle_surface, const class ImplicitField* rest_clearance = nullptr,
                const LatticeSettings& settings = {});

  /// Binds rest points (3×P, M) to their cells; a point with rigid_bone[j] ≥ 0 moves with
  /// that bone instead. @throws std::invalid_argument if a point lies outside the covered cells.
  LatticeBinding bind(const Eigen::Matrix3Xd& rest_mm, const std::vector<int>& rigid_bone = {}) const;

  /// Moves the nodes for the bone motions T_b (B, rest → now, in M).
  /// @throws std::invalid_argument on a wrong count or a non-rigid, non-finite transform.
  void update(const std::vector<Eigen::Isometry3d>& bone_motion_M);

  /// Current positions (3×P) of bound points.
  void carry(const LatticeBinding& points, Eigen::Matrix3Xd& out) const;
  /// Current positions and frames F (the map's gradient; the bone's rotation for tied points).
  void carry(const LatticeBinding& points, Eigen::Matrix3Xd& out, std::vector<Eigen::Matrix3d>& frames) const;
  /// Current positions (3×P) of bound points by the taut map (step 4; the map itself when λ = 0).
  void carryTaut(const LatticeBinding& points, Eigen::Matrix3Xd& out) const;
  /// The muscle's stretch along its blend in the last update (step 4; 1 at rest, 1 with one bone).
  double getStretch() const { return stretch_; }
  /// λ of the last update (step 4), in [0, 1].
  double getTautFraction() const { return taut_fraction_; }

  /// Sets the lift-off's guides (step 5): the rest fibres (3×F·P, M, P points each, the first
  /// tied to bone 0 and the last to bone 1) and whether each point lies on the origin bone at
  /// rest. Returns the pulley weight (0 when no fibre lies on the origin bone: each string then
  /// runs from its fibre's origin end).
  /// @throws std::invalid_argument without two bones and a joint centre, or for bad sizes.
  double setLiftOffGuides(const Eigen::Matrix3Xd& fibre_points_mm, int points_per_fibre,
                          const std::vector<bool>& on_origin_bone);
  /// The lift fraction of the last update (step 5), in [0, 1]; 0 without guides.
  double getLiftFraction() const { return lift_fraction_; }
  /// The largest rise of a node in the last update (mm).
  double getLiftMax() const { return lift_max_mm_; }
  /// The joint's turn in the last update: its centre now (M, mm) and the unit axis of bone 1's
  /// turn from bone 0's; none without two bones, a joint centre and a turn.
  std::optional<JointTurn> getJointTurn() const;
  /// Per-point vectors of bound points (3×P, such as rises) spread over the lattice as step 5
  /// spreads its rises: each node takes their mean over the points in its cells, lift_passes
  /// Laplacian passes smooth them, and each point takes its cell's interpolant (0 where tied to a bone).
  /// @throws std::invalid_argument when the sizes differ.
  Eigen::Matrix3Xd spreadLikeRises(const LatticeBinding& points, const Eigen::Matrix3Xd& vectors) const;

  /// Lattice coordinates → whether node (i, j, k) is active, and its index.
  int findNode(const Eigen::Vector3i& ijk) const;
  /// The active node within 1e-6 spacing of the rest point p, −1 when there is none.
  int findNodeAt(const Eigen::Vector3d& p_mm) const;
  /// Rest position of active node n.
  Eigen::Vector3d getRestNode(int n) const;
  /// Current positions of the active nodes (3×K).
  const Eigen::Matrix3Xd& getNodes() const { return nodes_mm_; }
  /// det of the current map's differences at every active node (K), from the thinned nodes.
  void calcVolumeChanges(Eigen::VectorXd& out) const;
  /// The blend's own volume change J = det DΦ at every active node (K) of the last update.
  const Eigen::VectorXd& getBlendVolumeChanges() const { return blend_volume_changes_; }
  /// Number of active nodes K.
  int countNodes() const { return static_cast<int>(rest_nodes_mm_.cols()); }
  /// Spacing h (mm).
  double getCellSize() const { return cell_mm_; }
  /// Number of bones B.
  int getNumBones() const { return num_bones_; }

 private:
  /// Positions of bound points and, when `frames` is given, their frames (see carry).
  void carryPoints(const LatticeBinding& points, const Eigen::Matrix3Xd& nodes_mm, Eigen::Matrix3Xd& out,
                   std::vector<Eigen::Matrix3d>* frames) const;
  /// Differences of `positions` at node n along the lattice axes (central where both
  /// neighbours are active, else one-sided, else the rest axis).
  Eigen::Matrix3d differentiate(const Eigen::Matrix3Xd& positions, int n) const;
  /// `passes` Laplacian passes over per-node vectors (each node halfway to its neighbours' mean).
  void smooth(Eigen::Matrix3Xd& vectors, int passes) const;
  /// passes at the lattice's own cell for `passes` at settings_.smoothing_cell_mm.
  int scalePasses(int passes) const;
  /// Step 5: raises nodes_mm_ by the lift fraction times the guides' spread rises.
  void liftOff();
  /// Adds `value` at bound point j to its cell's nodes by the trilinear weights (sums and shares).
  void addToNodes(const LatticeBinding& points, int j, const Eigen::Vector3d& value, Eigen::Matrix3Xd& sums,
                  Eigen::VectorXd& shares) const;
  /// Turns addToNodes' sums into means (nodes with no share keep 0) and smooths them by lift_passes.
  void smoothNodeMeans(Eigen::Matrix3Xd& sums, const Eigen::VectorXd& shares) const;

  int num_bones_ = 0;
  LatticeSettings settings_;
  Eigen::Vector3d origin_mm_;
  double cell_mm_;
  Eigen::Vector3i dims_ = Eigen::Vector3i::Zero();
  std::vector<int> node_of_cell_corner_;  ///< dense: lattice node → active index, −1 inactive
  std::vector<std::array<int, 6>> neighbours_;  ///< −x, +x, −y, +y, −z, +z active indices (−1 absent)
  Eigen::Matrix3Xd rest_nodes_mm_;
  Eigen::MatrixXd node_weights_;          ///< B×K blend weights
  Eigen::Matrix3Xd anchor_vectors_mm_;    ///< a per node (empty: no incompressibility)
  Eigen::VectorXd thin_directions_;       ///< k per node, in [1, 2]
  std::vector<Eigen::Isometry3d> motions_;
  std::vector<DualQuaternion> transforms_;
  Eigen::Matrix3Xd blended_mm_;           ///< Φ(x) per node
  Eigen::VectorXd blend_volume_changes_;
  Eigen::Matrix3Xd nodes_mm_;             ///< y per node
  Eigen::Matrix3Xd weight_gradients_;     ///< ∇w₁ per node (1/mm; step 4; empty unless B = 2)
  double stretch_ = 1.0, taut_fraction_ = 0.0;
  Eigen::Matrix3Xd taut_nodes_mm_;        ///< y + λ (linear blend − Φ) per node (empty when λ = 0)
  LatticeBinding guides_;                 ///< step 5's rest fibres (empty: no lift-off)
  int guide_points_per_fibre_ = 0;
  std::vector<int> string_starts_;        ///< per guide fibre: its first string point
  Eigen::VectorXd node_freedoms_;         ///< per node: the share of its rise it takes (0 where it turns with one bone)
  double lift_fraction_ = 0.0, lift_max_mm_ = 0.0;
};

}  // namespace rbfmuscle
