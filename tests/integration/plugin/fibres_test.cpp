/// Fibres of the RBFMuscle plugin through the host: gluteus maximus and iliacus
/// over hip flexion 0→80° in 10° frames, with their line-of-action paths
/// (models/hip/landmarks/line_of_action_paths.json: glmax2_r, iliacus_r).
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>

#include "model/storage_file.h"
#include "support/run_host.h"

namespace rbfmuscle {
namespace {

namespace fs = std::filesystem;

const fs::path kHip = fs::path(RBFMUSCLE_SOURCE_DIR) / "models/hip";

/// One muscle element of the hip flexion scene (models/hip/hip_flexion.xml) with a path.
std::string muscleXml(const std::string& name, const std::string& mesh, const std::string& surface,
                      const std::string& origin, const std::string& insertion, const std::string& path) {
  return "    <RBFMuscle name=\"" + name + "\">\n      <mesh_file>" + (kHip / "meshes" / mesh).string() +
         "</mesh_file>\n      <surface_file>" + (kHip / "surfaces" / surface).string() +
         "</surface_file>\n      <origin_landmarks_mm>" + origin + "</origin_landmarks_mm>\n" +
         "      <insertion_landmarks_mm>" + insertion + "</insertion_landmarks_mm>\n" +
         "      <landmark_radius_mm>25</landmark_radius_mm>\n      <line_of_action_mm>" + path +
         "</line_of_action_mm>\n      <socket_origin_body>pelvis</socket_origin_body>\n" +
         "      <socket_insertion_body>femur_r</socket_insertion_body>\n    </RBFMuscle>\n";
}

class HipFlexionFibres : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    // ctest runs each TEST in its own process, possibly in parallel: one directory per process.
    const std::string tag = "fibres_" + std::to_string(::getpid());
    dir_ = fs::path(RBFMUSCLE_BINARY_DIR) / "test_out/plugin" / tag;
    fs::remove_all(dir_);
    fs::create_directories(dir_);
    const fs::path model = dir_ / "model.xml";
    std::ofstream(model)
        << "<?xml version=\"1.0\"?>\n<RBFMuscleModel version=\"1\" name=\"fibres_test\">\n"
        << "  <skeleton file=\"" << (kHip / "hip_r.urdf").string() << "\"/>\n"
        << "  <plugin file=\"librbfmuscle_plugin.so\"/>\n"
        << "  <motion file=\"" << (kHip / "motions/hip_flexion_0_80_step10.mot").string() << "\"/>\n"
        << "  <components>\n"
        << muscleXml("glmax_r", "gluteus_maximus_r.ply", "gluteus_maximus_r.rbf",
                     "173.636 292.942 -314.153; 184.221 303.199 -338.869; 219.705 304.358 -400.427",
                     "99.428 282.659 -483.674; 102.304 275.524 -529.532; 101.32 270.787 -570.348",
                     "184.221 303.199 -338.869; 148.929 318.169 -406.071; 122.946 297.219 -484.096; "
                     "102.304 275.524 -529.532")
        << muscleXml("iliacus_r", "iliacus_r.ply", "iliacus_r.rbf", "138.474 235.451 -324.078",
                     "124.427 265.109 -493.253",
                     "138.474 235.451 -324.078; 140.054 198.662 -415.025; 128.956 253.909 -487.469; "
                     "124.427 265.109 -493.253")
        << "  </components>\n</RBFMuscleModel>\n";
    result_ = test::runHost("run '" + model.string() + "' -o '" + (dir_ / "out").string() + "' --frames-mesh --quiet",
                            "plugin", tag);
    if (result_.exit_code == 0) table_ = readStorage((dir_ / "out/outputs.sto").string());
  }
  static void TearDownTestSuite() { fs::remove_all(dir_); }
  /// Value of `column` at frame `row` (row k = 10k degrees).
  static double at(const std::string& column, int row) {
    const int c = table_.findColumn(column);
    EXPECT_GE(c, 0) << column;
    return c < 0 ? NAN : table_.rows[static_cast<size_t>(row)][static_cast<size_t>(c)];
  }
  static fs::path dir_;
  static test::HostResult result_;
  static StorageTable table_;
};
fs::path HipFlexionFibres::dir_;
test::HostResult HipFlexionFibres::result_;
StorageTable HipFlexionFibres::table_;

TEST_F(HipFlexionFibres, RunsAndWritesEveryFibre) {
  ASSERT_EQ(result_.exit_code, 0) << result_.err;
  ASSERT_EQ(table_.rows.size(), 9u);
  for (const char* muscle : {"glmax_r", "iliacus_r"}) {
    const std::string m(muscle);
    EXPECT_GE(table_.findColumn(m + ".fiber_length_mm_99"), 0);
    EXPECT_LT(table_.findColumn(m + ".fiber_length_mm_100"), 0);
    for (int row = 0; row < 9; ++row) {
      EXPECT_LE(at(m + ".fiber_length_min_mm", row), at(m + ".fiber_length_mean_mm", row));
      EXPECT_LE(at(m + ".fiber_length_mean_mm", row), at(m + ".fiber_length_max_mm", row));
      EXPECT_TRUE(std::isfinite(at(m + ".fiber_projections", row)));
      EXPECT_GE(at(m + ".fiber_points_outside", row), 0);
    }
    EXPECT_NEAR(at(m + ".fiber_length_normalised", 0), 1.0, 1e-9);
  }
  EXPECT_TRUE(fs::exists(dir_ / "out/glmax_r_fibres.pvd"));
}

// Issue 6: every fibre point inside (f > 0) through 80° flexion, fibre ends included, and
// the ends within 0.5 mm of their bone's motion (they move rigidly with it, the generator
// picks them at depth f ≥ end_depth, and the tracker pushes one that falls outside in by
// at most end_max_move_mm = 0.499 mm).
void expectEveryFibrePointInsideAndEndsOnTheirBones(const std::string& muscle, const StorageTable& table) {
  const int outside = table.findColumn(muscle + ".fiber_points_outside");
  const int end_offset = table.findColumn(muscle + ".fiber_end_offset_max_mm");
  ASSERT_GE(outside, 0);
  ASSERT_GE(end_offset, 0);
  for (size_t row = 0; row < table.rows.size(); ++row) {
    EXPECT_EQ(table.rows[row][static_cast<size_t>(outside)], 0) << muscle << " frame " << row;
    EXPECT_LE(table.rows[row][static_cast<size_t>(end_offset)], 0.5) << muscle << " frame " << row;
  }
}

TEST_F(HipFlexionFibres, EveryIliacusFibrePointStaysInsideAndItsEndsOnTheirBones) {
  ASSERT_EQ(result_.exit_code, 0) << result_.err;
  expectEveryFibrePointInsideAndEndsOnTheirBones("iliacus_r", table_);
}

TEST_F(HipFlexionFibres, EveryGluteusFibrePointStaysInsideAndItsEndsOnTheirBones) {
  ASSERT_EQ(result_.exit_code, 0) << result_.err;
  expectEveryFibrePointInsideAndEndsOnTheirBones("glmax_r", table_);
}

TEST_F(HipFlexionFibres, GluteusLengthensAndIliacusShortens) {
  ASSERT_EQ(result_.exit_code, 0) << result_.err;
  for (const char* muscle : {"glmax_r", "iliacus_r"}) {
    const std::string m(muscle);
    const double loa0 = at(m + ".line_of_action_length_mm", 0);
    std::printf("%s: fibres normalised mean 40° %.4f 80° %.4f | line of action ratio 40° %.4f 80° %.4f | "
                "projections 40° %.0f 80° %.0f\n",
                muscle, at(m + ".fiber_length_normalised", 4), at(m + ".fiber_length_normalised", 8),
                at(m + ".line_of_action_length_mm", 4) / loa0, at(m + ".line_of_action_length_mm", 8) / loa0,
                at(m + ".fiber_projections", 4), at(m + ".fiber_projections", 8));
  }
  EXPECT_GT(at("glmax_r.fiber_length_normalised", 8), 1.0);
  EXPECT_LT(at("iliacus_r.fiber_length_normalised", 8), 1.0);
  // The line of action agrees on the direction.
  EXPECT_GT(at("glmax_r.line_of_action_length_mm", 8), at("glmax_r.line_of_action_length_mm", 0));
  EXPECT_LT(at("iliacus_r.line_of_action_length_mm", 8), at("iliacus_r.line_of_action_length_mm", 0));
}

}  // namespace
}  // namespace rbfmuscle
