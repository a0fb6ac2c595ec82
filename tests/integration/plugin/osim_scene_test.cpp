// SPDX-License-Identifier: Apache-2.0
/// A scene from OpenSim files alone (models/hip/iliacus_osim.xml): the subject's .osim gives the
/// skeleton, the bones, and the iliacus's attachments and line of action; an OpenSim .mot moves
/// it. The line of action the component reports is checked against the muscle's path points
/// placed by the skeleton at each frame, with the conditional point leaving the path above its
/// range of hip flexion.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>

#include "model/osim_muscle_path.h"
#include "model/skeleton.h"
#include "model/storage_file.h"
#include "support/run_host.h"

namespace rbfmuscle {
namespace {

namespace fs = std::filesystem;
const fs::path kHip = fs::path(RBFMUSCLE_SOURCE_DIR) / "models/hip";
const std::string kOsim = (kHip / "osim/LHDL_hip_r.osim").string();
constexpr double kDeg = 3.141592653589793238462643383279502884 / 180.0;

/// Length of the path at skeleton pose `q` (rad), over the points on it there.
double calcExpectedLength_mm(Skeleton& skeleton, const MusclePath& path, const Eigen::VectorXd& q) {
  skeleton.setCoordinateValues(q);
  double length = 0;
  Eigen::Vector3d previous = Eigen::Vector3d::Constant(NAN);
  for (const MusclePathPoint& p : path.points) {
    if (p.coordinate >= 0 && !(q[p.coordinate] >= p.active_min && q[p.coordinate] <= p.active_max)) continue;
    const Eigen::Vector3d point_G = skeleton.getBodyTransform(p.body) * p.location_B_mm;
    if (previous.allFinite()) length += (point_G - previous).norm();
    previous = point_G;
  }
  return length;
}

TEST(OsimScene, IliacusLineOfActionFollowsTheModelsPathPoints) {
  const fs::path dir = fs::path(RBFMUSCLE_BINARY_DIR) / "test_out/plugin/osim_scene";
  fs::remove_all(dir);
  fs::create_directories(dir);
  const std::vector<double> flexion_deg = {1.576010535251095, 30.0, 60.0};  // rest, then either side of 54°
  {
    std::ofstream mot(dir / "flexion.mot");
    mot << "flexion\nversion=1\nnRows=3\nnColumns=2\ninDegrees=yes\nendheader\ntime\thip_flexion_r\n";
    for (size_t i = 0; i < flexion_deg.size(); ++i) mot << 0.1 * static_cast<double>(i) << '\t' << flexion_deg[i] << '\n';
  }
  const test::HostResult r = test::runHost("run '" + (kHip / "iliacus_osim.xml").string() + "' -o '" + (dir / "out").string() +
                                               "' --motion '" + (dir / "flexion.mot").string() +
                                               "' --quiet --set iliacus_r.surface_file=surfaces/iliacus_r.rbf --set iliacus_r.centres=2000",
                                           "plugin", "osim_scene");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const StorageTable table = readStorage((dir / "out/outputs.sto").string());
  const int column = table.findColumn("iliacus_r.line_of_action_length_mm");
  ASSERT_GE(column, 0);
  ASSERT_EQ(table.rows.size(), flexion_deg.size());

  Skeleton skeleton = Skeleton::fromOsim(kOsim);
  const Eigen::VectorXd rest = skeleton.solveBodiesAtGround();
  const MusclePath path = readOsimMusclePath(kOsim, "iliacus_r", skeleton);
  const int flexion = skeleton.findCoordinateIndex("hip_flexion_r");
  std::vector<double> expected;
  for (size_t i = 0; i < flexion_deg.size(); ++i) {
    Eigen::VectorXd q = rest;
    q[flexion] = flexion_deg[i] * kDeg;
    expected.push_back(calcExpectedLength_mm(skeleton, path, q));
    EXPECT_NEAR(table.rows[i][static_cast<size_t>(column)], expected.back(), 1e-6) << "frame " << i;
  }
  // At rest every body is at ground (to the 0.01 mm solveBodiesAtGround promises), so the path is
  // the file's five points as written (m → mm).
  double rest_length = 0;
  for (size_t k = 1; k < path.points.size(); ++k)
    rest_length += (path.points[k].location_B_mm - path.points[k - 1].location_B_mm).norm();
  EXPECT_NEAR(expected[0], rest_length, 0.01);
  // Flexion shortens the iliacus's path.
  EXPECT_LT(expected[1], expected[0]);
  EXPECT_LT(expected[2], expected[1]);
}

}  // namespace
}  // namespace rbfmuscle
