// SPDX-License-Identifier: Apache-2.0
/// Integration tests of the rbfmuscle host: run the executable on model files
/// under data/, with the test plugin (BodyOriginReporter), and check its
/// outputs and its error messages.
#include "model/storage_file.h"
#include "support/eigen_compare.h"
#include "support/run_host.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <map>
#include <chrono>
#include <vector>

namespace rbfmuscle {
namespace {

namespace fs = std::filesystem;

const fs::path kData = fs::path(RBFMUSCLE_SOURCE_DIR) / "tests/integration/host/data";
const fs::path kPluginDir = fs::path(RBFMUSCLE_BINARY_DIR) / "lib";

using test::HostResult;
using test::readText;

/// A fresh, absent output directory for one test.
fs::path outputDir(const std::string& name) {
  const fs::path root = fs::path(RBFMUSCLE_BINARY_DIR) / "test_out" / "host" / name;
  fs::remove_all(root);
  fs::create_directories(root);
  return root / "out";
}

/// Runs `rbfmuscle ARGS`, capturing stdout and stderr in test_out/host/NAME_log.
HostResult runHost(const std::string& args, const std::string& name) {
  return test::runHost(args, "host", name);
}

/// Runs a bad model: non-zero exit, one-line "rbfmuscle: error:" message
/// containing every `culprit`, and OUTDIR neither created nor left partial.
void expectFailure(const std::string& model, const std::vector<std::string>& culprits,
                   const std::string& extra_args = "", const std::string& tag = "") {
  const std::string name = tag.empty() ? model : tag;
  const fs::path out = outputDir(name);
  const HostResult r = runHost("run '" + (kData / (model + ".xml")).string() + "' -o '" +
                                   out.string() + "' " + extra_args,
                               name);
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_EQ(r.err.rfind("rbfmuscle: error: ", 0), 0u) << r.err;
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << "one line: " << r.err;
  for (const auto& culprit : culprits) EXPECT_NE(r.err.find(culprit), std::string::npos) << "missing '" << culprit << "' in: " << r.err;
  EXPECT_FALSE(fs::exists(out)) << "OUTDIR was created";
  EXPECT_TRUE(fs::is_empty(out.parent_path())) << "a staging directory was left behind";
}

/// hip_frame.json: hip joint centre (CT frame, mm) and the pelvis axes in CT
/// after Gram-Schmidt (as hip_r.urdf states them).
const Eigen::Vector3d kHipCentre_mm(143.225, 243.37, -432.499);
const Eigen::Vector3d kPelvisY(0.015392240843200072, -0.11868956608287687, 0.9928120999589416);
const Eigen::Vector3d kPelvisZ(-0.9924778435393231, 0.11879490607095902, 0.029588855590025755);

Eigen::Vector3d pointAt(const StorageTable& t, const std::string& component, int row) {
  Eigen::Vector3d p;
  const char* axes[3] = {"x_mm", "y_mm", "z_mm"};
  for (int k = 0; k < 3; ++k) {
    const int column = t.findColumn(component + "." + axes[k]);
    EXPECT_GE(column, 0) << component << "." << axes[k];
    p[k] = column >= 0 ? t.rows[row][column] : NAN;
  }
  return p;
}

TEST(Host, RunsPluginComponentOverFlexionAndReportsAnalyticFemurPoint) {
  const fs::path out = outputDir("femur_point");
  const HostResult r =
      runHost("run '" + (kData / "femur_point.xml").string() + "' -o '" + out.string() + "'", "femur_point");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const StorageTable t = readStorage((out / "outputs.sto").string());
  EXPECT_EQ(t.column_labels,
            (std::vector<std::string>{"time", "hip_flexion_r", "hip_adduction_r", "hip_rotation_r",
                                      "femur_knee.x_mm", "femur_knee.y_mm", "femur_knee.z_mm",
                                      "femur_origin.x_mm", "femur_origin.y_mm", "femur_origin.z_mm",
                                      "pelvis_point.x_mm", "pelvis_point.y_mm", "pelvis_point.z_mm"}));
  ASSERT_EQ(t.rows.size(), 81u);
  EXPECT_FALSE(t.in_degrees);
  const int last = 80;
  EXPECT_NEAR(t.rows[last][0], 80.0 / 30.0, 1e-12);
  const double q_rad = 80.0 * M_PI / 180.0;
  EXPECT_NEAR(t.rows[last][1], q_rad, 1e-15) << "coordinates are written in rad";

  // Frame 0: p = c + 400 mm along -Y_pelvis. Last frame: rotated by 80° about Z_pelvis through c.
  const Eigen::Vector3d p0_expected = kHipCentre_mm - 400.0 * kPelvisY;
  EXPECT_TRUE(test::isApprox(pointAt(t, "femur_knee", 0), p0_expected, 0.0, 1e-9));
  const Eigen::Vector3d p_last_expected =
      kHipCentre_mm + Eigen::AngleAxisd(q_rad, kPelvisZ) * (p0_expected - kHipCentre_mm);
  EXPECT_TRUE(test::isApprox(pointAt(t, "femur_knee", last), p_last_expected, 0.0, 1e-9));
  for (int row : {0, 40, last}) {
    EXPECT_TRUE(test::isApprox(pointAt(t, "femur_origin", row), kHipCentre_mm, 0.0, 1e-9)) << row;
    EXPECT_TRUE(test::isApprox(pointAt(t, "pelvis_point", row), Eigen::Vector3d(10, 20, 30), 0.0, 1e-12)) << row;
  }

  const std::string csv = readText(out / "outputs.csv");
  EXPECT_EQ(csv.substr(0, csv.find('\n')),
            "time,hip_flexion_r,hip_adduction_r,hip_rotation_r,femur_knee.x_mm,femur_knee.y_mm,"
            "femur_knee.z_mm,femur_origin.x_mm,femur_origin.y_mm,femur_origin.z_mm,"
            "pelvis_point.x_mm,pelvis_point.y_mm,pelvis_point.z_mm");
  const std::string summary = readText(out / "summary.json");
  EXPECT_NE(summary.find("\"frames\": 81"), std::string::npos) << summary;
  EXPECT_NE(summary.find("component femur_knee (BodyOriginReporter)"), std::string::npos) << summary;
  EXPECT_NE(summary.find("\"median\""), std::string::npos) << summary;
}

// The subject's OpenSim model as the skeleton: at rest (every body frame at ground) the femur is
// at its CT position, and flexion turns it about Z of hip_r's parent frame through the joint
// centre, both taken from the .osim's numbers here.
TEST(Host, RunsAnOpenSimSkeletonFromItsRestPose) {
  const fs::path out = outputDir("femur_point_osim");
  const HostResult r = runHost("run '" + (kData / "femur_point_osim.xml").string() + "' -o '" + out.string() + "'",
                               "femur_point_osim");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const StorageTable t = readStorage((out / "outputs.sto").string());
  ASSERT_EQ(t.rows.size(), 81u);
  ASSERT_EQ(t.column_labels.size(), 16u);  // time, nine coordinates, two points
  EXPECT_EQ(t.column_labels[7], "hip_flexion_r");
  // hip_r: orientation_in_parent (body-fixed XYZ) and location_in_parent of LHDL_hip_r.osim
  const Eigen::Matrix3d R_PF = (Eigen::AngleAxisd(-2.77372, Eigen::Vector3d::UnitX()) *
                                Eigen::AngleAxisd(-1.56193, Eigen::Vector3d::UnitY()) *
                                Eigen::AngleAxisd(1.80849, Eigen::Vector3d::UnitZ()))
                                   .toRotationMatrix();
  const Eigen::Vector3d centre(143.478, 243.439, -432.67);
  const Eigen::Vector3d knee(118, 265, -840);
  // 0.001 mm: hip_r's location in pelvis and femur differ by 1 µm
  EXPECT_TRUE(test::isApprox(pointAt(t, "femur_knee", 0), knee, 0.0, 1.1e-3));
  for (int row : {40, 80}) {
    const Eigen::Vector3d expected = centre + Eigen::AngleAxisd(row * M_PI / 180.0, R_PF.col(2)) * (knee - centre);
    EXPECT_TRUE(test::isApprox(pointAt(t, "femur_knee", row), expected, 0.0, 1.1e-3)) << row;
    EXPECT_TRUE(test::isApprox(pointAt(t, "pelvis_point", row), Eigen::Vector3d(10, 20, 30), 0.0, 1e-9)) << row;
  }
}

TEST(Host, ReplacesAnEarlierOutputAndKeepsItWhenARunFails) {
  const fs::path out = outputDir("rerun");
  const std::string good = "run '" + (kData / "femur_point.xml").string() + "' -o '" + out.string() + "'";
  ASSERT_EQ(runHost(good, "rerun").exit_code, 0);
  ASSERT_EQ(runHost(good, "rerun").exit_code, 0) << "an earlier output is replaced";
  const std::string before = readText(out / "outputs.sto");
  const HostResult bad = runHost(
      "run '" + (kData / "bad_reporter_pattern.xml").string() + "' -o '" + out.string() + "'", "rerun");
  EXPECT_NE(bad.exit_code, 0);
  EXPECT_EQ(readText(out / "outputs.sto"), before) << "a failed run leaves OUTDIR unchanged";
}

TEST(Host, WritesFrameMeshesOnlyWhenAsked) {
  const fs::path out = outputDir("frames_mesh");
  const HostResult r = runHost("run '" + (kData / "femur_point.xml").string() + "' -o '" +
                                   out.string() + "' --frames-mesh --quiet",
                               "frames_mesh");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(fs::is_directory(out / "meshes")) << "BodyOriginReporter has no geometry: empty";
  EXPECT_EQ(r.err.find("frame 81/81"), std::string::npos) << "--quiet prints no progress";
}

TEST(Host, InfoListsPluginTypesWithPropertiesSocketsAndOutputs) {
  const HostResult r = runHost("info -L rbfmuscle_testplugin", "info");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("BodyOriginReporter"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("point_mm (Vector3, default 0 0 0)"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("socket_body (body)"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("x_mm (double, mm)"), std::string::npos) << r.out;
  const HostResult none = runHost("info", "info_none");
  EXPECT_EQ(none.exit_code, 0);
  EXPECT_EQ(none.out.find("BodyOriginReporter"), std::string::npos);
}

TEST(Host, BadCommandLineGivesUsageAndExitCode2) {
  for (const std::string args : {"", "simulate x.xml", "run --bogus", "run a.xml", "info -o x"}) {
    const HostResult r = runHost(args, "usage");
    EXPECT_EQ(r.exit_code, 2) << args;
    EXPECT_EQ(r.err.rfind("rbfmuscle: error: ", 0), 0u) << r.err;
    EXPECT_NE(r.err.find("usage: rbfmuscle COMMAND"), std::string::npos) << r.err;
  }
  EXPECT_EQ(runHost("run --help", "help").exit_code, 0);
}

TEST(Host, AnOptionOfOneValueGivenTwiceIsAUsageError) {
  // The second would silently replace the first (the output directory, the motion).
  for (const std::string& args : {std::string("run a.xml -o x -o y"), std::string("run a.xml -o x --output y"),
                                  std::string("run a.xml -o x --motion m.mot --motion n.mot")}) {
    const HostResult r = runHost(args, "twice");
    EXPECT_EQ(r.exit_code, 2) << args;
    EXPECT_NE(r.err.find("is given twice"), std::string::npos) << r.err;
  }
}

TEST(HostErrors, UnknownClassListsRegisteredOnes) {
  expectFailure("bad_unknown_class", {"bad_unknown_class.xml:7: <HillMuscle name=\"m\">",
                                      "unknown component class 'HillMuscle'",
                                      "(registered: BodyOriginReporter)"});
}
TEST(HostErrors, WrongTypedProperty) {
  expectFailure("bad_property_type", {"bad_property_type.xml:8: <point_mm> in <BodyOriginReporter name=\"knee\">",
                                      "expected three numbers", "'0 minus400 0'"});
}
TEST(HostErrors, UnknownProperty) {
  expectFailure("bad_unknown_property", {"bad_unknown_property.xml:9: <radius_mm>",
                                         "unknown property 'radius_mm'", "properties: point_mm"});
}
TEST(HostErrors, UnknownSocketTargetListsBodies) {
  expectFailure("bad_socket_target", {"bad_socket_target.xml:7: <BodyOriginReporter name=\"knee\">",
                                      "unknown body 'tibia_r'", "pelvis", "femur_r"});
}
TEST(HostErrors, MissingUrdf) {
  expectFailure("bad_missing_urdf", {"bad_missing_urdf.xml:3: <skeleton>", "no_such_hip.urdf"});
}
TEST(HostErrors, RefusedOpenSimJointNamesModelLineAndOsimLine) {
  expectFailure("bad_osim_joint", {"bad_osim_joint.xml:3: <skeleton>", "unknown_joint.osim, line 13: <BallJoint name=\"knee\">",
                                   "joint type BallJoint is not supported"});
}
TEST(HostErrors, MissingMesh) {
  expectFailure("bad_missing_mesh", {"bad_missing_mesh.xml:3: <skeleton>", "femur_r_missing.ply"});
}
TEST(HostErrors, MotionWithUnknownCoordinate) {
  expectFailure("bad_motion_coordinate", {"bad_motion_coordinate.xml:5: <motion>", "knee_angle_r"});
}
TEST(HostErrors, MissingOrUnsupportedVersion) {
  expectFailure("bad_no_version", {"bad_no_version.xml:2: <RBFMuscleModel", "missing attribute 'version'"});
  expectFailure("bad_version", {"bad_version.xml:2:", "unsupported version '7'"});
}
TEST(HostErrors, ReporterPatternMatchingNoOutputFailsAfterStagingWithoutLeftovers) {
  expectFailure("bad_reporter_pattern", {"bad_reporter_pattern.xml:9: <reporter>", "'knee.w_mm'", "knee.x_mm"});
}
TEST(HostErrors, PluginNotFound) {
  expectFailure("femur_point", {"plugin no_such_plugin: not found (tried: no_such_plugin",
                                "libno_such_plugin.so"},
                "-L no_such_plugin", "plugin_not_found");
}
TEST(HostErrors, PluginWithoutEntryPoint) {
  const std::string lib = (kPluginDir / "librbfmuscle_model.so").string();
  expectFailure("femur_point", {"plugin " + lib + ": no entry point rbfmuscle_register_types"},
                "-L '" + lib + "'", "plugin_no_entry");
}
TEST(HostErrors, PluginThatIsNoLibrary) {
  const std::string file = (kData / "femur_point.xml").string();
  expectFailure("femur_point", {"plugin " + file + ": ", "femur_point.xml"}, "-L '" + file + "'", "plugin_not_library");
}

/// Writes `files` (name → text) into a fresh directory and runs the model `model` there:
/// non-zero exit, one error line containing every culprit, no OUTDIR and no staging left.
void expectGeneratedFailure(const std::string& name, const std::map<std::string, std::string>& files,
                            const std::string& model, const std::vector<std::string>& culprits) {
  const fs::path out = outputDir(name);
  const fs::path dir = out.parent_path() / "model";
  fs::create_directories(dir);
  for (const auto& [file, text] : files) std::ofstream(dir / file) << text;
  const HostResult r = runHost("run '" + (dir / model).string() + "' -o '" + out.string() + "' --quiet", name);
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_EQ(r.err.rfind("rbfmuscle: error: ", 0), 0u) << r.err;
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << "one line: " << r.err;
  for (const auto& culprit : culprits) EXPECT_NE(r.err.find(culprit), std::string::npos) << "missing '" << culprit << "' in: " << r.err;
  EXPECT_FALSE(fs::exists(out));
  for (const auto& entry : fs::directory_iterator(out.parent_path()))
    EXPECT_EQ(entry.path().filename().string().find("out.partial"), std::string::npos) << entry.path();
}

const char* const kLimit = R"(<axis xyz="0 0 1"/><limit lower="-1" upper="1" effort="1" velocity="1"/>)";

TEST(HostErrors, UrdfWithAJointCycleIsRefusedNamingTheLinks) {
  // It used to end in a segmentation fault (signal 11).
  const std::string urdf = std::string(R"(<robot name="cycle"><link name="base"/><link name="a"/><link name="b"/>
    <joint name="j_base_a" type="revolute"><parent link="base"/><child link="a"/>)") + kLimit + R"(</joint>
    <joint name="j_a_b" type="revolute"><parent link="a"/><child link="b"/>)" + kLimit + R"(</joint>
    <joint name="j_b_a" type="revolute"><parent link="b"/><child link="a"/>)" + kLimit + "</joint></robot>";
  expectGeneratedFailure("urdf_cycle",
                         {{"cycle.urdf", urdf},
                          {"cycle.mot", "m\ninDegrees=yes\nendheader\ntime\tj_base_a\n0\t0\n1\t1\n"},
                          {"cycle.xml", R"(<RBFMuscleModel version="1"><skeleton file="cycle.urdf"/>)"
                                        R"(<motion file="cycle.mot"/></RBFMuscleModel>)"}},
                         "cycle.xml",
                         {"cycle.xml:1: <skeleton>", "cycle.urdf: joints 'j_a_b', 'j_b_a' form a closed loop",
                          "('a' → 'b' → 'a')"});
}

TEST(HostErrors, MotionAngleOf1e10DegreesFailsFastNamingLineAndColumn) {
  // It used to hang (and leave OUTDIR.partial-PID behind when killed).
  const std::string model = R"(<RBFMuscleModel version="1"><skeleton file=")" +
                            (fs::path(RBFMUSCLE_SOURCE_DIR) / "models/hip/hip_r.urdf").string() +
                            R"("/><motion file="huge.mot"/></RBFMuscleModel>)";
  const auto start = std::chrono::steady_clock::now();
  expectGeneratedFailure("motion_huge_angle",
                         {{"huge.mot", "m\ninDegrees=yes\nendheader\ntime\thip_flexion_r\n0\t0\n0.1\t1e10\n"},
                          {"huge.xml", model}},
                         "huge.xml", {"huge.xml:1: <motion>", "huge.mot: line 6 (frame 1), column 'hip_flexion_r'",
                                      "1e+10 deg exceeds the 10000 rad"});
  EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(), 10.0);
}

TEST(HostErrors, MotionThatIsADeviceIsRefusedWithoutReading) {
  const std::string model = R"(<RBFMuscleModel version="1"><skeleton file=")" +
                            (fs::path(RBFMUSCLE_SOURCE_DIR) / "models/hip/hip_r.urdf").string() +
                            R"("/><motion file="/dev/zero"/></RBFMuscleModel>)";
  expectGeneratedFailure("motion_device", {{"device.xml", model}}, "device.xml",
                         {"device.xml:1: <motion>", "/dev/zero", "is a character device, not a regular file"});
}

TEST(HostErrors, OutputDirectoryHoldingTheModelIsRefusedAndKept) {
  // An earlier output (it has summary.json) that now holds the model would have been replaced,
  // model and all, by the run.
  const fs::path out = outputDir("outdir_holds_model");
  fs::create_directories(out);
  std::ofstream(out / "summary.json") << "{}\n";
  const std::string model = R"(<RBFMuscleModel version="1"><skeleton file=")" +
                            (fs::path(RBFMUSCLE_SOURCE_DIR) / "models/hip/hip_r.urdf").string() +
                            R"("/><motion file=")" +
                            (fs::path(RBFMUSCLE_SOURCE_DIR) / "models/hip/motions/hip_flexion_0_80.mot").string() +
                            R"("/></RBFMuscleModel>)";
  std::ofstream(out / "model.xml") << model;
  const HostResult r = runHost("run '" + (out / "model.xml").string() + "' -o '" + out.string() + "'",
                               "outdir_holds_model");
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_NE(r.err.find("run: -o " + out.string() + " holds the model file " + (out / "model.xml").string()),
            std::string::npos)
      << r.err;
  EXPECT_TRUE(fs::exists(out / "model.xml"));
}

}  // namespace
}  // namespace rbfmuscle
