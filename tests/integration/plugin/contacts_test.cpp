/// Bone contacts of the RBFMuscle component through the host (issue 5): the gluteus maximus
/// over 0°, 10°, 20° hip flexion against the pelvis and femur meshes, measured only (the
/// default) and with the response on. The iliacus with the response, through 80°, is checked by
/// hip_flexion_scene_test.cpp (the main job).
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>

#include "model/storage_file.h"
#include "support/run_host.h"

namespace rbfmuscle {
namespace {

namespace fs = std::filesystem;

const fs::path kHip = fs::path(RBFMUSCLE_SOURCE_DIR) / "models/hip";

fs::path testDir(const std::string& name) {
  const fs::path dir = fs::path(RBFMUSCLE_BINARY_DIR) / "test_out/plugin_contacts" / name;
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

/// A gluteus-only model (cached surface, no fibres) over 0°, 10°, 20° flexion, in `dir`.
fs::path writeModel(const fs::path& dir, bool respond) {
  std::ofstream(dir / "motion.mot") << "flexion_0_20\nversion=1\nnRows=3\nnColumns=4\ninDegrees=yes\nendheader\n"
                                    << "time\thip_flexion_r\thip_adduction_r\thip_rotation_r\n"
                                    << "0\t0\t0\t0\n0.0333\t10\t0\t0\n0.0667\t20\t0\t0\n";
  const fs::path path = dir / "model.xml";
  std::ofstream(path) << "<?xml version=\"1.0\"?>\n<RBFMuscleModel version=\"1\" name=\"contacts_test\">\n"
                      << "  <skeleton file=\"" << (kHip / "hip_r.urdf").string() << "\"/>\n"
                      << "  <plugin file=\"librbfmuscle_plugin.so\"/>\n"
                      << "  <motion file=\"" << (dir / "motion.mot").string() << "\"/>\n"
                      << "  <components>\n    <RBFMuscle name=\"glmax_r\">\n"
                      << "      <mesh_file>" << (kHip / "meshes/gluteus_maximus_r.ply").string() << "</mesh_file>\n"
                      << "      <surface_file>" << (kHip / "surfaces/gluteus_maximus_r.rbf").string()
                      << "</surface_file>\n"
                      << "      <origin_landmarks_mm>173.636 292.942 -314.153; 184.221 303.199 -338.869; "
                         "219.705 304.358 -400.427</origin_landmarks_mm>\n"
                      << "      <insertion_landmarks_mm>99.428 282.659 -483.674; 102.304 275.524 -529.532; "
                         "101.32 270.787 -570.348</insertion_landmarks_mm>\n"
                      << "      <landmark_radius_mm>25</landmark_radius_mm>\n"
                      << "      <fibres>0</fibres>\n"
                      << "      <contact_probes>1000</contact_probes>\n"
                      << "      <contact_response>" << (respond ? "true" : "false") << "</contact_response>\n"
                      << "      <socket_origin_body>pelvis</socket_origin_body>\n"
                      << "      <socket_insertion_body>femur_r</socket_insertion_body>\n"
                      << "    </RBFMuscle>\n  </components>\n</RBFMuscleModel>\n";
  return path;
}

StorageTable runModel(const std::string& name, bool respond) {
  const fs::path dir = testDir(name);
  const test::HostResult r =
      test::runHost("run '" + writeModel(dir, respond).string() + "' -o '" + (dir / "out").string() + "' --quiet",
                    "plugin_contacts", name);
  EXPECT_EQ(r.exit_code, 0) << r.err;
  return readStorage((dir / "out/outputs.sto").string());
}

TEST(RBFMuscleContacts, MeasuredByDefaultRestOverlapIsNotPenetration) {
  const StorageTable table = runModel("measure", false);
  ASSERT_EQ(table.rows.size(), 3u);
  const int penetration = table.findColumn("glmax_r.max_penetration_mm");
  const int substeps = table.findColumn("glmax_r.substeps");
  const int ms = table.findColumn("glmax_r.collision_ms");
  const int contacts = table.findColumn("glmax_r.contacts");
  const int iterations = table.findColumn("glmax_r.contact_iterations");
  ASSERT_GE(penetration, 0);
  ASSERT_GE(substeps, 0);
  ASSERT_GE(ms, 0);
  ASSERT_GE(contacts, 0);
  ASSERT_GE(iterations, 0);
  // At rest every probe inside a bone is rest overlap, excluded: nothing penetrates.
  EXPECT_LE(table.rows[0][penetration], 1e-9);
  for (const std::vector<double>& row : table.rows) {
    EXPECT_GE(row[penetration], 0.0);
    EXPECT_TRUE(std::isfinite(row[penetration]));
    EXPECT_EQ(row[substeps], 1.0);  // measuring only: no sub-steps
    EXPECT_EQ(row[iterations], 0.0);
    EXPECT_GT(row[ms], 0.0);
  }
}

TEST(RBFMuscleContacts, ResponseKeepsTheGluteusOutOfTheBones) {
  const StorageTable table = runModel("respond", true);
  ASSERT_EQ(table.rows.size(), 3u);
  const int penetration = table.findColumn("glmax_r.max_penetration_mm");
  const int substeps = table.findColumn("glmax_r.substeps");
  ASSERT_GE(penetration, 0);
  for (const std::vector<double>& row : table.rows) {
    EXPECT_LE(row[penetration], 0.5);
    EXPECT_GE(row[substeps], 1.0);
    EXPECT_LE(row[substeps], 8.0);
  }
}

}  // namespace
}  // namespace rbfmuscle
