// SPDX-License-Identifier: Apache-2.0
#include "fibres/line_of_action.h"

#include "fibre_test_shapes.h"

#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

namespace rbfmuscle {
namespace {

TEST(LineOfAction, ViaPointsGoByArcLengthToTheNearerEndsBone) {
  Eigen::Matrix3Xd p(3, 4);
  p << -30, -20, 10, 30, 0, 5, 5, 0, 0, 0, 0, 0;
  // Half the rest length ≈ 31.6 mm: the second point (11.2 mm along) on bone 0, the third (41.2) on bone 1.
  EXPECT_EQ(makeViaPointPath(p, 0, 1).bones, (std::vector<int>{0, 0, 1, 1}));
  EXPECT_EQ(makeViaPointPath(p, 1, 0).bones, (std::vector<int>{1, 1, 0, 0}));
}

TEST(LineOfAction, LengthOfAMovedPathIsAnalytic) {
  Eigen::Matrix3Xd p(3, 3);
  p << -30, 0, 30, 0, 5, 0, 0, 0, 0;
  const ViaPointPath path{p, {0, 0, 1}, {}};
  EXPECT_NEAR(calcPathLength(path, {Eigen::Isometry3d::Identity(), Eigen::Isometry3d::Identity()}),
              2 * std::sqrt(900.0 + 25.0), 1e-12);
  // Bone 1 turned 90° about z through the origin: (30,0,0) → (0,30,0); via point stays.
  const Eigen::Isometry3d turn = test::makeTurn(Eigen::Vector3d::Zero(), Eigen::Vector3d::UnitZ(), M_PI / 2);
  EXPECT_NEAR(calcPathLength(path, {Eigen::Isometry3d::Identity(), turn}), std::sqrt(925.0) + 25.0, 1e-12);
  // A common rigid motion leaves the length unchanged.
  Eigen::Isometry3d x = test::makeTurn(Eigen::Vector3d(1, 2, 3), Eigen::Vector3d(0.3, 1, -0.2), 1.1);
  x.translation() += Eigen::Vector3d(100, 0, -40);
  EXPECT_NEAR(calcPathLength(path, {x, x}), 2 * std::sqrt(925.0), 1e-9);
}

TEST(LineOfAction, ConditionalPointIsOnThePathOnlyWithinItsRange) {
  Eigen::Matrix3Xd p(3, 3);
  p << -30, 0, 30, 0, 5, 0, 0, 0, 0;
  const ViaPointPath path{p, {0, 0, 1}, {{-1, 0, 0}, {1, 0.0, 0.5}, {-1, 0, 0}}};
  const std::vector<Eigen::Isometry3d> rest(2, Eigen::Isometry3d::Identity());
  EXPECT_NEAR(calcPathLength(path, rest, Eigen::Vector2d(9.0, 0.25)), 2 * std::sqrt(925.0), 1e-12);
  EXPECT_NEAR(calcPathLength(path, rest, Eigen::Vector2d(9.0, 0.5)), 2 * std::sqrt(925.0), 1e-12);  // range closed
  EXPECT_NEAR(calcPathLength(path, rest, Eigen::Vector2d(9.0, 0.51)), 60.0, 1e-12);
  EXPECT_THROW(calcPathLength(path, rest, Eigen::VectorXd::Zero(1)), std::invalid_argument);  // no coordinate 1
  ViaPointPath short_conditions = path;
  short_conditions.conditions.pop_back();
  EXPECT_THROW(calcPathLength(short_conditions, rest, Eigen::Vector2d(0, 0)), std::invalid_argument);
}

TEST(LineOfAction, BadInputIsRefused) {
  EXPECT_THROW(makeViaPointPath(Eigen::Matrix3Xd::Zero(3, 1), 0, 1), std::invalid_argument);
  EXPECT_THROW(makeViaPointPath(Eigen::Matrix3Xd::Zero(3, 2), -1, 1), std::invalid_argument);
  const ViaPointPath path{Eigen::Matrix3Xd::Zero(3, 2), {0, 3}, {}};
  EXPECT_THROW(calcPathLength(path, {Eigen::Isometry3d::Identity()}), std::invalid_argument);
}

TEST(LineOfAction, ViaPointBodiesAreSplitFromTheirPoints) {
  const ViaPointText split = splitViaPointBodies(" 1 2 3 @ pelvis;4 5 6@femur_r ; 7 8 9 @femur_r;\n");
  EXPECT_EQ(split.bodies, (std::vector<std::string>{"pelvis", "femur_r", "femur_r"}));
  EXPECT_EQ(split.points, "1 2 3 ;4 5 6;7 8 9 ");
  const ViaPointText plain = splitViaPointBodies("1 2 3; 4 5 6");
  EXPECT_TRUE(plain.bodies.empty());
  EXPECT_EQ(plain.points, "1 2 3; 4 5 6");
}

TEST(LineOfAction, ViaPointBodiesMustBeGivenForEveryPoint) {
  const auto message = [](const std::string& text) {
    try {
      splitViaPointBodies(text);
    } catch (const std::invalid_argument& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_EQ(message("1 2 3 @ pelvis; 4 5 6"),
            "via point 2 '4 5 6' names no body; write 'x y z @ BODY' for every point or for none");
  EXPECT_EQ(message("1 2 3 @ ; 4 5 6 @ femur"), "via point 1 '1 2 3 @': expected one body name after '@'");
  EXPECT_EQ(message("1 2 3 @ femur r; 4 5 6 @ femur"), "via point 1 '1 2 3 @ femur r': expected one body name after '@'");
}

}  // namespace
}  // namespace rbfmuscle
