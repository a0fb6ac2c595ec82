// Stability checks of the dynamics on the real gluteus maximus (LHDL). The fit
// (300 centres) is cached in RBFMUSCLE_BINARY_DIR/test_cache/ and reused while the
// mesh hash and the fit settings match.
#include "dynamics/curvature_descent.h"
#include "dynamics/muscle_deformer.h"

#include "../../unit/dynamics/dynamics_test_shapes.h"
#include "fit/fit_pipeline.h"
#include "geometry/iso_surface.h"
#include "geometry/mesh_check.h"
#include "geometry/mesh_io.h"
#include "geometry/mesh_measures.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>

namespace rbfmuscle {
namespace {

const std::string kMesh = std::string(RBFMUSCLE_SOURCE_DIR) + "/models/hip/meshes/gluteus_maximus_r.ply";

const RbfSurface& gluteus() {
  static const RbfSurface surface = [] {
    const std::filesystem::path dir = std::filesystem::path(RBFMUSCLE_BINARY_DIR) / "test_cache";
    std::filesystem::create_directories(dir);
    const std::string cached = (dir / "gluteus_maximus_r_300.rbf").string();
    FitSettings settings;
    settings.max_centres = 300;
    settings.metric_points = 100000;
    if (std::filesystem::exists(cached)) {
      RbfSurface s = readRbfFile(cached);
      if (s.source_hash == hashFile(kMesh) && s.settings == describeSettings(settings)) return s;
    }
    MeshFit fit = fitMeshFile(kMesh, settings, false);
    writeRbfFile(cached, fit.surface);
    return fit.surface;
  }();
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
  attachByLandmarks(s.field, gluteusLandmarks(s.frame_offset_mm, 30.0), a);
  return a;
}

TEST(GluteusDynamics, LandmarksAttachBothEnds) {
  const Attachments a = gluteusAttachments(gluteus());
  EXPECT_EQ(gluteusLandmarks(gluteus().frame_offset_mm, 30.0).size(), 6u);
  EXPECT_GT(a.countAttachedTo(0), 0);
  EXPECT_GT(a.countAttachedTo(1), 0);
  EXPECT_LT(a.countAttached(), gluteus().field.getNumCentres());
}

// Issue 4 / dissertation 8.3.1: every free centre moved randomly by 5 % of the box
// diagonal, attachments held; the deformer's full per-frame pipeline at identity
// motion (descent, volume, island guard) brings the mean surface
// distance to the unperturbed surface to ≤ 0.5 % of the diagonal.
TEST(GluteusDynamics, DISABLED_RestoresRandomPerturbation_FailsAt1_11PercentOfDiagonal_Issue4Open) {
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

/// Flexes the femur (bone 1) about the hip centre, pelvis fixed, from `step_deg` to
/// 80° in steps of `step_deg`; at every frame: finite, volume within ±3 %, attached
/// centres exactly with their bone, one surface component (2 mm cells).
void runFlexion(int step_deg) {
  const RbfSurface& s = gluteus();
  const Attachments att = gluteusAttachments(s);
  MuscleDeformer d(s.field, att);
  ASSERT_EQ(checkMesh(d.extractSurface(2.0)).components, 1) << "rest";
  const Eigen::Vector3d hip = Eigen::Vector3d(143.225, 243.37, -432.499) - s.frame_offset_mm;
  const Eigen::Vector3d flexion_axis(-0.9924778435393229, 0.11879490607095865, 0.029588855590025775);  // pelvis Z (right)
  for (int deg = step_deg; deg <= 80; deg += step_deg) {
    const std::vector<Eigen::Isometry3d> motion = {Eigen::Isometry3d::Identity(),
                                                   test::makeRotationAbout(hip, flexion_axis, deg * M_PI / 180.0)};
    const DeformResult& r = d.update(motion);
    const int components = checkMesh(d.extractSurface(2.0)).components;
    if (deg % 10 == 0) {
      std::cout << deg << "°: components " << components << ", volume ratio " << r.volume_ratio << ", islands "
                << r.islands_found << " (" << toString(r.topology_stop) << "), cost " << r.curvature_cost
                << ", iterations " << r.iterations << " (" << toString(r.stop_reason) << "), predict " << r.predict_ms
                << " ms, descent " << r.descent_ms << " ms, volume " << r.volume_ms << " ms, guard " << r.topology_ms
                << " ms\n";
    }
    ASSERT_TRUE(std::isfinite(r.volume_mm3) && std::isfinite(r.curvature_cost)) << deg;
    ASSERT_TRUE(d.getField().getCentres().allFinite() && d.getField().getWeights().allFinite()) << deg;
    EXPECT_NEAR(r.volume_ratio, 1.0, 0.03) << deg;
    EXPECT_EQ(components, 1) << deg << "°";
    for (int k = 0; k < s.field.getNumCentres(); ++k) {
      const int b = att.bone_of_centre[static_cast<size_t>(k)];
      if (b < 0) continue;
      const Eigen::Vector3d expected = motion[static_cast<size_t>(b)] * Eigen::Vector3d(s.field.getCentres().col(k));
      ASSERT_LT((d.getField().getCentres().col(k) - expected).norm(), 1e-6) << "centre " << k << " at " << deg;
    }
  }
}

TEST(GluteusDynamics, DISABLED_FlexionStaysFiniteWithVolumeAndAttachmentsHeld_3PiecesAt40Deg_Issue4Open) {
  runFlexion(10);
}

TEST(GluteusDynamics, DISABLED_FlexionInOneDegreeStepsStaysOnePiece_Issue4Open) { runFlexion(1); }

}  // namespace
}  // namespace rbfmuscle
