// SPDX-License-Identifier: Apache-2.0
#include "dynamics/tissue_lattice.h"

#include "dynamics/joint_lift_off.h"
#include "dynamics/smoothstep.h"
#include "dynamics/thickness_axes.h"
#include "geometry/mesh_distance.h"

#include <Eigen/LU>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

namespace rbfmuscle {

namespace {

Eigen::Vector3i cellOf(const Eigen::Vector3d& p, const Eigen::Vector3d& origin, double h) {
  return ((p - origin) / h).array().floor().cast<int>();
}

/// Trilinear weight of a cell's corner (at +x if corner&1, +y if corner&2, +z if corner&4) at
/// local coordinates u ∈ [0, 1]³.
double calcCornerWeight(int corner, const Eigen::Vector3d& u) {
  return ((corner & 1) ? u.x() : 1.0 - u.x()) * ((corner & 2) ? u.y() : 1.0 - u.y()) *
         ((corner & 4) ? u.z() : 1.0 - u.z());
}

}  // namespace

double calcOnBoneWeight(double clearance_mm, double half_thickness_mm) {
  if (!(half_thickness_mm > 0.0) || !(clearance_mm < half_thickness_mm)) return 0.0;  // +∞ far from the bones
  return 1.0 - calcSmoothstep(std::max(clearance_mm, 0.0) / half_thickness_mm);
}

TissueLattice::TissueLattice(const Eigen::Matrix3Xd& rest_centres_mm, const Attachments& attachments,
                             const Eigen::Vector3d& origin_mm, double cell_mm, const Eigen::Matrix3Xd& cover_mm,
                             const MeshDistance* muscle_surface, const ImplicitField* rest_clearance,
                             const LatticeSettings& settings)
    : num_bones_(attachments.num_bones), settings_(settings), origin_mm_(origin_mm), cell_mm_(cell_mm) {
  if (!(cell_mm > 0.0) || !std::isfinite(cell_mm) || !origin_mm.allFinite())
    throw std::invalid_argument("TissueLattice: the spacing must be > 0 and the origin finite");
  if (!(settings.max_thinning >= 1.0) || settings.smoothing_passes < 0 || !(settings.smoothing_cell_mm >= 0.0) ||
      !std::isfinite(settings.smoothing_cell_mm) || !(settings.blend_length_mm > 0.0) ||
      !(settings.taut_stretch > 0.0) || !std::isfinite(settings.taut_stretch) || settings.lift_passes < 0)
    throw std::invalid_argument(
        "TissueLattice: need max_thinning >= 1, smoothing_passes >= 0, smoothing_cell_mm >= 0, blend_length_mm > 0, "
        "taut_stretch > 0, lift_passes >= 0");
  if (cover_mm.cols() == 0 || !cover_mm.allFinite())
    throw std::invalid_argument("TissueLattice: the points to cover must be finite and not empty");
  // Lattice box: the cover points' cells and their neighbours, corners included.
  Eigen::Vector3i lo = Eigen::Vector3i::Constant(std::numeric_limits<int>::max());
  Eigen::Vector3i hi = Eigen::Vector3i::Constant(std::numeric_limits<int>::min());
  for (Eigen::Index j = 0; j < cover_mm.cols(); ++j) {
    const Eigen::Vector3i c = cellOf(cover_mm.col(j), origin_mm_, cell_mm_);
    lo = lo.cwiseMin(c);
    hi = hi.cwiseMax(c);
  }
  lo.array() -= 1;
  hi.array() += 2;
  origin_mm_ += cell_mm_ * lo.cast<double>();
  dims_ = hi - lo + Eigen::Vector3i::Ones();
  if (static_cast<double>(dims_.prod()) > 5e7) throw std::invalid_argument("TissueLattice: more than 5e7 lattice nodes");
  node_of_cell_corner_.assign(static_cast<size_t>(dims_.prod()), -1);
  std::vector<Eigen::Vector3i> active;
  for (Eigen::Index j = 0; j < cover_mm.cols(); ++j) {
    const Eigen::Vector3i c = cellOf(cover_mm.col(j), origin_mm_, cell_mm_);
    for (int dz = -1; dz <= 2; ++dz)
      for (int dy = -1; dy <= 2; ++dy)
        for (int dx = -1; dx <= 2; ++dx) {
          const Eigen::Vector3i n = c + Eigen::Vector3i(dx, dy, dz);
          int& slot = node_of_cell_corner_[static_cast<size_t>((n.z() * dims_.y() + n.y()) * dims_.x() + n.x())];
          if (slot >= 0) continue;
          slot = static_cast<int>(active.size());
          active.push_back(n);
        }
  }
  const int k = static_cast<int>(active.size());
  rest_nodes_mm_.resize(3, k);
  for (int n = 0; n < k; ++n) {
    rest_nodes_mm_.col(n) = origin_mm_ + cell_mm_ * active[static_cast<size_t>(n)].cast<double>();
  }
  neighbours_.assign(static_cast<size_t>(k), {-1, -1, -1, -1, -1, -1});
  for (int n = 0; n < k; ++n)
    for (int axis = 0; axis < 3; ++axis)
      for (int side = 0; side < 2; ++side)
        neighbours_[static_cast<size_t>(n)][static_cast<size_t>(2 * axis + side)] =
            findNode(active[static_cast<size_t>(n)] + (side ? 1 : -1) * Eigen::Vector3i::Unit(axis));
  node_weights_ = settings_.joint_centre_mm
                      ? calcJointAngleBlendWeights(rest_nodes_mm_, rest_centres_mm, attachments, *settings_.joint_centre_mm)
                      : calcBlendWeights(rest_nodes_mm_, rest_centres_mm, attachments, settings_.blend_length_mm,
                                         settings_.blend_power);

  if (settings_.incompressible && muscle_surface) {
    const ThicknessAxes axes = calcThicknessAxes(*muscle_surface, rest_nodes_mm_);
    Eigen::Matrix3Xd mid_vectors_mm = -(axes.axes.array().rowwise() * axes.offsets_mm.transpose().array()).matrix();
    // The anchor moves from m towards each end of the chord that lies on a bone at rest.
    anchor_vectors_mm_ = mid_vectors_mm;
    if (rest_clearance)
      for (int n = 0; n < k; ++n) {
        const Eigen::Vector3d axis = axes.axes.col(n), mid = rest_nodes_mm_.col(n) + mid_vectors_mm.col(n);
        const double h = axes.half_chords_mm[n];
        const double on_bone = calcOnBoneWeight(rest_clearance->calcValue(mid - h * axis), h);
        const double on_bone_far = calcOnBoneWeight(rest_clearance->calcValue(mid + h * axis), h);
        anchor_vectors_mm_.col(n) += h * (on_bone_far - on_bone) * axis;
      }
    const int passes = scalePasses(settings_.smoothing_passes);
    smooth(mid_vectors_mm, passes);
    smooth(anchor_vectors_mm_, passes);
    // k = −div v: 1 where the mid-set is a surface (v = −o n), 2 where it is a line.
    thin_directions_.resize(k);
    for (int n = 0; n < k; ++n)
      thin_directions_[n] = std::clamp(-differentiate(mid_vectors_mm, n).trace(), 1.0, 2.0);
  }
  if (num_bones_ == 2) {
    // Step 4: ∇w₁, the way the blend weight runs from bone 0 to bone 1, and how fast.
    Eigen::Matrix3Xd weight_1(3, k);
    for (int n = 0; n < k; ++n) weight_1.col(n).setConstant(node_weights_(1, n));
    weight_gradients_.resize(3, k);
    for (int n = 0; n < k; ++n) weight_gradients_.col(n) = differentiate(weight_1, n).row(0).transpose();
  }
  update(std::vector<Eigen::Isometry3d>(static_cast<size_t>(num_bones_), Eigen::Isometry3d::Identity()));
}

int TissueLattice::scalePasses(int passes) const {
  const double scale = settings_.smoothing_cell_mm > 0.0 ? settings_.smoothing_cell_mm / cell_mm_ : 1.0;
  return static_cast<int>(std::lround(passes * scale * scale));
}

double TissueLattice::setLiftOffGuides(const Eigen::Matrix3Xd& fibre_points_mm, int points_per_fibre,
                                       const std::vector<bool>& on_origin_bone) {
  if (num_bones_ != 2 || !settings_.joint_centre_mm)
    throw std::invalid_argument("TissueLattice::setLiftOffGuides: the lift-off needs two bones and a joint centre");
  const Eigen::Index total = fibre_points_mm.cols();
  if (points_per_fibre < 2 || total == 0 || total % points_per_fibre != 0 ||
      static_cast<Eigen::Index>(on_origin_bone.size()) != total)
    throw std::invalid_argument("TissueLattice::setLiftOffGuides: need whole fibres of at least 2 points and one "
                                "on-bone flag per point");
  const int fibres = static_cast<int>(total / points_per_fibre);
  std::vector<int> ties(static_cast<size_t>(total), -1);
  for (int f = 0; f < fibres; ++f) {
    ties[static_cast<size_t>(f * points_per_fibre)] = 0;
    ties[static_cast<size_t>((f + 1) * points_per_fibre - 1)] = 1;
  }
  LatticeBinding guides = bind(fibre_points_mm, ties);
  // w₁ of each guide point, interpolated as the map carries it: 0 and 1 at the tied ends.
  Eigen::VectorXd weight_1(total);
  for (Eigen::Index j = 0; j < total; ++j) {
    const size_t jj = static_cast<size_t>(j);
    if (guides.rigid_bone[jj] >= 0) {
      weight_1[j] = guides.rigid_bone[jj];
      continue;
    }
    weight_1[j] = 0.0;
    for (int corner = 0; corner < 8; ++corner)
      weight_1[j] += calcCornerWeight(corner, guides.local.col(j)) *
                     node_weights_(1, guides.corners[jj][static_cast<size_t>(corner)]);
  }
  // The pulley: the median, over the fibres lying on the origin bone, of w₁ at their last point on it.
  std::vector<double> held;
  for (int f = 0; f < fibres; ++f)
    for (int j = (f + 1) * points_per_fibre - 1; j >= f * points_per_fibre; --j)
      if (on_origin_bone[static_cast<size_t>(j)]) {
        held.push_back(weight_1[j]);
        break;
      }
  double pulley = 0.0;
  if (!held.empty()) {
    std::nth_element(held.begin(), held.begin() + static_cast<long>(held.size() / 2), held.end());
    pulley = held[held.size() / 2];
  }
  string_starts_.assign(static_cast<size_t>(fibres), 0);
  for (int f = 0; f < fibres; ++f)
    for (int j = 0; j < points_per_fibre; ++j)
      if (weight_1[f * points_per_fibre + j] <= pulley) string_starts_[static_cast<size_t>(f)] = j;
  // Tissue that turns with one bone to second order (the blend ramp's quadratic ends) does not
  // lift, as a string does not at its held ends: the rise fades to 0 across those ends.
  const double end_weight = calcJointBlendEndWeight();
  node_freedoms_.resize(countNodes());
  for (int n = 0; n < countNodes(); ++n)
    node_freedoms_[n] = calcSmoothstep(std::min(node_weights_(1, n), 1.0 - node_weights_(1, n)) / end_weight);
  guides_ = std::move(guides);
  guide_points_per_fibre_ = points_per_fibre;
  update(motions_);
  return pulley;
}

void TissueLattice::liftOff() {
  const std::optional<JointTurn> turn = getJointTurn();
  if (!turn) return;
  Eigen::Matrix3Xd now;
  carryPoints(guides_, nodes_mm_, now, nullptr);
  const Eigen::Matrix3Xd rest = motions_[0] * guides_.rest_mm;  // the rest fibres, seen from the origin bone
  const int k = countNodes(), p = guide_points_per_fibre_;
  Eigen::Matrix3Xd rises = Eigen::Matrix3Xd::Zero(3, k);
  Eigen::VectorXd shares = Eigen::VectorXd::Zero(k);
  for (size_t f = 0; f < string_starts_.size(); ++f) {
    const int first = static_cast<int>(f) * p + string_starts_[f], count = (static_cast<int>(f) + 1) * p - first;
    const Eigen::Matrix3Xd string_rises = calcLiftOffRisesSinceRest(
        now.middleCols(first, count), rest.middleCols(first, count), turn->centre_mm, turn->axis, cell_mm_);
    for (int i = 0; i < count; ++i) addToNodes(guides_, first + i, string_rises.col(i), rises, shares);
  }
  smoothNodeMeans(rises, shares);
  for (int n = 0; n < k; ++n) rises.col(n) *= lift_fraction_ * node_freedoms_[n];
  nodes_mm_ += rises;
  lift_max_mm_ = rises.colwise().norm().maxCoeff();
}

std::optional<JointTurn> TissueLattice::getJointTurn() const {
  if (num_bones_ != 2 || !settings_.joint_centre_mm) return std::nullopt;
  const Eigen::AngleAxisd turn(motions_[1].linear() * motions_[0].linear().transpose());
  if (!(turn.angle() > 0.0)) return std::nullopt;
  return JointTurn{motions_[0] * *settings_.joint_centre_mm, turn.axis().normalized()};
}

void TissueLattice::addToNodes(const LatticeBinding& points, int j, const Eigen::Vector3d& value,
                               Eigen::Matrix3Xd& sums, Eigen::VectorXd& shares) const {
  const size_t jj = static_cast<size_t>(j);
  if (points.rigid_bone[jj] >= 0) return;
  for (int corner = 0; corner < 8; ++corner) {
    const double w = calcCornerWeight(corner, points.local.col(j));
    const int node = points.corners[jj][static_cast<size_t>(corner)];
    sums.col(node) += w * value;
    shares[node] += w;
  }
}

void TissueLattice::smoothNodeMeans(Eigen::Matrix3Xd& sums, const Eigen::VectorXd& shares) const {
  // Each node takes the mean of the points in its cells, then the means are smoothed, so they
  // fade towards the muscle's edge and its thin parts, where few points pass.
  for (Eigen::Index n = 0; n < sums.cols(); ++n)
    if (shares[n] > 0.0) sums.col(n) /= shares[n];
  smooth(sums, scalePasses(settings_.lift_passes));
}

Eigen::Matrix3Xd TissueLattice::spreadLikeRises(const LatticeBinding& points, const Eigen::Matrix3Xd& vectors) const {
  if (vectors.cols() != points.size())
    throw std::invalid_argument("TissueLattice::spreadLikeRises: " + std::to_string(vectors.cols()) + " vectors for " +
                                std::to_string(points.size()) + " points");
  const int k = countNodes();
  Eigen::Matrix3Xd at_nodes = Eigen::Matrix3Xd::Zero(3, k);
  Eigen::VectorXd shares = Eigen::VectorXd::Zero(k);
  for (int j = 0; j < points.size(); ++j) addToNodes(points, j, vectors.col(j), at_nodes, shares);
  smoothNodeMeans(at_nodes, shares);
  Eigen::Matrix3Xd out = Eigen::Matrix3Xd::Zero(3, points.size());
  for (int j = 0; j < points.size(); ++j) {
    const size_t jj = static_cast<size_t>(j);
    if (points.rigid_bone[jj] >= 0) continue;
    for (int corner = 0; corner < 8; ++corner)
      out.col(j) += calcCornerWeight(corner, points.local.col(j)) * at_nodes.col(points.corners[jj][static_cast<size_t>(corner)]);
  }
  return out;
}

void TissueLattice::smooth(Eigen::Matrix3Xd& vectors, int passes) const {
  for (int pass = 0; pass < passes; ++pass) {
    Eigen::Matrix3Xd smoothed = vectors;
    for (Eigen::Index n = 0; n < vectors.cols(); ++n) {
      Eigen::Vector3d sum = Eigen::Vector3d::Zero();
      int count = 0;
      for (int nb : neighbours_[static_cast<size_t>(n)])
        if (nb >= 0) {
          sum += vectors.col(nb);
          ++count;
        }
      if (count > 0) smoothed.col(n) = 0.5 * vectors.col(n) + 0.5 * sum / count;
    }
    vectors.swap(smoothed);
  }
}

int TissueLattice::findNode(const Eigen::Vector3i& ijk) const {
  if ((ijk.array() < 0).any() || (ijk.array() >= dims_.array()).any()) return -1;
  return node_of_cell_corner_[static_cast<size_t>((ijk.z() * dims_.y() + ijk.y()) * dims_.x() + ijk.x())];
}

int TissueLattice::findNodeAt(const Eigen::Vector3d& p_mm) const {
  const Eigen::Vector3d u = (p_mm - origin_mm_) / cell_mm_;
  const Eigen::Vector3d r = u.array().round();
  if (!u.allFinite() || (u - r).cwiseAbs().maxCoeff() > 1e-6) return -1;
  return findNode(r.cast<int>());
}

Eigen::Vector3d TissueLattice::getRestNode(int n) const { return rest_nodes_mm_.col(n); }

Eigen::Matrix3d TissueLattice::differentiate(const Eigen::Matrix3Xd& positions, int n) const {
  Eigen::Matrix3d d;
  const std::array<int, 6>& nb = neighbours_[static_cast<size_t>(n)];
  for (int axis = 0; axis < 3; ++axis) {
    const int lo = nb[static_cast<size_t>(2 * axis)], hi = nb[static_cast<size_t>(2 * axis + 1)];
    if (lo >= 0 && hi >= 0)
      d.col(axis) = (positions.col(hi) - positions.col(lo)) / (2.0 * cell_mm_);
    else if (hi >= 0)
      d.col(axis) = (positions.col(hi) - positions.col(n)) / cell_mm_;
    else if (lo >= 0)
      d.col(axis) = (positions.col(n) - positions.col(lo)) / cell_mm_;
    else
      d.col(axis) = Eigen::Vector3d::Unit(axis);
  }
  return d;
}

void TissueLattice::update(const std::vector<Eigen::Isometry3d>& bone_motion_M) {
  if (static_cast<int>(bone_motion_M.size()) != num_bones_)
    throw std::invalid_argument("TissueLattice: " + std::to_string(bone_motion_M.size()) + " bone motions for " +
                                std::to_string(num_bones_) + " bones");
  for (size_t b = 0; b < bone_motion_M.size(); ++b) {
    const Eigen::Matrix3d r = bone_motion_M[b].linear();
    if (!bone_motion_M[b].matrix().allFinite() || !(r.transpose() * r).isIdentity(1e-9) || r.determinant() < 0.0)
      throw std::invalid_argument("TissueLattice: bone motion " + std::to_string(b) + " is not a finite rigid transform");
  }
  motions_ = bone_motion_M;
  transforms_.clear();
  for (const Eigen::Isometry3d& m : motions_) transforms_.push_back(toDualQuaternion(m));
  const int k = countNodes();
  blended_mm_.resize(3, k);
  for (int n = 0; n < k; ++n) blended_mm_.col(n) = applyBlend(node_weights_.col(n).data(), transforms_, rest_nodes_mm_.col(n));
  blend_volume_changes_.resize(k);
  nodes_mm_ = blended_mm_;
  const bool thin = anchor_vectors_mm_.cols() == k, taut = weight_gradients_.cols() == k;
  double stretch_sum = 0.0, rate_sum = 0.0;  // Σ |∇w₁| |DΦ u| = Σ |DΦ ∇w₁|, and Σ |∇w₁|
  for (int n = 0; n < k; ++n) {
    const Eigen::Matrix3d d = differentiate(blended_mm_, n);
    const double j = d.determinant();
    blend_volume_changes_[n] = j;
    if (taut) {
      stretch_sum += (d * weight_gradients_.col(n)).norm();
      rate_sum += weight_gradients_.col(n).norm();
    }
    if (!thin) continue;
    const double t = j > 0.0 ? std::clamp(std::pow(j, -1.0 / thin_directions_[n]), 1.0 / settings_.max_thinning,
                                          settings_.max_thinning)
                             : settings_.max_thinning;  // a fold thickens as much as allowed
    nodes_mm_.col(n) -= (t - 1.0) * (d * anchor_vectors_mm_.col(n));
  }
  stretch_ = rate_sum > 0.0 ? stretch_sum / rate_sum : 1.0;
  // Step 5: a shortened muscle lifts off the joint.
  lift_fraction_ = guides_.size() > 0 ? calcSmoothstep((1.0 - stretch_) / settings_.taut_stretch) : 0.0;
  lift_max_mm_ = 0.0;
  if (lift_fraction_ > 0.0) liftOff();
  // Step 4: the taut nodes, part of the way from the blend's arcs to its chords.
  taut_fraction_ = calcSmoothstep((stretch_ - 1.0) / settings_.taut_stretch);
  taut_nodes_mm_.resize(3, 0);
  if (taut_fraction_ == 0.0) return;
  taut_nodes_mm_ = nodes_mm_;
  for (int n = 0; n < k; ++n)
    taut_nodes_mm_.col(n) += taut_fraction_ * (applyLinearBlend(node_weights_.col(n).data(), motions_,
                                                                rest_nodes_mm_.col(n)) - blended_mm_.col(n));
}

LatticeBinding TissueLattice::bind(const Eigen::Matrix3Xd& rest_mm, const std::vector<int>& rigid_bone) const {
  const Eigen::Index p = rest_mm.cols();
  if (!rigid_bone.empty() && static_cast<Eigen::Index>(rigid_bone.size()) != p)
    throw std::invalid_argument("TissueLattice::bind: " + std::to_string(rigid_bone.size()) + " bone ties for " +
                                std::to_string(p) + " points");
  LatticeBinding binding;
  binding.rest_mm = rest_mm;
  binding.corners.assign(static_cast<size_t>(p), {-1, -1, -1, -1, -1, -1, -1, -1});
  binding.local.setZero(3, p);
  binding.rigid_bone.assign(static_cast<size_t>(p), -1);
  for (Eigen::Index j = 0; j < p; ++j) {
    const int bone = rigid_bone.empty() ? -1 : rigid_bone[static_cast<size_t>(j)];
    if (bone >= num_bones_) throw std::invalid_argument("TissueLattice::bind: bone " + std::to_string(bone) + " out of range");
    if (bone >= 0) {
      binding.rigid_bone[static_cast<size_t>(j)] = bone;
      continue;
    }
    if (!rest_mm.col(j).allFinite()) throw std::invalid_argument("TissueLattice::bind: point " + std::to_string(j) + " is not finite");
    const Eigen::Vector3d u = (rest_mm.col(j) - origin_mm_) / cell_mm_;
    const Eigen::Vector3i c = u.array().floor().cast<int>();
    std::array<int, 8>& corners = binding.corners[static_cast<size_t>(j)];
    for (int corner = 0; corner < 8; ++corner) {
      corners[static_cast<size_t>(corner)] = findNode(c + Eigen::Vector3i(corner & 1, (corner >> 1) & 1, (corner >> 2) & 1));
      if (corners[static_cast<size_t>(corner)] < 0)
        throw std::invalid_argument("TissueLattice::bind: point " + std::to_string(j) +
                                    " lies outside the lattice's covered cells");
    }
    binding.local.col(j) = u - c.cast<double>();
  }
  return binding;
}

void TissueLattice::carry(const LatticeBinding& points, Eigen::Matrix3Xd& out) const {
  carryPoints(points, nodes_mm_, out, nullptr);
}

void TissueLattice::carry(const LatticeBinding& points, Eigen::Matrix3Xd& out,
                          std::vector<Eigen::Matrix3d>& frames) const {
  frames.resize(static_cast<size_t>(points.size()));
  carryPoints(points, nodes_mm_, out, &frames);
}

void TissueLattice::carryTaut(const LatticeBinding& points, Eigen::Matrix3Xd& out) const {
  carryPoints(points, taut_fraction_ > 0.0 ? taut_nodes_mm_ : nodes_mm_, out, nullptr);
}

void TissueLattice::carryPoints(const LatticeBinding& points, const Eigen::Matrix3Xd& nodes_mm, Eigen::Matrix3Xd& out,
                                std::vector<Eigen::Matrix3d>* frames) const {
  out.resize(3, points.size());
  for (int j = 0; j < points.size(); ++j) {
    const size_t jj = static_cast<size_t>(j);
    const int bone = points.rigid_bone[jj];
    if (bone >= 0) {
      out.col(j) = motions_[static_cast<size_t>(bone)] * Eigen::Vector3d(points.rest_mm.col(j));
      if (frames) (*frames)[jj] = motions_[static_cast<size_t>(bone)].linear();
      continue;
    }
    // Trilinear interpolation of the cell's nodes, and (for frames) its gradient.
    const Eigen::Vector3d u = points.local.col(j);
    Eigen::Vector3d y = Eigen::Vector3d::Zero();
    Eigen::Matrix3d f = Eigen::Matrix3d::Zero();
    for (int corner = 0; corner < 8; ++corner) {
      const int a = corner & 1, b = (corner >> 1) & 1, e = (corner >> 2) & 1;
      const double wx = a ? u.x() : 1.0 - u.x(), wy = b ? u.y() : 1.0 - u.y(), wz = e ? u.z() : 1.0 - u.z();
      const Eigen::Vector3d node = nodes_mm.col(points.corners[jj][static_cast<size_t>(corner)]);
      y += (wx * wy * wz) * node;
      if (!frames) continue;
      const double sx = a ? 1.0 : -1.0, sy = b ? 1.0 : -1.0, sz = e ? 1.0 : -1.0;
      f.col(0) += (sx * wy * wz) * node;
      f.col(1) += (wx * sy * wz) * node;
      f.col(2) += (wx * wy * sz) * node;
    }
    out.col(j) = y;
    if (frames) (*frames)[jj] = f / cell_mm_;
  }
}

void TissueLattice::calcVolumeChanges(Eigen::VectorXd& out) const {
  out.resize(countNodes());
  for (int n = 0; n < countNodes(); ++n) out[n] = differentiate(nodes_mm_, n).determinant();
}

}  // namespace rbfmuscle
