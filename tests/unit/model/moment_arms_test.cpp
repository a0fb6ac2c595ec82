// SPDX-License-Identifier: Apache-2.0
// Moment arms by central differences on the hip skeleton: a line from the pelvis to a femur
// point against the analytic −∂l/∂q about the URDF's flexion axis, and the coordinate lists.
#include <gtest/gtest.h>

#include <string>

#include "model/moment_arms.h"
#include "model/skeleton.h"
#include "model_test_support.h"

namespace rbfmuscle {
namespace {

const std::string kUrdf = std::string(RBFMUSCLE_SOURCE_DIR) + "/models/hip/hip_r.urdf";
// The flexion axis Z of the pelvis frame and the hip centre in CT (hip_r.urdf's header, mm).
const Eigen::Vector3d kFlexionAxis(-0.9924778435393231, 0.11879490607095902, 0.029588855590025755);
const Eigen::Vector3d kHipCentre_mm(143.225, 243.37, -432.499);

TEST(MomentArms, LineToTheFemurHasTheAnalyticArmAboutTheFlexionAxis) {
  const Skeleton skeleton = Skeleton::fromUrdf(kUrdf);
  const int pelvis = skeleton.findBodyIndex("pelvis"), femur = skeleton.findBodyIndex("femur_r");
  const int flexion = skeleton.findCoordinateIndex("hip_flexion_r");
  const Eigen::Vector3d origin_G(180, 300, -330);  // on the pelvis
  const Eigen::Vector3d insertion_B = skeleton.getBodyTransform(femur).inverse() * Eigen::Vector3d(130, 270, -480);
  MomentArms arms(skeleton, {flexion});
  const auto measure = [&](const Skeleton& posed, const Eigen::VectorXd&) {
    Eigen::VectorXd l(1);
    l[0] = (posed.getBodyTransform(femur) * insertion_B - posed.getBodyTransform(pelvis) * origin_G).norm();
    return l;
  };
  arms.update(skeleton.getCoordinateValues(), measure);  // at rest, q = 0
  const Eigen::Vector3d insertion_G = skeleton.getBodyTransform(femur) * insertion_B;
  const Eigen::Vector3d along = (insertion_G - origin_G).normalized();
  const double analytic = -along.dot(kFlexionAxis.cross(insertion_G - kHipCentre_mm));
  EXPECT_NEAR(arms.getArms(0)[0], analytic, 1e-3 * std::abs(analytic));
  // The run's skeleton is not moved by probing.
  EXPECT_TRUE(skeleton.getCoordinateValues().isZero(0.0));
}

TEST(MomentArms, AMeasurementThatChangesSizeIsRefused) {
  const Skeleton skeleton = Skeleton::fromUrdf(kUrdf);
  MomentArms arms(skeleton, {0});
  int calls = 0;
  EXPECT_THROW(arms.update(skeleton.getCoordinateValues(),
                           [&](const Skeleton&, const Eigen::VectorXd&) { return Eigen::VectorXd::Zero(++calls); }),
               std::invalid_argument);
}

TEST(CoordinateList, AllNamesOrNoneAndUnknownNamesListTheSkeletons) {
  const Skeleton skeleton = Skeleton::fromUrdf(kUrdf);
  EXPECT_TRUE(parseCoordinateList("", skeleton).empty());
  EXPECT_EQ(parseCoordinateList("all", skeleton), (std::vector<int>{0, 1, 2}));
  EXPECT_EQ(parseCoordinateList(" hip_rotation_r , hip_flexion_r,hip_flexion_r", skeleton),
            (std::vector<int>{skeleton.findCoordinateIndex("hip_flexion_r"), skeleton.findCoordinateIndex("hip_rotation_r")}));
  test::expectModelError([&] { parseCoordinateList("hip_flexion", skeleton); },
                         {"no coordinate 'hip_flexion'", "hip_flexion_r, hip_adduction_r, hip_rotation_r", "'all'"});
}

}  // namespace
}  // namespace rbfmuscle
