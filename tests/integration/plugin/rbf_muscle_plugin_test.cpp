// SPDX-License-Identifier: Apache-2.0
/// The RBFMuscle plugin through the host, as a user runs it: a gluteus
/// maximus scene over hip flexion, its outputs, determinism for any thread
/// count, and clear errors for bad muscle input.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <sstream>
#include <string>
#include <vector>

#include "model/storage_file.h"
#include "support/run_host.h"

namespace rbfmuscle {
namespace {

namespace fs = std::filesystem;
using test::HostResult;

const fs::path kHip = fs::path(RBFMUSCLE_SOURCE_DIR) / "models/hip";

/// Attachment areas of the hip scene (models/hip/hip_flexion.xml).
const std::string kAreas = (kHip / "landmarks/attachment_areas.json").string();
const std::string kOrigin = kAreas + ": LC_SET_Ori_1_R_M081_Glut_Max, LC_SET_Ori_2_R_M081_Glut_Max";
const std::string kInsertion = kAreas + ": LC_SET_Ins_1_R_M081_Glut_Max, LC_SET_Ins_2_R_M081_Glut_Max";

fs::path testDir(const std::string& name) {
  const fs::path dir = fs::path(RBFMUSCLE_BINARY_DIR) / "test_out/plugin" / name;
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

/// Writes a motion of two frames (0 and 1 s) with no coordinate into `dir`: the bones stay at
/// rest. Returns its path.
fs::path writeStillMotion(const fs::path& dir) {
  const fs::path path = dir / "still.mot";
  std::ofstream(path) << "still\nversion=1\nnRows=2\nnColumns=1\ninDegrees=yes\nendheader\ntime\n0\n1\n";
  return path;
}

/// Writes a one-muscle gluteus model into `dir` and returns its path.
fs::path writeModel(const fs::path& dir, const std::string& surface_file, const std::string& origin = kOrigin,
                    const std::string& motion = "hip_flexion_0_80_step10.mot", const fs::path& skeleton = kHip / "hip_r.urdf") {
  const fs::path path = dir / "model.xml";
  std::ofstream(path) << "<?xml version=\"1.0\"?>\n<RBFMuscleModel version=\"1\" name=\"glmax_test\">\n"
                      << "  <skeleton file=\"" << skeleton.string() << "\"/>\n"
                      << "  <plugin file=\"librbfmuscle_plugin.so\"/>\n"
                      << "  <motion file=\"" << (kHip / "motions" / motion).string() << "\"/>\n"
                      << "  <components>\n    <RBFMuscle name=\"glmax_r\">\n"
                      << "      <mesh_file>" << (kHip / "meshes/gluteus_maximus_r.ply").string() << "</mesh_file>\n"
                      << "      <surface_file>" << surface_file << "</surface_file>\n"
                      << "      <origin_area>" << origin << "</origin_area>\n"
                      << "      <insertion_area>" << kInsertion << "</insertion_area>\n"
                      << "      <socket_origin_body>pelvis</socket_origin_body>\n"
                      << "      <socket_insertion_body>femur_r</socket_insertion_body>\n"
                      << "    </RBFMuscle>\n  </components>\n</RBFMuscleModel>\n";
  return path;
}

HostResult runModel(const fs::path& model, const fs::path& out, const std::string& name,
                    const std::string& environment = "") {
  return test::runHost("run '" + model.string() + "' -o '" + out.string() + "' --quiet", "plugin", name, environment);
}

const std::string kCachedGluteus = (kHip / "surfaces/gluteus_maximus_r.rbf").string();

/// Runs the gluteus model written into `dir` (with its cached surface) with more `run` options.
HostResult runGluteusWith(const fs::path& dir, const std::string& options, const std::string& name) {
  return test::runHost("run '" + writeModel(dir, kCachedGluteus).string() + "' -o '" + (dir / "out").string() +
                           "' --quiet " + options,
                       "plugin", name);
}

TEST(RBFMusclePlugin, GluteusFollowsFlexionWithVolumeKept) {
  const fs::path dir = testDir("flexion");
  const HostResult r = runModel(writeModel(dir, kCachedGluteus), dir / "out", "flexion");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.err.find("glmax_r: blend by angle about the joint centre"), std::string::npos) << "the default\n" << r.err;
  const StorageTable table = readStorage((dir / "out/outputs.sto").string());
  ASSERT_EQ(table.rows.size(), 9u);  // 0°, 10°, …, 80°
  for (const char* column : {"glmax_r.volume_mm3", "glmax_r.volume_ratio", "glmax_r.curvature_cost",
                             "glmax_r.descent_iterations", "glmax_r.update_ms", "glmax_r.attached_kernels",
                             "glmax_r.fibre_length_mean_mm", "glmax_r.fibre_length_mm_0", "glmax_r.line_of_action_length_mm"})
    ASSERT_GE(table.findColumn(column), 0) << column;
  const int ratio = table.findColumn("glmax_r.volume_ratio");
  const int outside = table.findColumn("glmax_r.fibre_points_outside");
  const int fibre = table.findColumn("glmax_r.fibre_length_ratio");
  for (size_t i = 0; i < table.rows.size(); ++i) {
    const std::vector<double>& row = table.rows[i];
    for (size_t c = 0; c < row.size(); ++c) {
      // The surface is tracked with --frames-mesh only, the pieces counted with check_pieces_cell_mm only.
      const std::string& label = table.column_labels[c];
      if (label.find("surface") == std::string::npos && label != "glmax_r.pieces" &&
          label.rfind("glmax_r.stray_", 0) != 0) {
        EXPECT_TRUE(std::isfinite(row[c])) << label << " row " << i;
      }
    }
    EXPECT_NEAR(row[ratio], 1.0, 1e-3);
    EXPECT_EQ(row[outside], 0.0);
    if (i > 0) {
      EXPECT_GT(row[fibre], table.rows[i - 1][fibre]) << "the gluteus lengthens in flexion, row " << i;
    }
  }
  EXPECT_GT(table.rows.back()[table.findColumn("glmax_r.attached_kernels")], 0);
  // The host's summary gives the median and maximum of each reported time over the frames.
  std::ifstream in(dir / "out/summary.json");
  const std::string summary((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  for (const char* column : {"glmax_r.update_ms", "glmax_r.volume_ms"}) {
    std::vector<double> values;
    for (const std::vector<double>& row : table.rows) values.push_back(row[table.findColumn(column)]);
    std::sort(values.begin(), values.end());
    const std::string key = std::string("{\"output\": \"") + column + "\", \"median\": ";
    const std::size_t at = summary.find(key);
    ASSERT_NE(at, std::string::npos) << column << " in\n" << summary;
    const double median = std::stod(summary.substr(at + key.size()));
    EXPECT_NEAR(median, values[values.size() / 2], 1e-5 * values[values.size() / 2]) << column;  // 9 frames: the 5th
    const std::string max_key = "\"max\": ";
    const double max = std::stod(summary.substr(summary.find(max_key, at) + max_key.size()));
    EXPECT_NEAR(max, values.back(), 1e-5 * values.back()) << column;
  }
}

/// A 75° hip flexion in one frame: each frame depends only on its own bone poses, so the muscle
/// keeps every invariant it declares (volume within tolerance, finite positive volume and fibre
/// lengths, tracked surface out of the bones) and a --strict run with frame meshes succeeds.
TEST(RBFMusclePlugin, A75DegreeJumpInOneFrameKeepsEveryInvariant) {
  const fs::path dir = testDir("jump");
  const fs::path motion = fs::path(RBFMUSCLE_SOURCE_DIR) / "tests/integration/plugin/data/jump_flexion_75.mot";
  const HostResult r = test::runHost("run '" + writeModel(dir, kCachedGluteus).string() + "' -o '" + (dir / "out").string() +
                                         "' --quiet --strict --frames-mesh --motion '" + motion.string() + "'",
                                     "plugin", "jump");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(r.err.find("invariant"), std::string::npos) << r.err;
  const StorageTable t = readStorage((dir / "out/outputs.sto").string());
  ASSERT_EQ(t.rows.size(), 2u);
  const int depth = t.findColumn("glmax_r.surface_bone_depth_max_mm");
  ASSERT_GE(depth, 0);
  EXPECT_TRUE(std::isfinite(t.rows[1][static_cast<size_t>(depth)])) << "the surface was tracked and checked";
}

/// The same jump with the volume correction bounded to almost nothing: the volume cannot be held
/// and --strict fails at the jump's frame, naming the muscle, its output and the bound.
TEST(RBFMusclePlugin, A75DegreeJumpWithoutVolumeCorrectionFailsUnderStrict) {
  const fs::path dir = testDir("jump_strict");
  const fs::path motion = fs::path(RBFMUSCLE_SOURCE_DIR) / "tests/integration/plugin/data/jump_flexion_75.mot";
  const HostResult r = test::runHost("run '" + writeModel(dir, kCachedGluteus).string() + "' -o '" + (dir / "out").string() +
                                         "' --quiet --strict --set glmax_r/volume.max_correction=1e-6 --motion '" +
                                         motion.string() + "'",
                                     "plugin", "jump_strict");
  EXPECT_EQ(r.exit_code, 1) << r.err;
  for (const char* part : {"rbfmuscle: error: ", "<RBFMuscle name=\"glmax_r\">", "frame 1 (t = 0.0333333 s)",
                           "glmax_r.volume_ratio = ", "volume within the volume step's tolerance",
                           "from 0.999 to 1.001", "[--strict]"})
    EXPECT_NE(r.err.find(part), std::string::npos) << "missing '" << part << "' in: " << r.err;
  EXPECT_FALSE(fs::exists(dir / "out"));
}

TEST(RBFMusclePlugin, RunsOnOneAndTwoThreadsGiveIdenticalOutputs) {
  const fs::path dir = testDir("determinism");
  const fs::path model = writeModel(dir, kCachedGluteus, kOrigin, "hip_flexion_0_80_step10.mot");
  ASSERT_EQ(runModel(model, dir / "a", "determinism_a", "OMP_NUM_THREADS=1").exit_code, 0);
  ASSERT_EQ(runModel(model, dir / "b", "determinism_b", "OMP_NUM_THREADS=2").exit_code, 0);
  const StorageTable a = readStorage((dir / "a/outputs.sto").string());
  const StorageTable b = readStorage((dir / "b/outputs.sto").string());
  ASSERT_EQ(a.column_labels, b.column_labels);
  for (std::size_t c = 0; c < a.column_labels.size(); ++c) {
    const std::string& label = a.column_labels[c];
    if (label.size() > 3 && label.compare(label.size() - 3, 3, "_ms") == 0) continue;  // wall times
    for (std::size_t i = 0; i < a.rows.size(); ++i)  // NaN (a stage that did not run) equals NaN here
      if (!(std::isnan(a.rows[i][c]) && std::isnan(b.rows[i][c]))) {
        EXPECT_EQ(a.rows[i][c], b.rows[i][c]) << label << " row " << i;
      }
  }
}

TEST(RBFMusclePlugin, InfoListsTheComponent) {
  const HostResult r = test::runHost("info -L rbfmuscle_plugin RBFMuscle", "plugin", "info");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  for (const char* text : {"RBFMuscle", "mesh_file", "surface_file", "origin_area", "volume_ratio", "fibre_length_mm"})
    EXPECT_NE(r.out.find(text), std::string::npos) << text << "\n" << r.out;
}

TEST(RBFMusclePlugin, CacheOfAnotherMeshIsRefusedNotRefitted) {
  const fs::path dir = testDir("stale_cache");
  fs::copy_file(kHip / "surfaces/iliacus_r.rbf", dir / "stale.rbf");
  const HostResult r = runModel(writeModel(dir, (dir / "stale.rbf").string()), dir / "out", "stale_cache");
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("stale.rbf: fitted to a mesh with hash"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("never refitted silently"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(dir / "out"));
}

TEST(RBFMusclePlugin, AMissingAreaCloudIsNamedWithItsFile) {
  const fs::path dir = testDir("missing_cloud");
  const HostResult r = runModel(writeModel(dir, kCachedGluteus, kAreas + ": LC_SET_Ori_9_R_M081_Glut_Max"), dir / "out",
                                "missing_cloud");
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("no cloud \"LC_SET_Ori_9_R_M081_Glut_Max\""), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("attachment_areas.json"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(dir / "out"));
}

TEST(RBFMusclePlugin, AnAreaAwayFromTheMuscleIsRefused) {
  const fs::path dir = testDir("far_area");
  const HostResult r = runModel(writeModel(dir, kCachedGluteus, "0 0 0"), dir / "out", "far_area");
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("origin_area: no kernel centre lies within attachment_radius_mm"), std::string::npos) << r.err;
}

TEST(RBFMusclePlugin, AViaPointOnABodyTheSkeletonLacksIsRefusedNamingIt) {
  const fs::path dir = testDir("via_point_body");
  const HostResult r =
      runGluteusWith(dir, "--set 'glmax_r.line_of_action=180 300 -340 @ pelvis; 100 280 -530 @ femur'", "via_point_body");
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("line_of_action: via point 2: no body 'femur' in the skeleton"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(dir / "out"));
}

// Weights by distance stay a choice for joints without a centre.
TEST(RBFMusclePlugin, GluteusBlendedByDistanceKeepsVolumeFibresInsideAndLengthens) {
  const fs::path dir = testDir("blend_distance");
  const HostResult r = runGluteusWith(dir, "--set glmax_r.blend=distance", "blend_distance");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(r.err.find("blend by angle"), std::string::npos) << r.err;
  const StorageTable table = readStorage((dir / "out/outputs.sto").string());
  ASSERT_EQ(table.rows.size(), 9u);
  const int ratio = table.findColumn("glmax_r.volume_ratio"), outside = table.findColumn("glmax_r.fibre_points_outside");
  const int fibre = table.findColumn("glmax_r.fibre_length_ratio");
  for (size_t i = 0; i < table.rows.size(); ++i) {
    EXPECT_NEAR(table.rows[i][ratio], 1.0, 1e-3) << "row " << i;
    EXPECT_EQ(table.rows[i][outside], 0.0) << "row " << i;
    if (i > 0) {
      EXPECT_GT(table.rows[i][fibre], table.rows[i - 1][fibre]) << "row " << i;
    }
  }
}

// The default blend turns the tissue about the joint's centre; bones joined by no turning
// coordinate have none, and the error names the blend that works there.
TEST(RBFMusclePlugin, BonesThatCannotTurnAreRefusedByTheDefaultBlendNamingTheDistanceBlend) {
  const fs::path dir = testDir("fixed_joint");
  std::string urdf = test::readText(kHip / "hip_r.urdf");
  test::replaceAll(urdf, "type=\"revolute\"", "type=\"fixed\"");
  test::replaceAll(urdf, "filename=\"meshes/", "filename=\"" + (kHip / "meshes").string() + "/");
  std::ofstream(dir / "fixed.urdf") << urdf;
  const fs::path still = writeStillMotion(dir);
  const fs::path model = writeModel(dir, kCachedGluteus, kOrigin, still.string(), dir / "fixed.urdf");
  const HostResult r = runModel(model, dir / "out", "fixed_joint");
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("blend 'joint_angle': no rotational coordinate turns femur_r relative to pelvis; use 'distance'"),
            std::string::npos)
      << r.err;
  EXPECT_FALSE(fs::exists(dir / "out"));
}

TEST(RBFMusclePlugin, AMuscleSegmentedIntoItsBoneIsMovedOutAtRestWithAWarningEvenWithoutContacts) {
  // The psoas lies up to 3.5 mm inside the ilium as segmented. Its stored surface is the fit of
  // the moved mesh, so the run loads it from the cache.
  const fs::path dir = testDir("moved_out");
  const fs::path still = writeStillMotion(dir);
  const fs::path model = dir / "psoas.xml";
  std::ofstream(model) << "<?xml version=\"1.0\"?>\n<RBFMuscleModel version=\"1\" name=\"psoas_test\">\n"
                       << "  <skeleton file=\"" << (kHip / "hip_r.urdf").string() << "\"/>\n"
                       << "  <plugin file=\"librbfmuscle_plugin.so\"/>\n"
                       << "  <motion file=\"" << still.string() << "\"/>\n"
                       << "  <components>\n    <RBFMuscle name=\"psoas_r\">\n"
                       << "      <mesh_file>" << (kHip / "meshes/psoas_major_r.ply").string() << "</mesh_file>\n"
                       << "      <surface_file>" << (kHip / "surfaces/psoas_major_r.rbf").string() << "</surface_file>\n"
                       << "      <origin_area>" << kAreas << ": LC_SET_Ori_1_R_M090_Psoas_maj</origin_area>\n"
                       << "      <insertion_area>" << kAreas << ": LC_SET_Ins_1_R_M090_Psoas_maj</insertion_area>\n"
                       << "      <contacts>false</contacts>\n"
                       << "      <socket_origin_body>pelvis</socket_origin_body>\n"
                       << "      <socket_insertion_body>femur_r</socket_insertion_body>\n"
                       << "    </RBFMuscle>\n  </components>\n</RBFMuscleModel>\n";
  const HostResult r = runModel(model, dir / "out", "moved_out");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.err.find("psoas_major_r.ply: 70 vertices lay more than 0.5 mm inside the solids it must not enter "
                       "(the deepest 3.52 mm, in pelvis_iliac_r.ply)"),
            std::string::npos)
      << r.err;
  EXPECT_EQ(r.err.find("fitting"), std::string::npos) << r.err;
}

TEST(RBFMusclePlugin, AnUnknownBlendIsRefusedNamingTheOnesThereAre) {
  const fs::path dir = testDir("unknown_blend");
  const HostResult r = runGluteusWith(dir, "--set glmax_r.blend=angle", "unknown_blend");
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("blend: 'angle'; expected 'distance' or 'joint_angle'"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("glmax_r"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(dir / "out"));
}

TEST(RBFMusclePlugin, AFormerPropertyNameIsRefusedListingTheCurrentOnes) {
  const fs::path dir = testDir("former_property");
  const HostResult r = runGluteusWith(dir, "--set glmax_r.max_surface_step_mm=0.5", "former_property");
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("max_surface_step_mm"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("origin_area"), std::string::npos) << "lists the properties there are:\n" << r.err;
}

TEST(RBFMusclePlugin, StageSettingsAreSubcomponentsSetInTheFileOrOnTheCommandLine) {
  const fs::path dir = testDir("subcomponents");
  const fs::path model = writeModel(dir, kCachedGluteus);
  // From the command line: 7 fibres of 4 segments, one fibre_length_mm column each; the count
  // named as `rbfmuscle info` lists it.
  const HostResult r = test::runHost("run '" + model.string() + "' -o '" + (dir / "out").string() +
                                         "' --quiet --motion '" + (kHip / "motions/hip_flexion_0_80_step10.mot").string() +
                                         "' --set glmax_r.fibres/count=7 --set glmax_r/fibres.segments=4",
                                     "plugin", "subcomponents");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const StorageTable table = readStorage((dir / "out/outputs.sto").string());
  EXPECT_GE(table.findColumn("glmax_r.fibre_length_mm_6"), 0);
  EXPECT_LT(table.findColumn("glmax_r.fibre_length_mm_7"), 0);
  // The former flat property is refused, saying how to write it now.
  const HostResult former = test::runHost("run '" + model.string() + "' -o '" + (dir / "out2").string() +
                                              "' --quiet --set glmax_r.fibres=50",
                                          "plugin", "subcomponents_former");
  EXPECT_EQ(former.exit_code, 1);
  EXPECT_NE(former.err.find("'fibres' is a subcomponent: give its properties inside, as <fibres><PROPERTY>value</PROPERTY>"
                            "</fibres> (its properties: count, segments)"),
            std::string::npos)
      << former.err;
  const HostResult range = test::runHost("run '" + model.string() + "' -o '" + (dir / "out3").string() +
                                             "' --quiet --set glmax_r/descent.iterations=-1",
                                         "plugin", "subcomponents_range");
  EXPECT_EQ(range.exit_code, 1);
  EXPECT_NE(range.err.find("property 'iterations': value -1 is outside the allowed range"), std::string::npos) << range.err;
}

TEST(RBFMusclePlugin, SurfaceFileLeavingTheModelDirectoryIsRefusedAndNothingIsWritten) {
  // A surface_file of ../../x.rbf used to receive the fit, even when the run then failed.
  const fs::path dir = testDir("escape");
  const fs::path model_dir = dir / "model";
  fs::create_directories(model_dir);
  const HostResult r = runModel(writeModel(model_dir, "../escaped.rbf"), dir / "out", "escape");
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_NE(r.err.find("path '../escaped.rbf' leaves the model directory " + model_dir.string()), std::string::npos)
      << r.err;
  EXPECT_FALSE(fs::exists(dir / "escaped.rbf"));
  EXPECT_FALSE(fs::exists(dir / "out"));
}

TEST(RBFMusclePlugin, CacheWithAnImplausibleWeightIsRefusedNamingTheLine) {
  // One weight of 1e308 used to give curvature_cost = -nan in every frame, with exit 0.
  const fs::path dir = testDir("weight_1e308");
  std::ifstream in(kCachedGluteus);
  std::string line, text;
  int line_number = 0, bad_line = 0;
  bool in_centres = false;
  while (std::getline(in, line)) {
    ++line_number;
    if (in_centres && bad_line == 0 && !line.empty() && line[0] != '#') {
      std::istringstream fields(line);
      std::string x, y, z, weight, shape;
      fields >> x >> y >> z >> weight >> shape;
      line = x + " " + y + " " + z + " 1e308 " + shape;
      bad_line = line_number;
    }
    if (line.rfind("centres ", 0) == 0) in_centres = true;
    text += line + "\n";
  }
  std::ofstream(dir / "bad.rbf") << text;
  const HostResult r = runModel(writeModel(dir, (dir / "bad.rbf").string()), dir / "out", "weight_1e308");
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_NE(r.err.find("bad.rbf:" + std::to_string(bad_line) + ": centre 0: weight 1e+308 has a magnitude above 1e+06"),
            std::string::npos)
      << r.err;
  EXPECT_FALSE(fs::exists(dir / "out"));
}

TEST(RBFMusclePlugin, MeshFileThatIsNotAMeshIsReportedAsSuch) {
  // mesh_file = /etc/passwd used to be hashed, and the message advised deleting the .rbf.
  const fs::path dir = testDir("not_a_mesh");
  std::string model = test::readText(writeModel(dir, kCachedGluteus));
  const std::string mesh = (kHip / "meshes/gluteus_maximus_r.ply").string();
  model.replace(model.find(mesh), mesh.size(), "/etc/passwd");
  std::ofstream(dir / "model.xml") << model;
  const HostResult r = runModel(dir / "model.xml", dir / "out", "not_a_mesh");
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_NE(r.err.find("/etc/passwd: cannot read mesh"), std::string::npos) << r.err;
  EXPECT_EQ(r.err.find("delete the .rbf"), std::string::npos) << r.err;
}

}  // namespace
}  // namespace rbfmuscle
