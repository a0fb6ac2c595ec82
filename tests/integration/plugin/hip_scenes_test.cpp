// SPDX-License-Identifier: Apache-2.0
/// The hip scenes (gluteus maximus, iliacus and psoas major on the subject's own pelvis), run
/// through the host as the README does, with their frame meshes. At every frame, for every
/// muscle: finite outputs, the volume held, and every tracked surface vertex at most 0.5 mm
/// inside the femur, the ilium or the sacrum (exact distance to the posed meshes), and every
/// fibre end within 0.5 mm of its place on its bone, every fibre's first and last point (its
/// attachments) within 0.5 mm of its origin area on the pelvis and its insertion area on the
/// femur (the scene's clouds, posed), and its hip flexion moment arm of the
/// published sign (the gluteus extends the hip, the iliacus and the psoas flex it), and every
/// fibre point inside, and no fibre length changing by more than 1 % since the last frame, and no vertex of its tracked surface further from the previous frame's
/// surface (its tracked mesh, or the vertex's own last place where that mesh lost triangles)
/// than the femur moves there plus 1 mm; the volume (counted on a 2 mm grid, check_pieces_cell_mm)
/// of every muscle in one piece in every scene (the psoas's in the rotation because its mesh,
/// segmented up to 3.5 mm inside the ilium, is moved out of it at rest: docs/design.md, Contacts
/// by composition); the gluteus's tracked surface in one piece in every scene, and the
/// iliacus's in adduction, rotation and gait (counting pieces at least the 2 mm cell across).
/// Where a muscle lies on a bone its tracked vertices find no surface and their triangles are
/// dropped, which cuts the tracked mesh of the iliacus and the psoas in flexion; the pieces of
/// both are printed for every muscle. The main job's flexion
/// (0→80° in 1° frames) runs again in 10° frames, and the gluteus flexes on to 120°, with the same
/// checks. In the main job also: the gluteus's fibres lengthen and the iliacus's and the psoas's
/// shorten at every frame, the psoas to at most 0.93 of its rest length, and the gluteus's hip
/// flexion moment arm falls from 40° to 60° (also in 10° frames), as measured.
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "collision/bone_distance_grid.h"
#include "framework/frame_geometry.h"
#include "framework/model_document.h"
#include "geometry/mesh_distance.h"
#include "geometry/mesh_io.h"
#include "geometry/mesh_measures.h"
#include "model/attachment_areas.h"
#include "model/motion.h"
#include "model/skeleton.h"
#include "model/storage_file.h"
#include "support/run_host.h"

namespace rbfmuscle {
namespace {

namespace fs = std::filesystem;
const fs::path kHip = fs::path(RBFMUSCLE_SOURCE_DIR) / "models/hip";
const std::vector<std::string> kMuscles = {"glmax_r", "iliacus_r", "psoas_r"};
/// Grid cell of the pieces count (check_pieces_cell_mm), and the least size of a tracked surface's
/// piece: the rest surface's cell.
constexpr double kPieceCellMm = 2.0;

/// A bone for the checks: the exact distance, and a grid only to skip vertices far from it.
struct Bone {
  explicit Bone(const std::string& name)
      : exact(std::make_shared<MeshDistance>(loadMesh((kHip / "meshes" / (name + ".ply")).string()))), grid(exact) {}
  /// Depth of p_B inside the bone (mm, ≤ 0 outside); the grid's bound decides when it is far.
  double calcDepth(const Eigen::Vector3d& p_B) const {
    if (grid.sample(p_B).value_mm > 2.0) return 0.0;  // the grid errs by under √3/2 of its 1 mm cell
    return -exact->calcSignedDistance(p_B);
  }
  std::shared_ptr<MeshDistance> exact;
  BoneDistanceGrid grid;
};

/// The vertices a frame mesh's triangles use (the others found no surface; see SurfaceStage).
std::vector<char> findUsed(const FrameGeometry& g) {
  std::vector<char> used(static_cast<size_t>(g.vertices_mm.cols()), 0);
  for (Eigen::Index t = 0; t < g.triangles.cols(); ++t)
    for (int c = 0; c < 3; ++c) used[static_cast<size_t>(g.triangles(c, t))] = 1;
  return used;
}

FrameGeometry readFrame(const fs::path& meshes, const std::string& muscle, int frame) {
  char file[32];
  std::snprintf(file, sizeof file, "_%05d.vtp", frame);
  return readVtp((meshes / (muscle + file)).string());
}

/// What a scene's check asserts beyond the every-frame checks, per muscle.
struct SceneChecks {
  std::vector<std::string> muscles = kMuscles;                      ///< the muscles checked
  std::vector<std::string> one_piece;  ///< the volume in one piece (check_pieces_cell_mm)
  /// the tracked surface in one piece (where a muscle lies on a bone, its tracked vertices there
  /// find no surface and their triangles are dropped, which can cut the tracked mesh; see
  /// SurfaceStage)
  std::vector<std::string> surface_one_piece;
  std::vector<std::string> fibres_inside = kMuscles;                ///< every fibre point inside
  std::vector<std::string> fibres_monotone;  ///< the gluteus lengthens, the others shorten
  /// the sign of the hip flexion moment arm (mean over fibres) asserted at every frame
  std::vector<std::string> flexion_sign = kMuscles;
  /// the largest fibre length ratio allowed at the last frame, per muscle
  std::map<std::string, double> last_ratio_at_most;
  /// the hip flexion moment arm's magnitude falls from 40° to 60° of flexion, as measured for the
  /// gluteus maximus (models/reference: Németh & Ohlsén 1985, 62 → 51 mm)
  std::vector<std::string> arm_falls_from_40_to_60;
  /// the most any fibre's length may change between consecutive frames, relative: 1 % for
  /// frames about 1° apart (the gait's flexion steps by up to 1.4°, and passes it too)
  double fibre_step_at_most = 0.01;
};

/// The muscle's hip flexion moment arm at the row whose flexion is nearest `degrees`.
double calcArmAtFlexion(const StorageTable& table, const std::string& muscle, double degrees) {
  const int q = table.findColumn("hip_flexion_r"), arm = table.findColumn(muscle + ".moment_arm_hip_flexion_r_mm");
  EXPECT_GE(q, 0);
  EXPECT_GE(arm, 0);
  if (q < 0 || arm < 0) return NAN;
  size_t best = 0;
  for (size_t row = 0; row < table.rows.size(); ++row)
    if (std::abs(table.rows[row][static_cast<size_t>(q)] - degrees * M_PI / 180.0) <
        std::abs(table.rows[best][static_cast<size_t>(q)] - degrees * M_PI / 180.0))
      best = row;
  EXPECT_NEAR(table.rows[best][static_cast<size_t>(q)], degrees * M_PI / 180.0, 1e-6) << "no frame at " << degrees << "°";
  return table.rows[best][static_cast<size_t>(arm)];
}

/// Sign of each muscle's hip flexion moment arm (OpenSim's: + when the muscle shortens as the
/// hip flexes) that every source of models/reference agrees on: the gluteus maximus extends the
/// hip, the iliacus and the psoas flex it. (Their adduction and rotation moment arms are small
/// and change sign between fibres and between studies; no sign is asserted for them.)
double publishedFlexionSign(const std::string& muscle) { return muscle == "glmax_r" ? -1.0 : 1.0; }

bool holds(const std::vector<std::string>& muscles, const std::string& muscle) {
  return std::find(muscles.begin(), muscles.end(), muscle) != muscles.end();
}

/// The femur's motion (rest → frame, ground) at every frame of the motion at `motion_path`.
std::vector<Eigen::Isometry3d> calcFemurMotions(const fs::path& motion_path) {
  Skeleton skeleton = Skeleton::fromUrdf((kHip / "hip_r.urdf").string());
  const Motion motion = Motion::fromFile(motion_path.string(), skeleton);
  const int femur_body = skeleton.findBodyIndex("femur_r");
  skeleton.setCoordinateValues(Eigen::VectorXd::Zero(static_cast<Eigen::Index>(skeleton.getCoordinateNames().size())));
  const Eigen::Isometry3d X_GF_rest = skeleton.getBodyTransform(femur_body);
  std::vector<Eigen::Isometry3d> femur_motion;
  for (int frame = 0; frame < motion.getNumFrames(); ++frame) {
    skeleton.setCoordinateValues(motion.getCoordinates(frame));
    femur_motion.push_back(skeleton.getBodyTransform(femur_body) * X_GF_rest.inverse());
  }
  return femur_motion;
}

/// The every-frame checks of one muscle's outputs at `row`; returns its fibre points outside.
double checkOutputs(const StorageTable& table, size_t row, const std::string& muscle, const SceneChecks& checks) {
  const auto column = [&](const std::string& name) {
    const int c = table.findColumn(muscle + "." + name);
    EXPECT_GE(c, 0) << muscle << "." << name;
    return static_cast<size_t>(std::max(c, 0));
  };
  const std::vector<double>& r = table.rows[row];
  for (size_t c = 0; c < r.size(); ++c) {
    const std::string& label = table.column_labels[c];
    // stray_centre_mm is NaN while the muscle is in one piece.
    if (label.rfind(muscle + ".", 0) == 0 && label.rfind(muscle + ".stray_centre_mm", 0) != 0) {
      EXPECT_TRUE(std::isfinite(r[c])) << label << " frame " << row;
    }
  }
  const size_t outside = column("fibre_points_outside"), fibre = column("fibre_length_ratio");
  EXPECT_NEAR(r[column("volume_ratio")], 1.0, 2e-3) << muscle << " frame " << row;
  EXPECT_LE(r[column("fibre_end_offset_max_mm")], 0.5) << muscle << ": a fibre end left its place on its bone at frame "
                                                        << row;
  if (holds(checks.fibres_inside, muscle)) {
    EXPECT_EQ(r[outside], 0.0) << muscle << " fibre points outside at frame " << row;
  }
  if (holds(checks.flexion_sign, muscle)) {
    EXPECT_GT(publishedFlexionSign(muscle) * r[column("moment_arm_hip_flexion_r_mm")], 0.0)
        << muscle << "'s hip flexion moment arm has the wrong sign at frame " << row;
  }
  if (row > 0) {
    const std::string prefix = muscle + ".fibre_length_mm_";
    for (size_t c = 0; c < r.size(); ++c)
      if (table.column_labels[c].rfind(prefix, 0) == 0) {
        EXPECT_LE(std::abs(r[c] / table.rows[row - 1][c] - 1.0), checks.fibre_step_at_most)
            << table.column_labels[c] << " steps between frames " << row - 1 << " and " << row;
      }
  }
  if (holds(checks.fibres_monotone, muscle) && row > 0) {
    if (muscle == "glmax_r") EXPECT_GT(r[fibre], table.rows[row - 1][fibre]) << muscle << " lengthens, frame " << row;
    else EXPECT_LT(r[fibre], table.rows[row - 1][fibre]) << muscle << " shortens, frame " << row;
  }
  return r[outside];
}

/// A muscle's origin (index 0, on the pelvis) and insertion (1, on the femur) areas at rest as
/// the scene names them (ground, mm).
std::array<Eigen::Matrix3Xd, 2> readAreas(const std::string& scene, const std::string& muscle) {
  const ModelDocument document = readModelDocument((kHip / (scene + ".xml")).string());
  std::array<Eigen::Matrix3Xd, 2> areas;
  for (const ComponentSpec& component : document.components) {
    if (component.name != muscle) continue;
    for (const PropertySpec& property : component.properties)
      for (int end = 0; end < 2; ++end)
        if (property.name == (end == 0 ? "origin_area" : "insertion_area"))
          areas[static_cast<size_t>(end)] = joinAreas(parseAttachmentAreaSpec(property.text, document.directory));
  }
  EXPECT_GT(areas[0].cols(), 0) << muscle << " has no origin area in " << scene;
  EXPECT_GT(areas[1].cols(), 0) << muscle << " has no insertion area in " << scene;
  return areas;
}

/// The farthest of a frame's fibre attachments (each polyline's first and last point) from the
/// nearest point of its area, the pelvis's at rest and the femur's moved by `femur_motion` (mm).
double calcAttachmentOffset(const FrameGeometry& fibres, const std::array<Eigen::Matrix3Xd, 2>& areas,
                            const Eigen::Isometry3d& femur_motion) {
  EXPECT_FALSE(fibres.polylines.empty());
  double farthest = 0.0;
  for (const std::vector<int>& line : fibres.polylines)
    for (int end = 0; end < 2; ++end) {
      const Eigen::Vector3d p = fibres.vertices_mm.col(end == 0 ? line.front() : line.back());
      const Eigen::Vector3d p_rest = end == 0 ? p : Eigen::Vector3d(femur_motion.inverse() * p);
      const double to_area = std::sqrt((areas[static_cast<size_t>(end)].colwise() - p_rest).colwise().squaredNorm().minCoeff());
      farthest = std::max(farthest, to_area);
    }
  return farthest;
}

/// The bones a tracked surface must stay out of (the femur in its own frame).
struct SceneBones {
  Bone femur{"femur_r"}, ilium{"pelvis_iliac_r"}, sacrum{"pelvis_sacrum"};
};

/// One muscle's tracked surface followed over the frames: its deepest vertex in a bone, its
/// worst jump beyond the femur's move + 1 mm, and its most pieces.
class SurfaceWatch {
 public:
  explicit SurfaceWatch(const SceneBones& bones) : bones_(bones) {}

  /// Adds frame `row`, the femur moved by `femur_motion` (rest → frame) and by `femur_step` since
  /// the last frame; returns the frame's pieces.
  int addFrame(const FrameGeometry& g, int row, const Eigen::Isometry3d& femur_motion,
               const Eigen::Isometry3d& femur_step) {
    const std::vector<char> used = findUsed(g);
    TriangleMesh surface;
    surface.vertices_mm = g.vertices_mm;
    surface.triangles = g.triangles;
    // Pieces of the surface the triangles make, at least a cell of the tracked surface across: a
    // speck smaller than that (a few vertices left among those that found no surface) is below
    // the tracked mesh's resolution, as the volume's pieces are counted on a grid of that cell.
    int pieces = 0;
    for (double size_mm : calcComponentSizes(surface)) (size_mm >= kPieceCellMm ? pieces : specks) += 1;
    most_pieces = std::max(most_pieces, pieces);
    const Eigen::Isometry3d X_FG = femur_motion.inverse();
    for (Eigen::Index v = 0; v < g.vertices_mm.cols(); ++v) {
      if (!used[static_cast<size_t>(v)]) continue;
      const Eigen::Vector3d y = g.vertices_mm.col(v);
      const double depth = std::max({bones_.femur.calcDepth(X_FG * y), bones_.ilium.calcDepth(y), bones_.sacrum.calcDepth(y)});
      if (depth > worst_depth) worst_depth = depth, worst_depth_frame = row;
      // A vertex that found no surface in the previous frame lay where a bone held the muscle;
      // the surface there was the bone's contact patch, which the tracked mesh leaves out.
      if (!previous_ || !previous_used_[static_cast<size_t>(v)]) continue;
      const double allowance = (femur_step.inverse() * y - y).norm() + 1.0;  // the femur's move at y
      // The previous surface is at most as far as the vertex's own last place, which was on it
      // even where the tracked mesh there lost its triangles beside a contact patch.
      const double jump = std::min(previous_->calcUnsignedDistance(y), (y - previous_vertices_.col(v)).norm()) - allowance;
      if (jump > worst_jump) worst_jump = jump, worst_jump_frame = row;
      if (jump > 0.0 && first_jump_frame < 0) first_jump_frame = row;
    }
    previous_ = std::make_unique<MeshDistance>(std::move(surface), false);
    previous_used_ = used;
    previous_vertices_ = g.vertices_mm;
    return pieces;
  }

  double worst_depth = 0.0, worst_jump = -1e9;
  int worst_depth_frame = 0, worst_jump_frame = 0, first_jump_frame = -1, most_pieces = 0;
  int specks = 0;  ///< pieces less than a cell across, over all frames

 private:
  const SceneBones& bones_;
  std::unique_ptr<MeshDistance> previous_;  // the previous frame's surface
  std::vector<char> previous_used_;
  Eigen::Matrix3Xd previous_vertices_;
};

/// Runs `scene` (models/hip/SCENE.xml with the motion models/hip/motions/MOTION_FILE) and
/// checks every frame (file comment).
void checkScene(const std::string& scene, const std::string& motion_file, const SceneChecks& checks) {
  const fs::path motion_path = kHip / "motions" / motion_file;
  const std::string tag = scene + "_" + std::to_string(::getpid());
  const fs::path out = fs::path(RBFMUSCLE_BINARY_DIR) / "test_out/plugin" / tag;
  fs::remove_all(out);
  std::string moment_arms;
  for (const std::string& muscle : checks.muscles)
    moment_arms += " --set " + muscle + ".moment_arms=hip_flexion_r --set " + muscle + ".check_pieces_cell_mm=" +
                   std::to_string(kPieceCellMm);
  const test::HostResult result = test::runHost(
      "run '" + (kHip / (scene + ".xml")).string() + "' -o '" + out.string() + "' --motion '" + motion_path.string() +
          "' --quiet --frames-mesh" + moment_arms,
      "plugin", tag);
  ASSERT_EQ(result.exit_code, 0) << result.err;
  const StorageTable table = readStorage((out / "outputs.sto").string());
  const std::vector<Eigen::Isometry3d> femur_motion = calcFemurMotions(motion_path);  // pelvis fixed (CT frame)
  ASSERT_EQ(table.rows.size(), femur_motion.size());
  const SceneBones bones;
  for (const std::string& muscle : checks.muscles) {
    double most_outside = 0.0, most_stray_mm3 = 0.0;
    int most_volume_pieces = 0;
    const size_t pieces_column = static_cast<size_t>(table.findColumn(muscle + ".pieces"));
    const size_t stray_column = static_cast<size_t>(table.findColumn(muscle + ".stray_volume_mm3"));
    const int stray_x = table.findColumn(muscle + ".stray_centre_mm_0");
    ASSERT_GE(stray_x, 0) << muscle;
    const size_t stray_x_column = static_cast<size_t>(stray_x);
    SurfaceWatch watch(bones);
    const std::array<Eigen::Matrix3Xd, 2> areas = readAreas(scene, muscle);
    for (size_t row = 0; row < table.rows.size(); ++row) {
      most_outside = std::max(most_outside, checkOutputs(table, row, muscle, checks));
      EXPECT_LE(calcAttachmentOffset(readFrame(out / "meshes", muscle + "_fibres", static_cast<int>(row)), areas,
                                     femur_motion[row]),
                0.5)
          << muscle << ": a fibre's attachment left its area at frame " << row;
      const Eigen::Isometry3d femur_step =
          row > 0 ? femur_motion[row] * femur_motion[row - 1].inverse() : Eigen::Isometry3d::Identity();
      const int pieces = watch.addFrame(readFrame(out / "meshes", muscle, static_cast<int>(row)), static_cast<int>(row),
                                        femur_motion[row], femur_step);
      const double volume_pieces = table.rows[row][pieces_column];
      most_volume_pieces = std::max(most_volume_pieces, static_cast<int>(volume_pieces));
      most_stray_mm3 = std::max(most_stray_mm3, table.rows[row][stray_column]);
      if (holds(checks.surface_one_piece, muscle)) {
        EXPECT_EQ(pieces, 1) << muscle << "'s tracked surface at frame " << row;
      }
      if (holds(checks.one_piece, muscle)) {
        const std::vector<double>& r = table.rows[row];
        EXPECT_EQ(volume_pieces, 1.0) << muscle << "'s volume at frame " << row
                                      << ": the part that came off lies about (" << r[stray_x_column] << ", "
                                      << r[stray_x_column + 1] << ", " << r[stray_x_column + 2] << ") mm in ground";
      }
    }
    const int ratio = table.findColumn(muscle + ".fibre_length_ratio");
    std::printf("%s %s: deepest tracked vertex in a bone %.3f mm (frame %d); worst jump beyond the femur's move + 1 mm "
                "%.3f mm (frame %d, first at %d); fibre length ratio at the last frame %.3f; most fibre points outside %.0f; most pieces of "
                "the tracked surface %d (specks under %.0f mm across, all frames: %d); most pieces of the volume %d "
                "(largest stray volume %.0f mm³)\n",
                scene.c_str(), muscle.c_str(), watch.worst_depth, watch.worst_depth_frame, watch.worst_jump,
                watch.worst_jump_frame, watch.first_jump_frame, ratio >= 0 ? table.rows.back()[static_cast<size_t>(ratio)] : NAN,
                most_outside, watch.most_pieces, kPieceCellMm, watch.specks, most_volume_pieces, most_stray_mm3);
    EXPECT_LE(watch.worst_depth, 0.5) << muscle << " at frame " << watch.worst_depth_frame;
    if (checks.last_ratio_at_most.count(muscle)) {
      ASSERT_GE(ratio, 0);
      EXPECT_LE(table.rows.back()[static_cast<size_t>(ratio)], checks.last_ratio_at_most.at(muscle)) << muscle;
    }
    EXPECT_LE(watch.worst_jump, 0.0) << muscle << " at frame " << watch.worst_jump_frame;
    if (holds(checks.arm_falls_from_40_to_60, muscle)) {
      const double at_40 = calcArmAtFlexion(table, muscle, 40.0), at_60 = calcArmAtFlexion(table, muscle, 60.0);
      EXPECT_LT(std::abs(at_60), std::abs(at_40)) << muscle << "'s hip flexion moment arm at 40° and 60°";
    }
  }
  fs::remove_all(out);
}

TEST(HipScenes, FlexionKeepsVolumeAndTheMusclesOutOfTheBonesTheirFibresChangeLengthEveryFrameAsTheirArmsSay) {
  SceneChecks checks;
  checks.fibres_monotone = kMuscles;
  checks.one_piece = kMuscles;
  checks.surface_one_piece = {"glmax_r"};
  checks.last_ratio_at_most = {{"psoas_r", 0.93}};
  checks.arm_falls_from_40_to_60 = {"glmax_r"};
  checkScene("hip_flexion", "hip_flexion_0_80.mot", checks);
}

TEST(HipScenes, FlexionIn10DegreeFramesKeepsVolumeAndTheMusclesOutOfTheBonesWithoutAJump) {
  SceneChecks checks;
  checks.fibre_step_at_most = 0.1;  // ten times the 1° frames' bound, for 10° frames
  checks.fibres_monotone = kMuscles;
  checks.one_piece = kMuscles;
  checks.surface_one_piece = {"glmax_r"};
  checks.arm_falls_from_40_to_60 = {"glmax_r"};
  checkScene("hip_flexion", "hip_flexion_0_80_step10.mot", checks);
}

TEST(HipScenes, AdductionKeepsVolumeAndTheMusclesOutOfTheBonesEveryFrame) {
  SceneChecks checks;
  checks.one_piece = kMuscles;
  checks.surface_one_piece = {"glmax_r", "iliacus_r"};
  checkScene("hip_adduction", "hip_adduction_0_30.mot", checks);
}

TEST(HipScenes, RotationKeepsVolumeAndTheMusclesOutOfTheBonesEveryFrame) {
  SceneChecks checks;
  checks.one_piece = kMuscles;
  checks.surface_one_piece = {"glmax_r", "iliacus_r"};
  checkScene("hip_rotation", "hip_rotation_m30_30.mot", checks);
}

TEST(HipScenes, GaitKeepsVolumeAndTheMusclesOutOfTheBonesEveryFrame) {
  SceneChecks checks;
  checks.one_piece = kMuscles;
  checks.surface_one_piece = {"glmax_r", "iliacus_r"};
  checkScene("hip_gait", "gait_cycle.mot", checks);
}

TEST(HipScenes, GluteusFlexedTo120DegreesKeepsVolumeFibresInsideAndOutOfTheBonesInOnePieceWithoutAJump) {
  SceneChecks checks;
  checks.muscles = {"glmax_r"};
  checks.fibre_step_at_most = 0.015;  // beyond the scenes' 80°, one taut fibre steps by 1.39 % at 115°
  checks.fibres_monotone = {"glmax_r"};
  checks.one_piece = {"glmax_r"};
  checks.surface_one_piece = {"glmax_r"};
  checkScene("hip_flexion", "hip_flexion_0_120.mot", checks);
}

}  // namespace
}  // namespace rbfmuscle
