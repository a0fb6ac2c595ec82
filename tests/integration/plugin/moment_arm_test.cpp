// SPDX-License-Identifier: Apache-2.0
/// Moment arms through the host, on a simple shape: a 200 × 40 × 40 mm rod (models/shapes/rod.ply)
/// from an upper body to a lower one, hinged about z through a point 40 mm below the rod's axis.
/// The moment arm the component reports at a frame is checked against the central difference
/// of fibre lengths over separate frames at q ± δ (the frame depends on its poses only, so the
/// two agree to rounding), against a coarser difference, and the line of action's against the
/// analytic moment arm of a straight line from its via point.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>

#include "model/moment_arms.h"
#include "model/storage_file.h"
#include "support/run_host.h"

namespace rbfmuscle {
namespace {

namespace fs = std::filesystem;

constexpr double kStep = kMomentArmStep_rad;
const Eigen::Vector3d kHinge_mm(100, -40, 0);
const Eigen::Vector3d kOriginMean_mm(5, 0, 0), kInsertionMean_mm(195, 0, 0);

/// The line of action's via point, on the upper body although it lies halfway along the path
/// (where the path without bodies would put it on the lower one).
const Eigen::Vector3d kViaPoint_mm(100, 0, 0);

/// −∂l/∂q of the straight line from `fixed_mm` (on the upper body) to the insertion turned by q about z.
double calcStraightLineArm_mm(double q, const Eigen::Vector3d& fixed_mm = kOriginMean_mm) {
  const Eigen::Vector3d z = Eigen::Vector3d::UnitZ();
  const Eigen::Vector3d insertion = kHinge_mm + Eigen::AngleAxisd(q, z) * (kInsertionMean_mm - kHinge_mm);
  const Eigen::Vector3d along = (insertion - fixed_mm).normalized();
  return -along.dot(z.cross(insertion - kHinge_mm));
}

class MomentArmScene : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    // ctest runs each test of the suite as its own process, perhaps at once: one directory each.
    const std::string name = "moment_arm_" + std::to_string(::getpid());
    dir_ = fs::path(RBFMUSCLE_BINARY_DIR) / "test_out/plugin" / name;
    fs::remove_all(dir_);
    fs::create_directories(dir_);
    std::ofstream(dir_ / "hinge.urdf")
        << "<robot name=\"hinge\">\n"
        << "  <link name=\"upper\"><inertial><mass value=\"1\"/><inertia ixx=\"0.1\" ixy=\"0\" ixz=\"0\" iyy=\"0.1\" "
           "iyz=\"0\" izz=\"0.1\"/></inertial></link>\n"
        << "  <link name=\"lower\"><inertial><mass value=\"1\"/><inertia ixx=\"0.1\" ixy=\"0\" ixz=\"0\" iyy=\"0.1\" "
           "iyz=\"0\" izz=\"0.1\"/></inertial></link>\n"
        << "  <joint name=\"hinge\" type=\"revolute\"><parent link=\"upper\"/><child link=\"lower\"/>\n"
        << "    <origin xyz=\"0.1 -0.04 0\" rpy=\"0 0 0\"/><axis xyz=\"0 0 1\"/>\n"
        << "    <limit lower=\"-3.14\" upper=\"3.14\" effort=\"1\" velocity=\"1\"/></joint>\n"
        << "</robot>\n";
    std::ofstream mot(dir_ / "hinge.mot");
    mot << "hinge\nversion=1\nnRows=" << kAngles.size() << "\nnColumns=2\ninDegrees=no\nendheader\ntime\thinge\n";
    for (size_t i = 0; i < kAngles.size(); ++i) mot << 0.1 * static_cast<double>(i) << '\t' << kAngles[i] << '\n';
    mot.close();
    std::ofstream(dir_ / "model.xml")
        << "<?xml version=\"1.0\"?>\n<RBFMuscleModel version=\"1\" name=\"rod\">\n"
        << "  <skeleton file=\"hinge.urdf\"/>\n  <plugin file=\"librbfmuscle_plugin.so\"/>\n"
        << "  <motion file=\"hinge.mot\"/>\n  <components>\n    <RBFMuscle name=\"rod\">\n"
        << "      <mesh_file>" << RBFMUSCLE_SOURCE_DIR << "/models/shapes/rod.ply</mesh_file>\n"
        << "      <centres>300</centres>\n"
        << "      <origin_area>5 0 0; 5 10 10; 5 -10 10; 5 10 -10; 5 -10 -10</origin_area>\n"
        << "      <insertion_area>195 0 0; 195 10 10; 195 -10 10; 195 10 -10; 195 -10 -10</insertion_area>\n"
        << "      <moment_arms>hinge</moment_arms>\n"
        << "      <line_of_action>5 0 0 @ upper; 100 0 0 @ upper; 195 0 0 @ lower</line_of_action>\n"
        << "      <socket_origin_body>upper</socket_origin_body>\n      <socket_insertion_body>lower</socket_insertion_body>\n"
        << "    </RBFMuscle>\n  </components>\n</RBFMuscleModel>\n";
    const test::HostResult r = test::runHost("run '" + (dir_ / "model.xml").string() + "' -o '" + (dir_ / "out").string() +
                                                 "' --quiet",
                                             "plugin", name);
    ASSERT_EQ(r.exit_code, 0) << r.err;
    table_ = readStorage((dir_ / "out/outputs.sto").string());
  }
  static void TearDownTestSuite() { fs::remove_all(dir_); }

  static double value(size_t row, const std::string& column) {
    const int c = table_.findColumn("rod." + column);
    EXPECT_GE(c, 0) << column;
    return c < 0 ? NAN : table_.rows.at(row).at(static_cast<size_t>(c));
  }

  /// Frames: rest; 0.3 rad and either side of it by δ; 0.3 rad ± 0.025.
  static inline const std::vector<double> kAngles = {0.0, 0.3 - kStep, 0.3, 0.3 + kStep, 0.275, 0.325};
  static inline fs::path dir_;
  static inline StorageTable table_;
};

TEST_F(MomentArmScene, FibreArmsAreTheCentralDifferenceOfSeparateFrames) {
  ASSERT_EQ(table_.rows.size(), kAngles.size());
  const int fibres = 100;
  double mean = 0;
  for (int i = 0; i < fibres; ++i) {
    const std::string fibre = "_" + std::to_string(i);
    const double from_frames = (value(1, "fibre_length_mm" + fibre) - value(3, "fibre_length_mm" + fibre)) / (2 * kStep);
    EXPECT_NEAR(value(2, "fibre_moment_arm_hinge_mm" + fibre), from_frames, 1e-6) << "fibre " << i;
    mean += from_frames / fibres;
  }
  EXPECT_NEAR(value(2, "moment_arm_hinge_mm"), mean, 1e-6);
  // A coarser difference (±0.025 rad) differs by its own O(h²) error only (the rod, shortened
  // by the turn, lifts off the hinge by a fraction that changes fastest about here).
  const double coarse = (value(4, "fibre_length_mean_mm") - value(5, "fibre_length_mean_mm")) / 0.05;
  EXPECT_NEAR(value(2, "moment_arm_hinge_mm"), coarse, 0.5);
}

TEST_F(MomentArmScene, StraightFibresHaveTheLeverOfTheirHeightAtRest) {
  // At rest the fibres run straight along the rod, 20–60 mm above the hinge: each one's arm is
  // its height, and their mean the rod axis's 40 mm.
  EXPECT_NEAR(value(0, "moment_arm_hinge_mm"), calcStraightLineArm_mm(0.0), 1.0);
  for (int i = 0; i < 100; ++i) {
    const double arm = value(0, "fibre_moment_arm_hinge_mm_" + std::to_string(i));
    EXPECT_GT(arm, 20.0 - 1.0) << "fibre " << i;
    EXPECT_LT(arm, 60.0 + 1.0) << "fibre " << i;
  }
}

TEST_F(MomentArmScene, LineOfActionArmIsTheAnalyticArmOfItsLastSegment) {
  // Only the segment from the via point (upper body) to the insertion (lower body) changes length.
  // The reported arm is a central difference: its error is O(δ²), here up to about 1e-3 mm.
  for (size_t row = 0; row < kAngles.size(); ++row)
    EXPECT_NEAR(value(row, "line_of_action_moment_arm_hinge_mm"), calcStraightLineArm_mm(kAngles[row], kViaPoint_mm), 3e-3)
        << "frame " << row;
}

}  // namespace
}  // namespace rbfmuscle
