// SPDX-License-Identifier: Apache-2.0
// Lift-off: a string's distance from the axis is its hull's, and a shortened string rises to it;
// a fibre's sag below its string, and a fibre that sags more than at rest rises by the difference.
#include "dynamics/joint_lift_off.h"

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>

namespace rbfmuscle {
namespace {

Eigen::Vector3d polar(double radius_mm, double angle_rad, double z_mm = 0.0) {
  return Eigen::Vector3d(radius_mm * std::cos(angle_rad), radius_mm * std::sin(angle_rad), z_mm);
}

TEST(StringDistances, ADentLiesUnderTheLineBetweenEndsThatClearTheAxis) {
  Eigen::Matrix2Xd points(2, 3);
  points << -10, 0, 10,  //
            10, 5, 10;
  const Eigen::VectorXd s = calcStringDistances(points);
  EXPECT_NEAR(s[0], std::hypot(10.0, 10.0), 1e-12);
  EXPECT_NEAR(s[1], 10.0, 1e-12) << "the dent's ray leaves the hull through the line y = 10";
  EXPECT_NEAR(s[2], std::hypot(10.0, 10.0), 1e-12);
}

TEST(StringDistances, AFibreWoundOnTheDrumStaysOnIt) {
  Eigen::Matrix2Xd points(2, 7);
  for (int j = 0; j < 7; ++j) points.col(j) = polar(12.0, 0.6 * j).head<2>();  // 3.6 rad: more than half a turn
  const Eigen::VectorXd s = calcStringDistances(points);
  for (int j = 0; j < 7; ++j) EXPECT_NEAR(s[j], 12.0, 1e-9) << "point " << j;
}

TEST(StringDistances, APointOnTheAxisAndNonFiniteInput) {
  Eigen::Matrix2Xd points(2, 2);
  points << 0, 5,  //
            0, 0;
  EXPECT_EQ(calcStringDistances(points)[0], 0.0);
  points(0, 1) = std::nan("");
  EXPECT_THROW(calcStringDistances(points), std::invalid_argument);
}

/// A string wound over a drum about z: from (−20, 10), through (0, 10), to (20, 10) at rest, 10
/// mm from the axis at its middle. The drum map turns each point by its share of the turn, so
/// the insertion end comes closer to the origin end along its arc by θ, and the middle turns
/// the same way by θ/2, 10 mm from the axis.
struct Drum {
  double end_radius = std::hypot(20.0, 10.0), end_angle = std::atan2(10.0, 20.0);
  Eigen::Matrix3Xd rest() const {
    Eigen::Matrix3Xd p(3, 3);
    p << -20, 0, 20,  //
         10, 10, 10,  //
         0, 3, 6;     // the heights along the axis do not matter
    return p;
  }
  Eigen::Matrix3Xd shortened(double theta) const {
    Eigen::Matrix3Xd p = rest();
    p.col(1) = polar(10.0, M_PI / 2 + theta / 2, 3.0);
    p.col(2) = polar(end_radius, end_angle + theta, 6.0);
    return p;
  }
};

TEST(LiftOffRises, AShortenedStringRisesToTheLineBetweenItsEnds) {
  const Drum drum;
  const double theta = 0.7;
  const Eigen::Matrix3Xd now = drum.shortened(theta);
  const Eigen::Matrix3Xd rises = calcLiftOffRisesSinceRest(now, drum.rest(), Eigen::Vector3d::Zero(),
                                                           Eigen::Vector3d::UnitZ(), 1.0);
  // The ends are apart by π − 2 end_angle − θ seen from the axis; their chord passes at
  // R cos(half of that), and the middle lies on its normal.
  const double string_mm = drum.end_radius * std::cos(0.5 * (M_PI - 2.0 * drum.end_angle - theta));
  const Eigen::Vector3d lifted = now.col(1) + rises.col(1);
  EXPECT_NEAR(lifted.head<2>().norm(), string_mm, 1e-9);
  EXPECT_NEAR(lifted.z(), 3.0, 1e-12) << "straight away from the axis";
  EXPECT_NEAR(std::atan2(lifted.y(), lifted.x()), M_PI / 2 + theta / 2, 1e-12);
  EXPECT_NEAR(rises.col(0).norm(), 0.0, 1e-12) << "the held end";
  EXPECT_NEAR(rises.col(2).norm(), 0.0, 1e-12) << "the insertion end";
}

TEST(LiftOffRises, NothingRisesAtRestUnderATurnAboutTheAxisOrWhereTheStringComesCloser) {
  const Drum drum;
  const Eigen::Vector3d axis = Eigen::Vector3d::UnitZ();
  EXPECT_EQ(calcLiftOffRisesSinceRest(drum.rest(), drum.rest(), Eigen::Vector3d::Zero(), axis, 1.0).norm(), 0.0);
  const Eigen::Matrix3Xd turned = Eigen::AngleAxisd(1.1, axis).toRotationMatrix() * drum.rest();
  EXPECT_LT(calcLiftOffRisesSinceRest(turned, drum.rest(), Eigen::Vector3d::Zero(), axis, 1.0).norm(), 1e-12);
  const Eigen::Matrix3Xd lengthened = drum.shortened(-0.3);
  EXPECT_LT(calcLiftOffRisesSinceRest(lengthened, drum.rest(), Eigen::Vector3d::Zero(), axis, 1.0).norm(), 1e-12);
}

TEST(LiftOffRises, FadeNearTheAxisAndRefuseBadInput) {
  const Drum drum;
  const Eigen::Vector3d axis = Eigen::Vector3d::UnitZ();
  const Eigen::Matrix3Xd now = drum.shortened(0.7);
  const double full = calcLiftOffRisesSinceRest(now, drum.rest(), Eigen::Vector3d::Zero(), axis, 1.0).col(1).norm();
  // The middle's rest string lies 10 mm away: a fade of 20 mm scales its rise by smoothstep(½) = ½.
  EXPECT_NEAR(calcLiftOffRisesSinceRest(now, drum.rest(), Eigen::Vector3d::Zero(), axis, 20.0).col(1).norm(),
              0.5 * full, 1e-12);
  EXPECT_THROW(calcLiftOffRisesSinceRest(now, drum.rest(), Eigen::Vector3d::Zero(), 2.0 * axis, 1.0),
               std::invalid_argument);
  EXPECT_THROW(calcLiftOffRisesSinceRest(now, drum.rest(), Eigen::Vector3d::Zero(), axis, 0.0), std::invalid_argument);
  EXPECT_THROW(calcLiftOffRisesSinceRest(now.leftCols(2), drum.rest(), Eigen::Vector3d::Zero(), axis, 1.0),
               std::invalid_argument);
}

TEST(StringSags, ADentSagsByItsDistanceToItsStringAndNoFurtherThanItMoves) {
  Eigen::Matrix2Xd points(2, 3);
  points << -10, 0, 10,  //
            10, 5, 10;
  const Eigen::VectorXd sags = calcStringSags(points);
  EXPECT_NEAR(sags[0], 0.0, 1e-12);
  EXPECT_NEAR(sags[1], 5.0, 1e-12) << "below the line y = 10 between the ends";
  EXPECT_NEAR(sags[2], 0.0, 1e-12);
  Eigen::Matrix2Xd moved = points;
  moved.col(1) += Eigen::Vector2d(3.0, 0.4);
  EXPECT_LE(std::abs(calcStringSags(moved)[1] - sags[1]), 0.5 + 1e-12) << "a distance: 1-Lipschitz in the point";
}

TEST(StringSags, AFibreOnItsStringOrAlongARayDoesNotSag) {
  Eigen::Matrix2Xd wound(2, 7);
  for (int j = 0; j < 7; ++j) wound.col(j) = polar(12.0, 0.6 * j).head<2>();  // more than half a turn
  EXPECT_LT(calcStringSags(wound).cwiseAbs().maxCoeff(), 1e-9);
  // Points on a line through the axis have no string: nothing sags.
  Eigen::Matrix2Xd radial(2, 3);
  radial << 1, 3, 2,  //
            1, 3, 2;
  EXPECT_EQ(calcStringSags(radial), Eigen::VectorXd::Zero(3));
  radial(0, 1) = std::nan("");
  EXPECT_THROW(calcStringSags(radial), std::invalid_argument);
}

TEST(SagRises, AFibreSaggingMoreThanAtRestRisesByTheDifference) {
  const Drum drum;  // its middle lies on the line between its ends at rest: no sag
  const double theta = 0.7;
  const Eigen::Matrix3Xd now = drum.shortened(theta);
  const Eigen::Vector3d axis = Eigen::Vector3d::UnitZ();
  const Eigen::Matrix3Xd rises = calcSagRisesSinceRest(now, drum.rest(), Eigen::Vector3d::Zero(), axis, 1.0);
  // The middle lies on the normal of its ends' chord through the axis, so it rises onto the chord.
  const double string_mm = drum.end_radius * std::cos(0.5 * (M_PI - 2.0 * drum.end_angle - theta));
  const Eigen::Vector3d lifted = now.col(1) + rises.col(1);
  EXPECT_NEAR(lifted.head<2>().norm(), string_mm, 1e-9);
  EXPECT_NEAR(lifted.z(), 3.0, 1e-12) << "straight away from the axis";
  EXPECT_NEAR(std::atan2(lifted.y(), lifted.x()), M_PI / 2 + theta / 2, 1e-12);
  EXPECT_NEAR(rises.col(0).norm() + rises.col(2).norm(), 0.0, 1e-12) << "the ends lie on the string";
  // A fibre that sagged 2 mm at rest rises by its sag beyond that.
  Eigen::Matrix3Xd dented = drum.rest();
  dented(1, 1) -= 2.0;
  const Eigen::Matrix3Xd from_dented = calcSagRisesSinceRest(now, dented, Eigen::Vector3d::Zero(), axis, 1.0);
  EXPECT_NEAR(from_dented.col(1).norm(), rises.col(1).norm() - 2.0, 1e-9);
  // Turned about the axis, a fibre sags as at rest, and one that sags less does not sink.
  const Eigen::Matrix3Xd turned = Eigen::AngleAxisd(1.1, axis).toRotationMatrix() * dented;
  EXPECT_LT(calcSagRisesSinceRest(turned, dented, Eigen::Vector3d::Zero(), axis, 1.0).norm(), 1e-12);
  EXPECT_EQ(calcSagRisesSinceRest(drum.rest(), dented, Eigen::Vector3d::Zero(), axis, 1.0).norm(), 0.0);
}

TEST(SagRises, FadeNearTheAxisAndRefuseBadInput) {
  const Drum drum;
  const Eigen::Vector3d axis = Eigen::Vector3d::UnitZ();
  const Eigen::Matrix3Xd now = drum.shortened(0.7);
  const double full = calcSagRisesSinceRest(now, drum.rest(), Eigen::Vector3d::Zero(), axis, 1.0).col(1).norm();
  // The middle lies 10 mm from the axis: a fade of 20 mm scales its rise by smoothstep(½) = ½.
  EXPECT_NEAR(calcSagRisesSinceRest(now, drum.rest(), Eigen::Vector3d::Zero(), axis, 20.0).col(1).norm(), 0.5 * full,
              1e-12);
  EXPECT_THROW(calcSagRisesSinceRest(now, drum.rest(), Eigen::Vector3d::Zero(), 2.0 * axis, 1.0), std::invalid_argument);
  EXPECT_THROW(calcSagRisesSinceRest(now, drum.rest(), Eigen::Vector3d::Zero(), axis, 0.0), std::invalid_argument);
  EXPECT_THROW(calcSagRisesSinceRest(now.leftCols(2), drum.rest(), Eigen::Vector3d::Zero(), axis, 1.0),
               std::invalid_argument);
}

}  // namespace
}  // namespace rbfmuscle
