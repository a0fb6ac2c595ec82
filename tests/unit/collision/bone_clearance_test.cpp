// SPDX-License-Identifier: Apache-2.0
// BoneClearance: the nearest of several posed bones, culling by region, and the exact way out
// of a point deep inside a bone.
#include "collision/bone_clearance.h"
#include "geometry/mesh_distance.h"
#include "geometry/test_meshes.h"

#include <Eigen/Geometry>
#include <gtest/gtest.h>

namespace rbfmuscle {
namespace {

ClearanceBone makeSphereBone(const std::string& name, double radius_mm) {
  return ClearanceBone{name, std::make_shared<BoneDistanceGrid>(test::makeIcosphere(radius_mm, 4))};
}

TEST(BoneClearance, IsTheSignedDistanceToTheNearestPosedBone) {
  BoneClearance clearance({makeSphereBone("a", 10.0), makeSphereBone("b", 10.0)});
  const Eigen::AlignedBox3d everywhere(Eigen::Vector3d::Constant(-100), Eigen::Vector3d::Constant(100));
  clearance.setPoses({Eigen::Isometry3d(Eigen::Translation3d(-15, 0, 0)), Eigen::Isometry3d(Eigen::Translation3d(15, 0, 0))},
                     everywhere);
  EXPECT_EQ(clearance.countNearBones(), 2);
  // Midway: 5 mm from both surfaces; 2 mm outside b; 3 mm inside a.
  EXPECT_NEAR(clearance.sample(Eigen::Vector3d(0, 0, 0)).value_mm, 5.0, 0.05);
  const ClearanceSample near_b = clearance.sample(Eigen::Vector3d(3, 0, 0));
  EXPECT_NEAR(near_b.value_mm, 2.0, 0.05);
  EXPECT_NEAR(near_b.gradient.x(), -1.0, 0.05) << "away from b's centre, in the muscle frame";
  EXPECT_NEAR(clearance.sample(Eigen::Vector3d(-8, 0, 0)).value_mm, -3.0, 0.05);
}

TEST(BoneClearance, ABoneWhosePosedBoxMissesTheRegionIsNotSampled) {
  BoneClearance clearance({makeSphereBone("a", 10.0)});
  clearance.setPoses({Eigen::Isometry3d(Eigen::Translation3d(500, 0, 0))},
                     Eigen::AlignedBox3d(Eigen::Vector3d::Constant(-50), Eigen::Vector3d::Constant(50)));
  EXPECT_EQ(clearance.countNearBones(), 0);
  EXPECT_FALSE(clearance.sample(Eigen::Vector3d::Zero()).near);
  EXPECT_EQ(clearance.calcValue(Eigen::Vector3d::Zero()), std::numeric_limits<double>::infinity());
}

TEST(BoneClearance, APointDeepInsideABoneKnowsItsExactWayOut) {
  BoneClearance clearance({makeSphereBone("big", 30.0)});  // band 6 mm < depth
  clearance.setPoses({Eigen::Isometry3d::Identity()},
                     Eigen::AlignedBox3d(Eigen::Vector3d::Constant(-50), Eigen::Vector3d::Constant(50)));
  const ClearanceSample deep = clearance.sample(Eigen::Vector3d(0, 0, 12));
  EXPECT_TRUE(deep.near);
  EXPECT_NEAR(deep.value_mm, -18.0, 0.1);
  EXPECT_NEAR(deep.gradient.z(), 1.0, 1e-2);
}

}  // namespace
}  // namespace rbfmuscle
