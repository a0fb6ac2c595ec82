// Stability checks of the dynamics on the real gluteus maximus and iliacus (LHDL), with
// the surfaces and landmark attachments of the hip scenes.
#include "dynamics/curvature_descent.h"
#include "dynamics/muscle_deformer.h"

#include "../../unit/dynamics/dynamics_test_shapes.h"
#include "fit/fit_pipeline.h"
#include "geometry/iso_surface.h"
#include "geometry/mesh_check.h"
#include "geometry/mesh_io.h"
#include "geometry/mesh_measures.h"
#include "support/flexion_jump.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <stdexcept>
#include <fstream>
#include <regex>
#include <sstream>

namespace rbfmuscle {
namespace {

/// The scenes' fitted surface models/hip/surfaces/<name>.rbf (gluteus maximus 1000
/// centres, iliacus 2000), checked against its mesh so a stale file fails loudly.
RbfSurface readSceneSurface(const std::string& name) {
  const std::string hip = std::string(RBFMUSCLE_SOURCE_DIR) + "/models/hip/";
  RbfSurface s = readRbfFile(hip + "surfaces/" + name + ".rbf");
  if (s.source_hash != hashFile(hip + "meshes/" + name + ".ply")) {
    throw std::runtime_error(name + ".rbf was fitted to another mesh: refit it (models/hip/README.md)");
  }
  return s;
}

const RbfSurface& gluteus() {
  static const RbfSurface surface = readSceneSurface("gluteus_maximus_r");
  return surface;
}

/// Origins (P1, pelvis = bone 0) and insertions (last point, femur = bone 1) of the
/// glmax1..3 line-of-action paths, in M (CT minus frame_offset_mm).
std::vector<AttachmentLandmark> gluteusLandmarks(const Eigen::Vector3d& frame_offset_mm, double radius_mm) {
  std::ifstream in(std::string(RBFMUSCLE_SOURCE_DIR) + "/models/hip/landmarks/line_of_action_paths.json");
  std::stringstream text;
  text << in.rdbuf();
  const std::string json = text.str();
  std::vector<AttachmentLandmark> out;
  const std::regex path_re("\"glmax[0-9]_r\"\\s*:\\s*\\[((?:\\s*\\[[^\\]]*\\]\\s*,?)+)\\]");
  const std::regex num_re("-?[0-9]+(?:\\.[0-9]+)?(?:[eE][-+]?[0-9]+)?");
  for (auto m = std::sregex_iterator(json.begin(), json.end(), path_re); m != std::sregex_iterator(); ++m) {
    const std::string body = (*m)[1];
    std::vector<double> v;
    for (auto n = std::sregex_iterator(body.begin(), body.end(), num_re); n != std::sregex_iterator(); ++n)
      v.push_back(std::stod(n->str()));
    if (v.size() < 6 || v.size() % 3 != 0) continue;
    const size_t last = v.size() - 3;
    out.push_back({0, Eigen::Vector3d(v[0], v[1], v[2]) - frame_offset_mm, radius_mm});
    out.push_back({1, Eigen::Vector3d(v[last], v[last + 1], v[last + 2]) - frame_offset_mm, radius_mm});
  }
  return out;
}

Attachments gluteusAttachments(const RbfSurface& s) {
  Attachments a = makeFreeAttachments(s.field.getNumCentres(), 2);
  attachByLandmarks(s.field, gluteusLandmarks(s.frame_offset_mm, 25.0), a);  // as in hip_flexion.xml
  return a;
}

TEST(GluteusDynamics, LandmarksAttachBothEnds) {
  const Attachments a = gluteusAttachments(gluteus());
  EXPECT_EQ(gluteusLandmarks(gluteus().frame_offset_mm, 25.0).size(), 6u);
  EXPECT_GT(a.countAttachedTo(0), 0);
  EXPECT_GT(a.countAttachedTo(1), 0);
  EXPECT_LT(a.countAttached(), gluteus().field.getNumCentres());
}

// Issue 4 / dissertation 8.3.1: every free centre moved randomly by 5 % of the box
// diagonal, attachments held; the deformer's full per-frame pipeline at identity
// motion (descent, volume, island guard) brings the mean surface
// distance to the unperturbed surface to ≤ 0.5 % of the diagonal.
TEST(GluteusDynamics, RestoresRandomPerturbation) {
  const RbfSurface& s = gluteus();
  const Attachments att = gluteusAttachments(s);
  MuscleDeformer d(s.field, att);
  const std::vector<Eigen::Isometry3d> identity(2, Eigen::Isometry3d::Identity());
  d.update(identity);
  const TriangleMesh rest = d.extractSurface(1.5);
  const double diagonal = rest.calcBoundingBox().diagonal().norm();
  d.setCurrentCentres(test::perturbFreeCentres(s.field.getCentres(), att, 0.05 * diagonal, 5));
  const double perturbed = test::calcMeanSurfaceDistance(rest, d.extractSurface(1.5));
  const DeformResult& r = d.update(identity);
  const double distance = test::calcMeanSurfaceDistance(rest, d.extractSurface(1.5));
  RecordProperty("diagonal_mm", std::to_string(diagonal));
  RecordProperty("perturbed_distance_mm", std::to_string(perturbed));
  RecordProperty("restored_distance_mm", std::to_string(distance));
  std::cout << "diagonal " << diagonal << " mm, perturbed " << perturbed << " mm, restored " << distance
            << " mm (" << r.iterations << " descent iterations, " << toString(r.stop_reason) << ", volume ratio "
            << r.volume_ratio << ")\n";
  EXPECT_GT(perturbed, 0.005 * diagonal);  // the perturbation is visible
  EXPECT_LE(distance, 0.005 * diagonal);
}

/// Landmark attachments of the iliacus (hip_flexion.xml): origin in the iliac fossa
/// (pelvis, bone 0), insertion on the lesser trochanter (femur, bone 1).
Attachments iliacusAttachments(const RbfSurface& s) {
  Attachments a = makeFreeAttachments(s.field.getNumCentres(), 2);
  attachByLandmarks(s.field,
                    {{0, Eigen::Vector3d(138.474, 235.451, -324.078) - s.frame_offset_mm, 25.0},
                     {1, Eigen::Vector3d(124.427, 265.109, -493.253) - s.frame_offset_mm, 25.0}},
                    a);
  return a;
}

const RbfSurface& iliacus() {
  static const RbfSurface surface = readSceneSurface("iliacus_r");
  return surface;
}

/// Flexes the femur (bone 1) about the hip centre, pelvis fixed, from `step_deg` to
/// `last_deg` in steps of `step_deg`; at every frame: finite, volume within ±3 %,
/// attached centres exactly with their bone, one closed surface (2 mm cells), and no
/// jump (when `check_jumps`): every 10th vertex of the new surface lies within
/// 2 r sin(Δθ/2) + 1 mm of the previous surface, the femur's own move at that place
/// (r = distance from the flexion axis) plus 1 mm for the descent's correction. The
/// worst excess is printed either way.
void runFlexion(const RbfSurface& s, const Attachments& att, int step_deg, int last_deg, bool check_jumps,
                const DeformerSettings& settings = {}) {
  MuscleDeformer d(s.field, att, settings);
  TriangleMesh previous = d.extractSurface(2.0);
  ASSERT_EQ(checkMesh(previous).components, 1) << "rest";
  const Eigen::Vector3d hip = test::kHipCentre_CT_mm - s.frame_offset_mm;
  const Eigen::Vector3d& flexion_axis = test::kFlexionAxis_CT;  // the same in M (a translation of CT)
  const double step_rad = step_deg * M_PI / 180.0;
  for (int deg = step_deg; deg <= last_deg; deg += step_deg) {
    const std::vector<Eigen::Isometry3d> motion = {Eigen::Isometry3d::Identity(),
                                                   test::makeRotationAbout(hip, flexion_axis, deg * M_PI / 180.0)};
    const DeformResult& r = d.update(motion);
    TriangleMesh surface = d.extractSurface(2.0);
    const int components = checkMesh(surface).components;
    if (deg % 10 == 0) {
      std::cout << deg << "°: components " << components << ", volume ratio " << r.volume_ratio << ", islands "
                << r.islands_found << " (" << toString(r.topology_stop) << "), necks " << r.necks_raised << ", cost " << r.curvature_cost
                << ", iterations " << r.iterations << " (" << toString(r.stop_reason) << "), predict " << r.predict_ms
                << " ms, descent " << r.descent_ms << " ms, volume " << r.volume_ms << " ms, guard " << r.topology_ms
                << " ms\n";
    }
    ASSERT_TRUE(std::isfinite(r.volume_mm3) && std::isfinite(r.curvature_cost)) << deg;
    const Eigen::Matrix3Xd& centres = d.getField().getCentres();
    ASSERT_TRUE(centres.allFinite() && d.getField().getWeights().allFinite()) << deg;
    EXPECT_NEAR(r.volume_ratio, 1.0, 0.03) << deg;
    EXPECT_EQ(components, 1) << deg << "°";
    for (int k = 0; k < s.field.getNumCentres(); ++k) {
      const int b = att.bone_of_centre[static_cast<size_t>(k)];
      if (b < 0) continue;
      const Eigen::Vector3d expected = motion[static_cast<size_t>(b)] * Eigen::Vector3d(s.field.getCentres().col(k));
      ASSERT_LT((centres.col(k) - expected).norm(), 1e-6) << "centre " << k << " at " << deg;
    }
    const MeshDistance to_previous(std::move(previous));
    int jumps = 0;
    double worst_mm = 0.0;
    for (int v = 0; v < surface.countVertices(); v += 10) {
      const Eigen::Vector3d p = surface.vertices_mm.col(v);
      const double excess = to_previous.calcUnsignedDistance(p) - test::calcJumpAllowance_mm(p, hip, step_rad);
      worst_mm = std::max(worst_mm, excess);
      if (excess > 0.0) ++jumps;
    }
    if (jumps > 0) {
      std::cout << deg << "°: " << jumps << " surface points jump, worst by " << worst_mm << " mm (guard removed "
                << r.islands_found << ", descent " << r.iterations << " iterations)\n";
    }
    if (check_jumps) {
      EXPECT_EQ(jumps, 0) << deg << "°";
    }
    previous = std::move(surface);
  }
}

TEST(GluteusDynamics, FlexionTo80InTenDegreeStepsKeepsVolumeAttachmentsAndOnePiece) {
  runFlexion(gluteus(), gluteusAttachments(gluteus()), 10, 80, false);
}

TEST(GluteusDynamics, FlexionTo80InOneDegreeSteps) {
  runFlexion(gluteus(), gluteusAttachments(gluteus()), 1, 80, false);
}

// Hard case of issue 4: beyond the scenes' range.
TEST(GluteusDynamics, FlexionTo120InTenDegreeSteps) {
  runFlexion(gluteus(), gluteusAttachments(gluteus()), 10, 120, false);
}

TEST(IliacusDynamics, FlexionTo80InTenDegreeSteps) {
  runFlexion(iliacus(), iliacusAttachments(iliacus()), 10, 80, true);
}

TEST(IliacusDynamics, FlexionTo80InOneDegreeSteps) {
  runFlexion(iliacus(), iliacusAttachments(iliacus()), 1, 80, false);
}

/// The deformer as the hip scenes run it: the step limit on (max_surface_step_mm 0.5).
DeformerSettings sceneSettings() {
  DeformerSettings settings;
  settings.step_limit.max_step_mm = 0.5;
  return settings;
}

// Issue 4 also asks that no frame jumps further than the bone moves. Without the step limit
// (the library's default) the surface still jumps beyond the femur's move plus 1 mm (measured
// 2026-12-03): the gluteus by up to 0.97 mm at 1° steps (56°) and 3.6 mm at 10° steps (80°,
// where the stretched belly thins), the iliacus by 1.9 mm at 1° steps (52°). Before the guard's
// changes were carried and the fits clamped at 10 mm such jumps were 19 mm; before the guard kept
// thinning necks, 2.0 mm (gluteus, 61°) and 3.3 mm (iliacus, 51°). With the scenes' step limit
// neither muscle has any.
TEST(GluteusDynamics, NoSurfaceJumpAtOneDegreeStepsWithTheStepLimit) {
  runFlexion(gluteus(), gluteusAttachments(gluteus()), 1, 80, true, sceneSettings());
}

TEST(GluteusDynamics, NoSurfaceJumpAtTenDegreeStepsWithTheStepLimit) {
  runFlexion(gluteus(), gluteusAttachments(gluteus()), 10, 80, true, sceneSettings());
}

// The iliacus's thin top (43°–54°) leaves one-node crumbs beside the body. Before the guard joined
// such a crumb across a shallow dip (TopologySettings::crumb_join_level) it removed it, which sank
// the flat sheet beside it; the limit's pull-back raised the sheet, the crumb came back, and at 43°
// the surface moved 0.13 mm too far.
TEST(IliacusDynamics, NoSurfaceJumpAtOneDegreeStepsWithTheStepLimit) {
  runFlexion(iliacus(), iliacusAttachments(iliacus()), 1, 80, true, sceneSettings());
}

}  // namespace
}  // namespace rbfmuscle
