// SPDX-License-Identifier: Apache-2.0
/// Integration tests of `rbfmuscle run --set COMPONENT.PROPERTY=VALUE` and
/// `--motion FILE`: the overrides change the run as if written in the model
/// file, and bad ones fail naming the assignment at fault.
#include "model/storage_file.h"
#include "support/eigen_compare.h"
#include "support/run_host.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>

namespace rbfmuscle {
namespace {

namespace fs = std::filesystem;

const fs::path kData = fs::path(RBFMUSCLE_SOURCE_DIR) / "tests/integration/host/data";
const fs::path kMotions = fs::path(RBFMUSCLE_SOURCE_DIR) / "models/hip/motions";

/// hip_frame.json: hip joint centre (CT frame, mm) and the pelvis Y axis in CT.
const Eigen::Vector3d kHipCentre_mm(143.225, 243.37, -432.499);
const Eigen::Vector3d kPelvisY(0.015392240843200072, -0.11868956608287687, 0.9928120999589416);

/// A fresh, absent output directory for one test.
fs::path outputDir(const std::string& name) {
  const fs::path root = fs::path(RBFMUSCLE_BINARY_DIR) / "test_out" / "host_overrides" / name;
  fs::remove_all(root);
  fs::create_directories(root);
  return root / "out";
}

/// `rbfmuscle run femur_point.xml -o OUT EXTRA`.
test::HostResult runFemurPoint(const fs::path& out, const std::string& extra, const std::string& name) {
  return test::runHost("run '" + (kData / "femur_point.xml").string() + "' -o '" + out.string() + "' --quiet " + extra,
                       "host_overrides", name);
}

Eigen::Vector3d kneeAt(const StorageTable& t, int row) {
  Eigen::Vector3d p;
  const char* axes[3] = {"x_mm", "y_mm", "z_mm"};
  for (int k = 0; k < 3; ++k) {
    const int column = t.findColumn(std::string("femur_knee.") + axes[k]);
    EXPECT_GE(column, 0) << axes[k];
    p[k] = column >= 0 ? t.rows[row][column] : NAN;
  }
  return p;
}

TEST(HostOverrides, SetChangesAPropertyAndMotionReplacesTheMotion) {
  const fs::path out = outputDir("good");
  const test::HostResult r =
      runFemurPoint(out,
                    "--set 'femur_knee.point_mm=0 -200 0' --motion '" +
                        (kMotions / "hip_flexion_0_80_step10.mot").string() + "'",
                    "good");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const StorageTable t = readStorage((out / "outputs.sto").string());
  ASSERT_EQ(t.rows.size(), 9u) << "the 10-degree motion has 9 frames (the model's has 81)";
  const int flexion = t.findColumn("hip_flexion_r");
  ASSERT_GE(flexion, 0);
  EXPECT_NEAR(t.rows[8][flexion], 80.0 * M_PI / 180.0, 1e-12);
  // The model file says 400 mm; the override puts the point 200 mm from the hip centre.
  EXPECT_TRUE(test::isApprox(kneeAt(t, 0), kHipCentre_mm - 200.0 * kPelvisY, 0.0, 1e-9));
  EXPECT_NEAR((kneeAt(t, 8) - kHipCentre_mm).norm(), 200.0, 1e-9) << "rigid with the femur";
}

TEST(HostOverrides, LaterSetWins) {
  const fs::path out = outputDir("later");
  const test::HostResult r =
      runFemurPoint(out, "--set 'femur_knee.point_mm=0 -100 0' --set 'femur_knee.point_mm=0 -300 0'", "later");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const StorageTable t = readStorage((out / "outputs.sto").string());
  EXPECT_TRUE(test::isApprox(kneeAt(t, 0), kHipCentre_mm - 300.0 * kPelvisY, 0.0, 1e-9));
}

/// A bad override: exit code, one-line message containing every culprit, no OUTDIR.
void expectFailure(const std::string& extra, int exit_code, const std::vector<std::string>& culprits,
                   const std::string& name) {
  const fs::path out = outputDir(name);
  const test::HostResult r = runFemurPoint(out, extra, name);
  EXPECT_EQ(r.exit_code, exit_code) << r.err;
  EXPECT_EQ(r.err.rfind("rbfmuscle: error: ", 0), 0u) << r.err;
  for (const auto& culprit : culprits)
    EXPECT_NE(r.err.find(culprit), std::string::npos) << "missing '" << culprit << "' in: " << r.err;
  EXPECT_FALSE(fs::exists(out)) << "OUTDIR was created";
}

TEST(HostOverrides, UnknownComponentListsTheModelsComponents) {
  expectFailure("--set 'tibia.point_mm=1 2 3'", 1,
                {"command line: --set tibia.point_mm=1 2 3", "no component 'tibia'",
                 "components: femur_knee, femur_origin, pelvis_point"},
                "unknown_component");
}

TEST(HostOverrides, UnknownPropertyNamesTheAssignmentAndTheClassProperties) {
  expectFailure("--set femur_knee.radius_mm=3", 1,
                {"command line: --set femur_knee.radius_mm=3", "unknown property 'radius_mm'",
                 "properties: point_mm"},
                "unknown_property");
}

TEST(HostOverrides, BadValueNamesTheAssignment) {
  expectFailure("--set 'femur_knee.point_mm=0 minus200 0'", 1,
                {"command line: --set femur_knee.point_mm=0 minus200 0", "expected three numbers"}, "bad_value");
}

TEST(HostOverrides, MalformedAssignmentOrMissingMotionFail) {
  expectFailure("--set femur_knee.point_mm", 2, {"--set expects COMPONENT.PROPERTY=VALUE", "'femur_knee.point_mm'"},
                "malformed");
  expectFailure("--set femur_knee.socket_body=pelvis", 1, {"'socket_body' is a socket"}, "socket");
  expectFailure("--motion no_such_motion.mot", 1, {"command line: --motion no_such_motion.mot", "no_such_motion.mot"},
                "missing_motion");
}

}  // namespace
}  // namespace rbfmuscle
