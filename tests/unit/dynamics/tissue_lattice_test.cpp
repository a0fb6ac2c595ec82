// SPDX-License-Identifier: Apache-2.0
// TissueLattice: rigid motions stay rigid, frames are the map's gradient, and incompressibility
// thins a stretched rod and keeps its volume.
#include "dynamics/joint_lift_off.h"
#include "dynamics/tissue_lattice.h"
#include "dynamics_test_shapes.h"
#include "geometry/mesh_distance.h"
#include "rbf/implicit_field.h"

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

namespace rbfmuscle {
namespace {


struct Rod {
  GaussianField field = test::makeRodField();
  Attachments attachments = test::makeRodAttachments(field);
  TriangleMesh mesh = test::makeBox(Eigen::Vector3d(-38, -8, -6), Eigen::Vector3d(38, 8, 6));
};

/// A flat bone under the rod: s(p) = p_z + 6 mm, zero on the rod's lower face.
struct FloorBelowTheRod final : ImplicitField {
  double calcValue(const Eigen::Vector3d& p_mm) const override { return p_mm.z() + 6.0; }
  Eigen::Vector3d calcGradient(const Eigen::Vector3d&) const override { return Eigen::Vector3d::UnitZ(); }
};

/// Flat bones above and below the rod: s(p) = min(p_z + 6, 6 − p_z) mm, zero on both faces.
struct FloorAndCeilingAroundTheRod final : ImplicitField {
  double calcValue(const Eigen::Vector3d& p_mm) const override { return std::min(p_mm.z() + 6.0, 6.0 - p_mm.z()); }
  Eigen::Vector3d calcGradient(const Eigen::Vector3d& p_mm) const override {
    return p_mm.z() < 0.0 ? Eigen::Vector3d::UnitZ() : Eigen::Vector3d(-Eigen::Vector3d::UnitZ());
  }
};

TissueLattice makeLattice(const Rod& rod, bool incompressible, const LatticeSettings& base = {},
                          const ImplicitField* rest_clearance = nullptr, double cell_mm = 2.0) {
  LatticeSettings settings = base;
  settings.incompressible = incompressible;
  const MeshDistance surface(rod.mesh);
  std::vector<Eigen::Vector3d> grid;  // every point a test binds lies in [−40, 40] × [−10, 10] × [−8, 8]
  for (double x = -40; x <= 40; x += 2)
    for (double y = -10; y <= 10; y += 2)
      for (double z = -8; z <= 8; z += 2) grid.emplace_back(x, y, z);
  Eigen::Matrix3Xd cover(3, static_cast<Eigen::Index>(grid.size()));
  for (size_t i = 0; i < grid.size(); ++i) cover.col(static_cast<Eigen::Index>(i)) = grid[i];
  return TissueLattice(rod.field.getCentres(), rod.attachments, Eigen::Vector3d::Zero(), cell_mm, cover, &surface,
                       rest_clearance, settings);
}

TEST(TissueLattice, ACommonRigidMotionMovesEveryPointAndFrameRigidly) {
  const Rod rod;
  TissueLattice lattice = makeLattice(rod, true);
  const Eigen::Isometry3d t = Eigen::Translation3d(12.0, -7.0, 30.0) * Eigen::AngleAxisd(1.1, Eigen::Vector3d(1, -2, 0.5).normalized());
  lattice.update({t, t});
  const LatticeBinding points = lattice.bind(rod.field.getCentres(), rod.attachments.bone_of_centre);
  Eigen::Matrix3Xd moved;
  std::vector<Eigen::Matrix3d> frames;
  lattice.carry(points, moved, frames);
  for (int k = 0; k < points.size(); ++k) {
    EXPECT_LT((moved.col(k) - t * Eigen::Vector3d(rod.field.getCentres().col(k))).norm(), 1e-6) << "kernel " << k;
    EXPECT_LT((frames[static_cast<size_t>(k)] - t.linear()).norm(), 1e-9) << "kernel " << k;
  }
  Eigen::VectorXd volume;
  lattice.calcVolumeChanges(volume);
  EXPECT_LT((volume.array() - 1.0).abs().maxCoeff(), 1e-9);
}

TEST(TissueLattice, PointsTiedToABoneMoveAndTurnExactlyWithIt) {
  const Rod rod;
  TissueLattice lattice = makeLattice(rod, true);
  const Eigen::Isometry3d turn = test::makeRotationAbout(Eigen::Vector3d(20, 0, 0), Eigen::Vector3d::UnitY(), 0.5);
  lattice.update({Eigen::Isometry3d::Identity(), turn});
  const LatticeBinding kernels = lattice.bind(rod.field.getCentres(), rod.attachments.bone_of_centre);
  Eigen::Matrix3Xd moved;
  std::vector<Eigen::Matrix3d> frames;
  lattice.carry(kernels, moved, frames);
  for (int k = 0; k < kernels.size(); ++k) {
    const int bone = rod.attachments.bone_of_centre[static_cast<size_t>(k)];
    if (bone < 0) continue;
    const Eigen::Isometry3d& t = bone == 0 ? Eigen::Isometry3d::Identity() : turn;
    EXPECT_LT((moved.col(k) - t * Eigen::Vector3d(rod.field.getCentres().col(k))).norm(), 1e-12) << "kernel " << k;
    EXPECT_LT((frames[static_cast<size_t>(k)] - t.linear()).norm(), 1e-12) << "kernel " << k;
  }
}

TEST(TissueLattice, FramesAreTheGradientOfTheCarriedMap) {
  const Rod rod;
  TissueLattice lattice = makeLattice(rod, true);
  const Eigen::Isometry3d bend = Eigen::Translation3d(30, 0, 0) * Eigen::AngleAxisd(0.8, Eigen::Vector3d::UnitZ()) *
                                 Eigen::Translation3d(-30, 0, 0);
  lattice.update({Eigen::Isometry3d::Identity(), bend});
  const Eigen::Vector3d p(3.3, 1.7, -0.9);
  const double h = 1e-4;
  Eigen::Matrix3Xd stencil(3, 7);
  stencil.col(0) = p;
  for (int i = 0; i < 3; ++i) {
    stencil.col(1 + 2 * i) = p + h * Eigen::Vector3d::Unit(i);
    stencil.col(2 + 2 * i) = p - h * Eigen::Vector3d::Unit(i);
  }
  Eigen::Matrix3Xd moved;
  std::vector<Eigen::Matrix3d> frames;
  lattice.carry(lattice.bind(stencil), moved, frames);
  for (int i = 0; i < 3; ++i)
    EXPECT_LT((frames[0].col(i) - (moved.col(1 + 2 * i) - moved.col(2 + 2 * i)) / (2 * h)).norm(), 1e-6) << "axis " << i;
}

TEST(TissueLattice, AStretchedRodThinsAcrossItsThicknessAndKeepsItsVolume) {
  const Rod rod;
  // Insertion bone pulled 20 mm along the rod: the blend stretches the middle.
  const Eigen::Isometry3d pull(Eigen::Translation3d(20, 0, 0));
  TissueLattice blend_only = makeLattice(rod, false), thinned = makeLattice(rod, true);
  blend_only.update({Eigen::Isometry3d::Identity(), pull});
  thinned.update({Eigen::Isometry3d::Identity(), pull});
  Eigen::VectorXd j_blend, j_thinned;
  blend_only.calcVolumeChanges(j_blend);
  thinned.calcVolumeChanges(j_thinned);
  const int middle = thinned.findNodeAt(Eigen::Vector3d(0, 0, 0));
  ASSERT_GE(middle, 0);
  EXPECT_GT(j_blend[middle], 1.1) << "the blend stretches the middle";
  EXPECT_NEAR(j_thinned[middle], 1.0, 0.05) << "thinned, the tissue keeps its volume";
  // The thinned rod is thinner across y or z at the middle, not shorter along x.
  const int side = thinned.findNodeAt(Eigen::Vector3d(0, 4, 0));
  ASSERT_GE(side, 0);
  EXPECT_LT(std::abs(thinned.getNodes()(1, side) - thinned.getNodes()(1, middle)),
            std::abs(blend_only.getNodes()(1, side) - blend_only.getNodes()(1, middle)) + 1e-9);
}

/// The rod compressed by its insertion pushed 16 mm towards its origin, free and with bones at
/// rest `bones`: the heights (mm) of the middle of its lower and upper faces, and its volume
/// change at the middle.
struct CompressedRod {
  double lower_mm, upper_mm, volume_change;
};

std::array<CompressedRod, 2> compressRodFreeAndWith(const ImplicitField& bones) {
  const Rod rod;
  std::array<CompressedRod, 2> result{};
  for (int with_bones = 0; with_bones < 2; ++with_bones) {
    TissueLattice lattice = makeLattice(rod, true, {}, with_bones ? &bones : nullptr);
    lattice.update({Eigen::Isometry3d::Identity(), Eigen::Isometry3d(Eigen::Translation3d(-16, 0, 0))});
    const int lower = lattice.findNodeAt(Eigen::Vector3d(0, 0, -6)), upper = lattice.findNodeAt(Eigen::Vector3d(0, 0, 6));
    const int middle = lattice.findNodeAt(Eigen::Vector3d::Zero());
    if (lower < 0 || upper < 0 || middle < 0) {
      ADD_FAILURE() << "the faces' middles and the middle are lattice nodes";
      return result;
    }
    Eigen::VectorXd volume;
    lattice.calcVolumeChanges(volume);
    result[static_cast<size_t>(with_bones)] = {lattice.getNodes()(2, lower), lattice.getNodes()(2, upper), volume[middle]};
  }
  return result;
}

// Compressed, the rod thickens to keep its volume. Lying on a floor, it thickens away from the
// floor: its lower face stays on it (about its mid-surface, it would sink by half the thickening).
TEST(TissueLattice, ACompressedRodLyingOnABoneThickensAwayFromTheBone) {
  const auto [free_rod, on_floor] = compressRodFreeAndWith(FloorBelowTheRod{});
  const double thickening_mm = free_rod.upper_mm - free_rod.lower_mm - 12.0;
  ASSERT_GT(thickening_mm, 1.0) << "the blend compresses the middle and the rod thickens";
  EXPECT_LT(free_rod.lower_mm, -6.0 - 0.4 * thickening_mm) << "about the mid-surface: into the floor";
  EXPECT_NEAR(on_floor.lower_mm, -6.0, 0.05 * thickening_mm) << "on the floor: stays on it";
  EXPECT_NEAR(on_floor.upper_mm - on_floor.lower_mm, 12.0 + thickening_mm, 0.05 * thickening_mm) << "and thickens as much";
  EXPECT_NEAR(on_floor.volume_change, free_rod.volume_change, 0.02) << "the anchor does not change the volume";
}

// The smoothing of the rest mid-surface and anchor vectors spans the same length on a finer
// lattice: the compressed rod's faces then move alike on lattices of 2 and 1 mm.
TEST(TissueLattice, SmoothingSpansTheSameLengthOnAFinerLattice) {
  const Rod rod;
  const Eigen::Isometry3d push(Eigen::Translation3d(-16, 0, 0));
  Eigen::Matrix3Xd faces(3, 0);  // the rod's faces between its attachments, 1 mm apart
  std::vector<Eigen::Vector3d> on_faces;
  for (double x = -20; x <= 20; x += 1)
    for (double y = -8; y <= 8; y += 1)
      for (double z : {-6.0, 6.0}) on_faces.emplace_back(x, y, z);
  faces.resize(3, static_cast<Eigen::Index>(on_faces.size()));
  for (size_t i = 0; i < on_faces.size(); ++i) faces.col(static_cast<Eigen::Index>(i)) = on_faces[i];
  const auto carryFaces = [&](double cell_mm, double smoothing_cell_mm) {
    LatticeSettings settings;
    settings.smoothing_cell_mm = smoothing_cell_mm;
    TissueLattice lattice = makeLattice(rod, true, settings, nullptr, cell_mm);
    lattice.update({Eigen::Isometry3d::Identity(), push});
    Eigen::Matrix3Xd carried;
    lattice.carry(lattice.bind(faces), carried);
    return carried;
  };
  const Eigen::Matrix3Xd coarse = carryFaces(2.0, 0.0), fine = carryFaces(1.0, 2.0), fine_same_passes = carryFaces(1.0, 0.0);
  const double scaled = (fine - coarse).colwise().norm().maxCoeff();
  const double unscaled = (fine_same_passes - coarse).colwise().norm().maxCoeff();
  std::printf("faces' largest difference from the 2 mm lattice's: %.3f mm with the passes scaled, %.3f mm without\n",
              scaled, unscaled);
  EXPECT_LT(scaled, 0.5 * unscaled);
}

// Pinched between two bones, the rod has no free side: it thickens about its middle, as a free
// rod does.
TEST(TissueLattice, ACompressedRodBetweenTwoBonesThickensAboutItsMiddle) {
  const auto [free_rod, pinched] = compressRodFreeAndWith(FloorAndCeilingAroundTheRod{});
  const double thickening_mm = free_rod.upper_mm - free_rod.lower_mm - 12.0;
  ASSERT_GT(thickening_mm, 1.0);
  EXPECT_NEAR(pinched.lower_mm, free_rod.lower_mm, 0.05 * thickening_mm);
  EXPECT_NEAR(pinched.upper_mm, free_rod.upper_mm, 0.05 * thickening_mm);
}

TEST(TissueLattice, ASurfaceLiesOnABoneByItsClearanceAgainstTheHalfThickness) {
  EXPECT_EQ(calcOnBoneWeight(-1.0, 5.0), 1.0);
  EXPECT_EQ(calcOnBoneWeight(0.0, 5.0), 1.0);
  EXPECT_DOUBLE_EQ(calcOnBoneWeight(2.5, 5.0), 0.5);
  EXPECT_EQ(calcOnBoneWeight(5.0, 5.0), 0.0);
  EXPECT_EQ(calcOnBoneWeight(std::numeric_limits<double>::infinity(), 5.0), 0.0);
  EXPECT_EQ(calcOnBoneWeight(1.0, 0.0), 0.0) << "no thickness, nothing to anchor";
  EXPECT_GT(calcOnBoneWeight(1.0, 5.0), calcOnBoneWeight(2.0, 5.0));
}

// The rod arches over a joint 30 mm below its middle, and its insertion bone turns about the
// joint towards its origin: weights by angle about the joint keep the blend from folding up to
// the turn calcFoldFreeTurn promises; weights by distance fold it there.
TEST(TissueLattice, WeightsByAngleAboutTheJointDoNotFoldWhereWeightsByDistanceDo) {
  const Rod rod;
  const Eigen::Vector3d joint(0, -30, 0);
  LatticeSettings by_angle;
  by_angle.joint_centre_mm = joint;
  const double alpha = calcAttachmentAngle(rod.field.getCentres(), rod.attachments, joint);
  const double turn = 0.9 * calcFoldFreeTurn(alpha);
  ASSERT_GT(turn, 0.5);
  double least[2] = {};  // least blend J of each weighting, over both senses of the turn
  for (int weighting = 0; weighting < 2; ++weighting) {
    TissueLattice lattice = makeLattice(rod, false, weighting ? by_angle : LatticeSettings{});
    least[weighting] = 1e300;
    for (double sense : {1.0, -1.0}) {
      lattice.update({Eigen::Isometry3d::Identity(), test::makeRotationAbout(joint, Eigen::Vector3d::UnitZ(), sense * turn)});
      least[weighting] = std::min(least[weighting], lattice.getBlendVolumeChanges().minCoeff());
    }
  }
  EXPECT_LT(least[0], 0.0) << "by distance";
  EXPECT_GT(least[1], 0.0) << "by angle";
}

/// The rod's bones turn apart (−0.5 rad about the joint below it) or together (+0.5 rad).
TEST(TissueLattice, AStretchedMuscleIsTautAndTakesTheChordsAShortenedOneKeepsTheArcs) {
  const Rod rod;
  const Eigen::Vector3d joint(0, -30, 0);
  LatticeSettings by_angle;
  by_angle.joint_centre_mm = joint;
  TissueLattice lattice = makeLattice(rod, true, by_angle);
  const LatticeBinding middle = lattice.bind(Eigen::Matrix3Xd(Eigen::Vector3d(0, 0, 0)));
  Eigen::Matrix3Xd on_arc, taut;
  lattice.carryTaut(middle, taut);
  EXPECT_EQ(lattice.getStretch(), 1.0);
  EXPECT_EQ(lattice.getTautFraction(), 0.0);

  lattice.update({Eigen::Isometry3d::Identity(), test::makeRotationAbout(joint, Eigen::Vector3d::UnitZ(), 0.5)});
  EXPECT_LT(lattice.getStretch(), 1.0);
  EXPECT_EQ(lattice.getTautFraction(), 0.0);
  lattice.carry(middle, on_arc);
  lattice.carryTaut(middle, taut);
  EXPECT_EQ(taut, on_arc) << "a shortened muscle keeps the map";

  lattice.update({Eigen::Isometry3d::Identity(), test::makeRotationAbout(joint, Eigen::Vector3d::UnitZ(), -0.5)});
  EXPECT_GT(lattice.getStretch(), 1.1);
  EXPECT_EQ(lattice.getTautFraction(), 1.0);
  lattice.carry(middle, on_arc);
  lattice.carryTaut(middle, taut);
  // The rod's middle turns about the joint on its arc (30 mm away) in the map, and towards the
  // chord of its places on the two bones in the taut map: 30 cos(0.25) mm away when its
  // weights are equal; not quite, as its weights are not (the rod's areas differ), so > 0.5 mm closer.
  EXPECT_NEAR((on_arc.col(0) - joint).norm(), 30.0, 0.5);
  EXPECT_LT((taut.col(0) - joint).norm(), (on_arc.col(0) - joint).norm() - 0.5);
  EXPECT_GT((taut.col(0) - joint).norm(), 30.0 * std::cos(0.25) - 0.5);
}

/// Straight fibres filling the rod, a lattice cell apart: 7 × 5 of them, each of kRodFibrePoints
/// points from x = −36 to 36 mm.
constexpr int kRodFibres = 35, kRodFibrePoints = 37, kRodGuidePoints = kRodFibres * kRodFibrePoints;
Eigen::Matrix3Xd makeRodFibres() {
  Eigen::Matrix3Xd points(3, kRodGuidePoints);
  int column = 0;
  for (int y = -6; y <= 6; y += 2)
    for (int z = -4; z <= 4; z += 2)
      for (int j = 0; j < kRodFibrePoints; ++j) points.col(column++) = Eigen::Vector3d(-36.0 + 2.0 * j, y, z);
  return points;
}

/// The lift-off's tests turn the rod about a joint 30 mm below its middle, weights by angle about it.
const Eigen::Vector3d kRodJoint(0, -30, 0);
TissueLattice makeRodLatticeByAngle(const Rod& rod) {
  LatticeSettings by_angle;
  by_angle.joint_centre_mm = kRodJoint;
  return makeLattice(rod, true, by_angle);
}

/// The rod's middle, carried by a lattice whose bones turn together by +0.5 rad about the joint.
Eigen::Vector3d carryMiddleShortened(TissueLattice& lattice) {
  lattice.update({Eigen::Isometry3d::Identity(), test::makeRotationAbout(kRodJoint, Eigen::Vector3d::UnitZ(), 0.5)});
  Eigen::Matrix3Xd middle;
  lattice.carry(lattice.bind(Eigen::Matrix3Xd(Eigen::Vector3d(0, 0, 0))), middle);
  return middle.col(0);
}

TEST(TissueLattice, AShortenedRodLiftsOffTheJointTowardsItsStrings) {
  const Rod rod;
  const Eigen::Vector3d& joint = kRodJoint;
  TissueLattice on_arcs = makeRodLatticeByAngle(rod), lifted = makeRodLatticeByAngle(rod);
  const Eigen::Matrix3Xd fibres = makeRodFibres();
  EXPECT_EQ(lifted.setLiftOffGuides(fibres, kRodFibrePoints, std::vector<bool>(kRodGuidePoints, false)), 0.0) << "held at the ends";
  EXPECT_EQ(lifted.getNodes(), on_arcs.getNodes()) << "nothing lifts at rest";
  EXPECT_EQ(lifted.getLiftFraction(), 0.0);

  const Eigen::Vector3d arc = carryMiddleShortened(on_arcs), up = carryMiddleShortened(lifted);
  ASSERT_GT(lifted.getLiftFraction(), 0.9);
  // The guides' own largest rise, from the fibres the map carries.
  Eigen::Matrix3Xd carried;
  std::vector<int> ties(kRodGuidePoints, -1);
  for (int f = 0; f < kRodFibres; ++f) {
    ties[static_cast<size_t>(kRodFibrePoints * f)] = 0;
    ties[static_cast<size_t>(kRodFibrePoints * (f + 1) - 1)] = 1;
  }
  on_arcs.carry(on_arcs.bind(fibres, ties), carried);
  double guide_max = 0.0;
  for (int f = 0; f < kRodFibres; ++f)
    guide_max = std::max(guide_max, calcLiftOffRisesSinceRest(carried.middleCols(kRodFibrePoints * f, kRodFibrePoints),
                                                              fibres.middleCols(kRodFibrePoints * f, kRodFibrePoints),
                                                              joint, Eigen::Vector3d::UnitZ(), 2.0)
                                        .colwise()
                                        .norm()
                                        .maxCoeff());
  ASSERT_GT(guide_max, 2.0);
  const double rise = (up - joint).norm() - (arc - joint).norm();
  EXPECT_GT(rise, 0.5 * guide_max) << "the middle rises away from the joint";
  EXPECT_NEAR((up - arc).norm(), rise, 0.05 * rise) << "straight away from it";
  EXPECT_LE(lifted.getLiftMax(), lifted.getLiftFraction() * guide_max + 1e-9) << "never beyond its strings";
}

TEST(TissueLattice, TheJointTurnsWithTheInsertionBoneFromTheOriginBone) {
  const Rod rod;
  TissueLattice lattice = makeRodLatticeByAngle(rod);
  EXPECT_FALSE(lattice.getJointTurn()) << "no turn at rest";
  const Eigen::Isometry3d shift(Eigen::Translation3d(5.0, -2.0, 7.0));
  lattice.update({shift, shift * test::makeRotationAbout(kRodJoint, Eigen::Vector3d::UnitZ(), 0.5)});
  const std::optional<JointTurn> turn = lattice.getJointTurn();
  ASSERT_TRUE(turn);
  EXPECT_LT((turn->centre_mm - shift * kRodJoint).norm(), 1e-12) << "the centre moves with the origin bone";
  EXPECT_LT((turn->axis - Eigen::Vector3d::UnitZ()).norm(), 1e-12);
  EXPECT_FALSE(makeLattice(rod, true).getJointTurn()) << "no joint centre";
}

TEST(TissueLattice, VectorsSpreadLikeTheRisesAreAveragesOfTheirNeighbours) {
  const Rod rod;
  const TissueLattice lattice = makeRodLatticeByAngle(rod);
  const Eigen::Matrix3Xd fibres = makeRodFibres();
  std::vector<int> ties(kRodGuidePoints, -1);
  ties[0] = 0;
  const LatticeBinding points = lattice.bind(fibres, ties);
  // The same vector everywhere: each point gets it scaled by at most 1 (nodes no fibre reaches
  // count 0), and the middle of the rod nearly all of it.
  const Eigen::Vector3d up(0.0, 3.0, 0.0);
  const Eigen::Matrix3Xd spread = lattice.spreadLikeRises(points, up.replicate(1, kRodGuidePoints));
  EXPECT_EQ(spread.col(0), Eigen::Vector3d::Zero()) << "a point tied to a bone";
  for (int j = 1; j < kRodGuidePoints; ++j) {
    EXPECT_LT((spread.col(j) - spread.col(j).dot(up) / up.squaredNorm() * up).norm(), 1e-12);
    EXPECT_LE(spread.col(j).norm(), up.norm() + 1e-12);
  }
  const int middle = (kRodFibres / 2) * kRodFibrePoints + kRodFibrePoints / 2;
  EXPECT_NEAR(fibres.col(middle).norm(), 0.0, 1e-12);
  EXPECT_GT(spread.col(middle).norm(), 0.5 * up.norm());
  // Linear in the vectors, and sizes must match.
  EXPECT_LT((lattice.spreadLikeRises(points, -2.0 * up.replicate(1, kRodGuidePoints)) + 2.0 * spread).norm(), 1e-9);
  EXPECT_THROW(lattice.spreadLikeRises(points, up.replicate(1, 3)), std::invalid_argument);
}

TEST(TissueLattice, ARodLyingOnItsOriginBoneIsHeldWhereItLeavesItAndLiftsLess) {
  const Rod rod;
  const Eigen::Vector3d& joint = kRodJoint;
  TissueLattice held_at_ends = makeRodLatticeByAngle(rod), held_on_bone = makeRodLatticeByAngle(rod);
  const Eigen::Matrix3Xd fibres = makeRodFibres();
  std::vector<bool> on_bone(kRodGuidePoints, false);
  for (int j = 0; j < kRodGuidePoints; ++j) on_bone[static_cast<size_t>(j)] = fibres(0, j) <= -12.0;
  held_at_ends.setLiftOffGuides(fibres, kRodFibrePoints, std::vector<bool>(kRodGuidePoints, false));
  const double pulley = held_on_bone.setLiftOffGuides(fibres, kRodFibrePoints, on_bone);
  // w₁ at x = −12 mm: every fibre's last point on the bone, at the same angle about the joint.
  const Eigen::VectorXd w = calcJointAngleBlendWeights(Eigen::Matrix3Xd(Eigen::Vector3d(-12, 0, 0)),
                                                       rod.field.getCentres(), rod.attachments, joint)
                                .row(1)
                                .transpose();
  EXPECT_GT(pulley, 0.0);
  EXPECT_NEAR(pulley, w[0], 0.05);
  const Eigen::Vector3d ends = carryMiddleShortened(held_at_ends), bone = carryMiddleShortened(held_on_bone);
  EXPECT_GT(held_on_bone.getLiftMax(), 0.0);
  EXPECT_LT((bone - joint).norm(), (ends - joint).norm() - 0.1);
}

TEST(TissueLattice, TheLiftOffNeedsTwoBonesAJointCentreAndWholeFibres) {
  const Rod rod;
  TissueLattice by_distance = makeLattice(rod, true);
  const Eigen::Matrix3Xd fibres = makeRodFibres();
  EXPECT_THROW(by_distance.setLiftOffGuides(fibres, kRodFibrePoints, std::vector<bool>(kRodGuidePoints, false)), std::invalid_argument);
  TissueLattice lattice = makeRodLatticeByAngle(rod);
  EXPECT_THROW(lattice.setLiftOffGuides(fibres, kRodFibrePoints - 1, std::vector<bool>(kRodGuidePoints, false)), std::invalid_argument);
  EXPECT_THROW(lattice.setLiftOffGuides(fibres, kRodFibrePoints, std::vector<bool>(kRodGuidePoints - 1, false)), std::invalid_argument);
  EXPECT_THROW(lattice.setLiftOffGuides(fibres, 1, std::vector<bool>(kRodGuidePoints, false)), std::invalid_argument);
}

TEST(TissueLattice, ACommonRigidMotionIsNoStretch) {
  const Rod rod;
  LatticeSettings by_angle;
  by_angle.joint_centre_mm = Eigen::Vector3d(0, -30, 0);
  TissueLattice lattice = makeLattice(rod, true, by_angle);
  const Eigen::Isometry3d common = test::makeRotationAbout(Eigen::Vector3d(5, 7, -3), Eigen::Vector3d(1, 2, 3), 0.9);
  lattice.update({common, common});
  EXPECT_NEAR(lattice.getStretch(), 1.0, 1e-12);
  EXPECT_LT(lattice.getTautFraction(), 1e-20);
}

TEST(TissueLattice, PointsOutsideTheCoveredCellsAreRefused) {
  const Rod rod;
  const TissueLattice lattice = makeLattice(rod, false);
  EXPECT_THROW(lattice.bind(Eigen::Matrix3Xd::Constant(3, 1, 500.0)), std::invalid_argument);
}

}  // namespace
}  // namespace rbfmuscle
