// SPDX-License-Identifier: Apache-2.0
#include "model/motion.h"

#include <gtest/gtest.h>

#include <cmath>

#include "model/skeleton.h"
#include "model_test_support.h"

namespace rbfmuscle {
namespace {

using test::expectModelError;
using test::TempFile;

constexpr double kDeg = 3.141592653589793238462643383279502884 / 180.0;
const std::string kHipDir = std::string(RBFMUSCLE_SOURCE_DIR) + "/models/hip";

class HipMotion : public ::testing::Test {
 protected:
  static void SetUpTestSuite() { skeleton_ = new Skeleton(Skeleton::fromUrdf(kHipDir + "/hip_r.urdf")); }
  static void TearDownTestSuite() { delete skeleton_; }
  static Motion load(const std::string& name) {
    return Motion::fromFile(kHipDir + "/motions/" + name, *skeleton_);
  }
  static Skeleton* skeleton_;
};
Skeleton* HipMotion::skeleton_ = nullptr;

TEST_F(HipMotion, Flexion0To80InDegreeStepsIsConvertedToRadians) {
  const Motion m = load("hip_flexion_0_80.mot");
  ASSERT_EQ(m.getNumFrames(), 81);
  const int flex = skeleton_->findCoordinateIndex("hip_flexion_r");
  for (int i = 0; i < m.getNumFrames(); ++i) {
    EXPECT_NEAR(m.getCoordinates(i)[flex], i * kDeg, 1e-15);
    EXPECT_NEAR(m.getTime(i), i / 30.0, 1e-15);
    EXPECT_EQ(m.getCoordinates(i).size(), 3);
  }
}

TEST_F(HipMotion, SingleAxisMotionsCoverTheirRanges) {
  struct Case {
    const char* file;
    const char* coordinate;
    int frames;
    double first_deg, last_deg;
  };
  for (const Case& c : {Case{"hip_adduction_0_30.mot", "hip_adduction_r", 31, 0, 30},
                        Case{"hip_rotation_m30_30.mot", "hip_rotation_r", 61, -30, 30},
                        Case{"hip_flexion_0_80_step10.mot", "hip_flexion_r", 9, 0, 80}}) {
    const Motion m = load(c.file);
    ASSERT_EQ(m.getNumFrames(), c.frames) << c.file;
    const int k = skeleton_->findCoordinateIndex(c.coordinate);
    EXPECT_NEAR(m.getCoordinates(0)[k], c.first_deg * kDeg, 1e-15) << c.file;
    EXPECT_NEAR(m.getCoordinates(c.frames - 1)[k], c.last_deg * kDeg, 1e-15) << c.file;
    for (int i = 0; i < m.getNumFrames(); ++i)  // the other coordinates stay at 0
      EXPECT_EQ(m.getCoordinates(i).cwiseAbs().sum(), std::abs(m.getCoordinates(i)[k])) << c.file;
  }
}

TEST_F(HipMotion, GaitCycleIsClosedAndInRange) {
  const Motion m = load("gait_cycle.mot");
  ASSERT_EQ(m.getNumFrames(), 101);
  const int flex = skeleton_->findCoordinateIndex("hip_flexion_r");
  double lo = 1e9, hi = -1e9;
  for (int i = 0; i < m.getNumFrames(); ++i) {
    lo = std::min(lo, m.getCoordinates(i)[flex]);
    hi = std::max(hi, m.getCoordinates(i)[flex]);
    EXPECT_LE(m.getCoordinates(i).tail(2).cwiseAbs().maxCoeff(), 5 * kDeg + 1e-12);
  }
  EXPECT_NEAR(lo, -10 * kDeg, 1e-12);
  EXPECT_NEAR(hi, 35 * kDeg, 1e-12);
  EXPECT_TRUE(m.getCoordinates(0).isApprox(m.getCoordinates(100), 1e-15));
}

TEST_F(HipMotion, RadiansFileIsNotConverted) {
  TempFile f("radians.mot");
  f.write("rad\ninDegrees=no\nendheader\ntime\thip_rotation_r\n0\t0.5\n");
  const Motion m = Motion::fromFile(f.path(), *skeleton_);
  EXPECT_EQ(m.getCoordinates(0)[skeleton_->findCoordinateIndex("hip_rotation_r")], 0.5);
  EXPECT_EQ(m.getPath(), f.path());
}

TEST_F(HipMotion, UnknownCoordinateNamesFileColumnAndCoordinates) {
  TempFile f("unknown.mot");
  f.write("m\ninDegrees=yes\nendheader\ntime\tknee_angle_r\n0\t1\n");
  expectModelError([&] { Motion::fromFile(f.path(), *skeleton_); },
                   {"motion " + f.path(), "column 'knee_angle_r' is not a coordinate of skeleton hip_r",
                    "(coordinates: hip_flexion_r, hip_adduction_r, hip_rotation_r)"});
}

TEST_F(HipMotion, NoFramesIsAnError) {
  TempFile f("empty.mot");
  f.write("m\ninDegrees=yes\nendheader\ntime\thip_flexion_r\n");
  expectModelError([&] { Motion::fromFile(f.path(), *skeleton_); }, {f.path(), "no frames"});
}

TEST_F(HipMotion, NonFiniteValueIsAnError) {
  TempFile f("nan.mot");
  f.write("m\ninDegrees=yes\nendheader\ntime\thip_flexion_r\n0\t1\n0.1\tnan\n");
  expectModelError([&] { Motion::fromFile(f.path(), *skeleton_); },
                   {f.path(), "frame 1", "'hip_flexion_r'", "non-finite"});
}

TEST_F(HipMotion, TimeMustIncrease) {
  TempFile f("time.mot");
  f.write("m\ninDegrees=yes\nendheader\ntime\thip_flexion_r\n0\t1\n0\t2\n");
  expectModelError([&] { Motion::fromFile(f.path(), *skeleton_); }, {f.path(), "frame 1", "increase"});
}

TEST_F(HipMotion, StorageErrorsPassThroughWithLine) {
  TempFile f("short.mot");
  f.write("m\ninDegrees=yes\nendheader\ntime\thip_flexion_r\n0\n");
  expectModelError([&] { Motion::fromFile(f.path(), *skeleton_); }, {f.path(), "line 5"});
}

TEST_F(HipMotion, AngleBeyondTheBoundIsRefusedNamingLineAndColumn) {
  // 1e10 degrees made a run hang; the reader refuses |q| > 1e4 rad and names where.
  TempFile f("huge_angle.mot");
  f.write("huge\ninDegrees=yes\nendheader\ntime\thip_flexion_r\thip_adduction_r\n0\t0\t0\n0.1\t1\t1e10\n");
  expectModelError([&] { Motion::fromFile(f.path(), *skeleton_); },
                   {f.path(), "line 6 (frame 1)", "column 'hip_adduction_r'", "1e+10 deg", "exceeds the 10000 rad"});
}

TEST_F(HipMotion, AngleJustWithinTheBoundIsRead) {
  TempFile f("bound_angle.mot");
  f.write("bound\ninDegrees=no\nendheader\ntime\thip_flexion_r\n0\t0\n0.1\t-10000\n");
  EXPECT_EQ(Motion::fromFile(f.path(), *skeleton_).getCoordinates(1)[skeleton_->findCoordinateIndex("hip_flexion_r")],
            -10000.0);
}

TEST_F(HipMotion, MotionPathThatIsADeviceOrDirectoryIsRefusedWithoutReading) {
  expectModelError([&] { Motion::fromFile("/dev/urandom", *skeleton_); },
                   {"/dev/urandom", "is a character device, not a regular file"});
  expectModelError([&] { Motion::fromFile(kHipDir, *skeleton_); }, {kHipDir, "is a directory, not a regular file"});
}

// OpenSim models: columns by coordinate name (or OpenSim 4 state path), translational
// coordinates in metres, degrees only for rotational ones, and coordinates not mentioned at rest.
class OsimMotion : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    skeleton_ = new Skeleton(Skeleton::fromOsim(kHipDir + "/osim/LHDL_hip_r.osim"));
    skeleton_->setRestCoordinateValues(skeleton_->solveBodiesAtGround());
  }
  static void TearDownTestSuite() { delete skeleton_; }
  static int index(const char* name) { return skeleton_->findCoordinateIndex(name); }
  static Skeleton* skeleton_;
};
Skeleton* OsimMotion::skeleton_ = nullptr;

TEST_F(OsimMotion, HeaderVariantsDriveCoordinatesByName) {
  const Eigen::VectorXd& rest = skeleton_->getRestCoordinateValues();
  TempFile f("osim_degrees.mot");
  // version, counts, a quoted units line, degrees; a translational column in metres.
  f.write("hip flexion\nversion=1\nnRows=2\nnColumns=3\ninDegrees=yes\n"
          "\"Units are S.I. units (second, meters, Newtons, ...)\"\nendheader\n"
          "time\thip_flexion_r\tpelvis_tx\n0\t10\t0.25\n0.1\t20\t-0.001\n");
  Motion m = Motion::fromFile(f.path(), *skeleton_);
  ASSERT_EQ(m.getNumFrames(), 2);
  EXPECT_NEAR(m.getCoordinates(1)[index("hip_flexion_r")], 20 * kDeg, 1e-15);
  EXPECT_DOUBLE_EQ(m.getCoordinates(0)[index("pelvis_tx")], 250.0);  // m → mm, not degrees
  EXPECT_DOUBLE_EQ(m.getCoordinates(1)[index("pelvis_tx")], -1.0);
  for (const char* other : {"hip_adduction_r", "hip_rotation_r", "pelvis_tilt", "pelvis_tz"})
    EXPECT_EQ(m.getCoordinates(1)[index(other)], rest[index(other)]) << other;

  // Radians; OpenSim 4 state paths, speeds skipped.
  f.write("states\ninDegrees=no\nendheader\ntime\t/jointset/hip_r/hip_adduction_r/value\t"
          "/jointset/hip_r/hip_adduction_r/speed\n0\t0.1\t5\n");
  m = Motion::fromFile(f.path(), *skeleton_);
  EXPECT_DOUBLE_EQ(m.getCoordinates(0)[index("hip_adduction_r")], 0.1);
  EXPECT_EQ(m.getCoordinates(0)[index("hip_flexion_r")], rest[index("hip_flexion_r")]);

  // SIMM header, no inDegrees: radians.
  f.write("simm\ndatacolumns 2\ndatarows 1\nendheader\ntime hip_rotation_r\n0 0.2\n");
  EXPECT_DOUBLE_EQ(Motion::fromFile(f.path(), *skeleton_).getCoordinates(0)[index("hip_rotation_r")], 0.2);

  // The same coordinate twice.
  f.write("m\nendheader\ntime\thip_rotation_r\t/jointset/hip_r/hip_rotation_r/value\n0\t1\t1\n");
  expectModelError([&] { Motion::fromFile(f.path(), *skeleton_); },
                   {f.path(), "'hip_rotation_r' and '/jointset/hip_r/hip_rotation_r/value' both give coordinate"});
}

// The scene's motion: flexion from the rest pose, 1° a frame, by the osim's own coordinate.
TEST_F(OsimMotion, SceneMotionStartsAtRestAndFlexesBy80Degrees) {
  const Motion m = Motion::fromFile(kHipDir + "/motions/hip_flexion_osim_0_80.mot", *skeleton_);
  ASSERT_EQ(m.getNumFrames(), 81);
  const Eigen::VectorXd& rest = skeleton_->getRestCoordinateValues();
  EXPECT_LT((m.getCoordinates(0) - rest).cwiseAbs().maxCoeff(), 1e-9);
  for (int i = 0; i < m.getNumFrames(); ++i) {
    Eigen::VectorXd expected = rest;
    expected[index("hip_flexion_r")] += i * kDeg;
    EXPECT_LT((m.getCoordinates(i) - expected).cwiseAbs().maxCoeff(), 1e-9) << "frame " << i;
    EXPECT_NEAR(m.getTime(i), i / 30.0, 1e-12);
  }
}

}  // namespace
}  // namespace rbfmuscle
