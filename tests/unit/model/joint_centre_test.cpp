// SPDX-License-Identifier: Apache-2.0
// The joint centre between two bodies from the skeleton's kinematics: the hip's three hinges
// meet at the centre in hip_r.urdf's header; the subject's OpenSim hip turns about its own
// centre; a single hinge gives the point of its axis nearest the given point.
#include <gtest/gtest.h>

#include <string>

#include "model/joint_centre.h"
#include "model/skeleton.h"
#include "model_test_support.h"

namespace rbfmuscle {
namespace {

const std::string kHipDir = std::string(RBFMUSCLE_SOURCE_DIR) + "/models/hip";
const Eigen::Vector3d kHipCentre_mm(143.225, 243.37, -432.499);  // hip_r.urdf's header (CT, mm)

TEST(JointCentre, HipsThreeHingesMeetAtTheUrdfsHipCentre) {
  const Skeleton skeleton = Skeleton::fromUrdf(kHipDir + "/hip_r.urdf");
  const std::optional<JointCentre> centre = findJointCentre(
      skeleton, skeleton.findBodyIndex("pelvis"), skeleton.findBodyIndex("femur_r"), Eigen::Vector3d(150, 250, -400));
  ASSERT_TRUE(centre);
  EXPECT_LT((centre->p_G_mm - kHipCentre_mm).norm(), 1e-6);
  EXPECT_LT(centre->residual_mm, 1e-6);  // rounding of coordinates of ~500 mm
  EXPECT_EQ(centre->coordinates, 3);
  EXPECT_TRUE(skeleton.getCoordinateValues().isZero(0.0));  // the run's skeleton did not move
}

TEST(JointCentre, SubjectsOpenSimHipTurnsAboutAPointNearTheLandmark) {
  Skeleton skeleton = Skeleton::fromFile(kHipDir + "/osim/LHDL_hip_r.osim");
  skeleton.setRestCoordinateValues(skeleton.solveBodiesAtGround());
  const std::optional<JointCentre> centre = findJointCentre(
      skeleton, skeleton.findBodyIndex("pelvis"), skeleton.findBodyIndex("femur_r"), Eigen::Vector3d(150, 250, -400));
  ASSERT_TRUE(centre);
  EXPECT_LT(centre->residual_mm, 1e-6);  // a ball joint: one point stays
  EXPECT_LT((centre->p_G_mm - kHipCentre_mm).norm(), 2.0) << centre->p_G_mm.transpose();
}

TEST(JointCentre, SingleHingeGivesThePointOfItsAxisNearestTheGivenPoint) {
  test::TempFile urdf("single_hinge.urdf");
  urdf.write(R"(<robot name="hinge">
  <link name="a"><inertial><mass value="1"/><inertia ixx="1" ixy="0" ixz="0" iyy="1" iyz="0" izz="1"/></inertial></link>
  <link name="b"><inertial><mass value="1"/><inertia ixx="1" ixy="0" ixz="0" iyy="1" iyz="0" izz="1"/></inertial></link>
  <joint name="knee" type="revolute"><parent link="a"/><child link="b"/>
    <origin xyz="0.01 0.02 0.03" rpy="0 0 0"/><axis xyz="0 0 1"/><limit lower="-3" upper="3" effort="1" velocity="1"/>
  </joint>
</robot>)");
  const Skeleton skeleton = Skeleton::fromUrdf(urdf.path());
  const std::optional<JointCentre> centre =
      findJointCentre(skeleton, skeleton.findBodyIndex("a"), skeleton.findBodyIndex("b"), Eigen::Vector3d(50, -40, 77));
  ASSERT_TRUE(centre);
  EXPECT_LT((centre->p_G_mm - Eigen::Vector3d(10, 20, 77)).norm(), 1e-4) << centre->p_G_mm.transpose();
  EXPECT_EQ(centre->coordinates, 1);
}

TEST(JointCentre, NoneBetweenABodyAndItself) {
  const Skeleton skeleton = Skeleton::fromUrdf(kHipDir + "/hip_r.urdf");
  const int pelvis = skeleton.findBodyIndex("pelvis");
  EXPECT_FALSE(findJointCentre(skeleton, pelvis, pelvis, Eigen::Vector3d::Zero()));
  EXPECT_THROW(findJointCentre(skeleton, pelvis, 99, Eigen::Vector3d::Zero()), std::invalid_argument);
}

}  // namespace
}  // namespace rbfmuscle
