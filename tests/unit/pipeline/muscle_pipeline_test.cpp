// SPDX-License-Identifier: Apache-2.0
// MusclePipeline on a rod between two bones: rigid motions stay rigid, a frame depends on its
// pose only, two runs agree bitwise, and the volume is kept through a bend.
#include "pipeline/muscle_pipeline.h"

#include "../dynamics/dynamics_test_shapes.h"
#include "collision/bone_distance_grid.h"
#include "dynamics/joint_lift_off.h"
#include "geometry/iso_surface.h"
#include "geometry/mesh_measures.h"

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>

namespace rbfmuscle {
namespace {


MuscleDefinition makeRod() {
  MuscleDefinition rod;
  rod.rest_field = test::makeRodField();
  rod.rest_mesh_M = test::makeBox(Eigen::Vector3d(-36, -7, -4), Eigen::Vector3d(36, 7, 4.5));
  rod.attachments = test::makeRodAttachments(rod.rest_field);
  rod.origin_area_M = Eigen::Vector3d(-30, 0, 0);
  rod.insertion_area_M = Eigen::Vector3d(30, 0, 0);
  return rod;
}

PipelineSettings fewFibres() {
  PipelineSettings settings;
  settings.fibres = 6;
  settings.fibre_segments = 8;
  settings.quadrature_points = 3000;
  return settings;
}

/// The insertion bone turned about the z axis through (20, 0, 0).
FrameInput bend(double degrees) {
  FrameInput input;
  const double a = degrees * M_PI / 180.0;
  input.bone_motion_M = {Eigen::Isometry3d::Identity(),
                         Eigen::Isometry3d(Eigen::Translation3d(20, 0, 0) * Eigen::AngleAxisd(a, Eigen::Vector3d::UnitZ()) *
                                           Eigen::Translation3d(-20, 0, 0))};
  return input;
}

std::vector<double> reports(const MusclePipeline& pipeline) {
  std::vector<double> values;
  pipeline.appendReports(values);
  const std::vector<ReportField> fields = MusclePipeline::describeReports();
  std::vector<double> kept;  // timings differ between runs; everything else must not
  for (size_t i = 0; i < fields.size(); ++i)
    if (fields[i].unit != "ms") kept.push_back(std::isnan(values[i]) ? -1e300 : values[i]);  // NaN ≠ NaN
  return kept;
}

/// The pipeline's last report named `name` (NaN if there is none).
double reportValue(const MusclePipeline& pipeline, const std::string& name) {
  std::vector<double> values;
  pipeline.appendReports(values);
  const std::vector<ReportField> fields = MusclePipeline::describeReports();
  for (size_t i = 0; i < fields.size(); ++i)
    if (fields[i].name == name) return values[i];
  return std::nan("");
}

TEST(MusclePipeline, ReportsAsManyValuesAsItDescribes) {
  MusclePipeline pipeline(makeRod(), fewFibres());
  pipeline.run(bend(10));
  std::vector<double> values;
  pipeline.appendReports(values);
  EXPECT_EQ(values.size(), MusclePipeline::describeReports().size());
}

TEST(MusclePipeline, ARigidMotionOfBothBonesMovesTheMuscleRigidly) {
  const MuscleDefinition rod = makeRod();
  MusclePipeline pipeline(rod, fewFibres());
  const Eigen::Isometry3d t = Eigen::Translation3d(15, -40, 7) * Eigen::AngleAxisd(0.9, Eigen::Vector3d(1, 1, 0.3).normalized());
  FrameInput input;
  input.bone_motion_M = {t, t};
  input.want_surface = true;
  pipeline.run(input);
  const MuscleState& state = pipeline.getState();
  // Kernels, fibres and the tracked surface moved by t to 1e-6 mm; the field equals the rest field moved.
  for (int k = 0; k < rod.rest_field.getNumCentres(); ++k)
    EXPECT_LT((state.field.getCentres().col(k) - t * Eigen::Vector3d(rod.rest_field.getCentres().col(k))).norm(), 1e-6);
  const RestFibres& fibres = *pipeline.getRestFibres();
  for (Eigen::Index j = 0; j < fibres.points_mm.cols(); ++j)
    EXPECT_LT((state.fibre_points_mm.col(j) - t * Eigen::Vector3d(fibres.points_mm.col(j))).norm(), 1e-6) << "fibre point " << j;
  DeformedField rest(rod.rest_field, fewFibres().cutoff);
  const TriangleMesh& surface = pipeline.getRestSurface();
  for (Eigen::Index v = 0; v < surface.vertices_mm.cols(); v += 7) {
    const Eigen::Vector3d x = surface.vertices_mm.col(v);
    EXPECT_NEAR(state.field.calcValue(t * x), rest.calcValue(x), 1e-9) << "vertex " << v;
  }
  EXPECT_NEAR(pipeline.getState().field.getWeights()[0], rod.rest_field.getWeights()[0], 1e-12);
}

TEST(MusclePipeline, TrackedVerticesStartAtTheRestFieldsResidualAfterARigidMotion) {
  const MuscleDefinition rod = makeRod();
  MusclePipeline pipeline(rod, fewFibres());
  FrameInput input;
  input.bone_motion_M = {Eigen::Isometry3d::Identity(), Eigen::Isometry3d::Identity()};
  input.want_surface = true;
  pipeline.run(input);
  // At rest the carried vertices are the rest surface's: the largest |f| there, from the rest field.
  DeformedField rest(rod.rest_field, fewFibres().cutoff);
  const TriangleMesh& surface = pipeline.getRestSurface();
  double rest_residual = 0.0;
  for (Eigen::Index v = 0; v < surface.vertices_mm.cols(); ++v)
    rest_residual = std::max(rest_residual, std::abs(rest.calcValue(surface.vertices_mm.col(v))));
  ASSERT_GT(rest_residual, 0.0);  // an extracted surface lies only near f = 0, so the check is not 0 = 0
  const double at_rest = reportValue(pipeline, "surface_start_residual_max");
  EXPECT_NEAR(at_rest, rest_residual, 1e-6);
  // A rigid motion moves the field and the tissue map together.
  const Eigen::Isometry3d t = Eigen::Translation3d(-8, 25, 3) * Eigen::AngleAxisd(-1.2, Eigen::Vector3d(0.2, 1, 0.5).normalized());
  input.bone_motion_M = {t, t};
  pipeline.run(input);
  EXPECT_NEAR(reportValue(pipeline, "surface_start_residual_max"), at_rest, 1e-9);
}

TEST(MusclePipeline, AFrameDependsOnItsPoseOnlyAndTwoRunsAreBitwiseEqual) {
  MusclePipeline stepped(makeRod(), fewFibres()), direct(makeRod(), fewFibres());
  for (int degrees = 1; degrees <= 40; ++degrees) stepped.run(bend(degrees));
  direct.run(bend(40));
  EXPECT_EQ(reports(stepped), reports(direct));
  EXPECT_EQ(stepped.getState().field.getCentres(), direct.getState().field.getCentres());
  EXPECT_EQ(stepped.getState().fibre_points_mm, direct.getState().fibre_points_mm);
}

TEST(MusclePipeline, ABentRodKeepsItsVolumeInOnePieceWithItsFibresInside) {
  MusclePipeline pipeline(makeRod(), fewFibres());
  const double rest_volume = pipeline.getRestVolume();
  for (int degrees : {20, 45, 70}) {
    pipeline.run(bend(degrees));
    EXPECT_NEAR(reportValue(pipeline, "volume_ratio"), 1.0, 2e-3) << degrees << "°";
    EXPECT_EQ(reportValue(pipeline, "fibre_points_outside"), 0.0) << degrees << "°";
    // Independent check: the extracted surface's volume and pieces.
    const MuscleShape shape(pipeline.getState());
    Eigen::AlignedBox3d box(Eigen::Vector3d(-60, -60, -20), Eigen::Vector3d(60, 60, 20));
    const TriangleMesh surface = extractIsoSurface(
        [&](const Eigen::Matrix3Xd& points, Eigen::VectorXd& out) {
          out.resize(points.cols());
          for (Eigen::Index j = 0; j < points.cols(); ++j) out[j] = shape.calcValue(points.col(j));
        },
        box, 0.75);
    EXPECT_EQ(countComponents(surface), 1) << degrees << "°";
    EXPECT_NEAR(calcVolume(surface) / rest_volume, 1.0, 0.03) << degrees << "°";
  }
}

/// A bone ridge (6 mm wide across the rod, along y) pushed 2 mm up into the rod's underside
/// from below, where it did not touch the rod at rest. Tracked vertices of the underside are then
/// in the bone; each must go where the way into the muscle leaves the bone, the ridge's top.
/// From a vertex near the ridge's side, the nearest bone surface is that side instead: vertices
/// gathered on the two sides and the tracked mesh stretched across the ridge.
TEST(MusclePipeline, TrackedVerticesPushedIntoABoneGoOntoItsFaceTowardsTheMuscle) {
  MuscleDefinition rod = makeRod();
  MusclePipeline probe(rod, fewFibres());
  double underside_mm = 0.0;  // the rest surface's lowest point under the rod's middle
  const TriangleMesh& rest = probe.getRestSurface();
  for (Eigen::Index v = 0; v < rest.vertices_mm.cols(); ++v)
    if (std::abs(rest.vertices_mm(0, v)) < 3.0) underside_mm = std::min(underside_mm, rest.vertices_mm(2, v));
  const Eigen::Vector3d lo(-3, -30, underside_mm - 8.0), hi(3, 30, underside_mm - 2.0);
  rod.bones.push_back(ClearanceBone{"ridge", std::make_shared<BoneDistanceGrid>(test::makeBox(lo, hi))});
  rod.rest_X_MB.push_back(Eigen::Isometry3d::Identity());
  MusclePipeline pipeline(rod, fewFibres());
  FrameInput input;
  input.bone_motion_M.assign(2, Eigen::Isometry3d::Identity());
  input.X_MB = {Eigen::Isometry3d(Eigen::Translation3d(0, 0, 4.0))};  // top now 2 mm above the underside
  input.want_surface = true;
  pipeline.run(input);
  const TriangleMesh& surface = pipeline.getState().surface_M;
  const double ridge_top_mm = hi.z() + 4.0;
  int on_top = 0;
  double longest_edge_mm = 0.0;
  for (Eigen::Index t = 0; t < surface.triangles.cols(); ++t)
    for (int e = 0; e < 3; ++e)
      longest_edge_mm = std::max(longest_edge_mm, (surface.vertices_mm.col(surface.triangles(e, t)) -
                                                   surface.vertices_mm.col(surface.triangles((e + 1) % 3, t))).norm());
  for (Eigen::Index v = 0; v < surface.vertices_mm.cols(); ++v)
    if (std::abs(surface.vertices_mm(0, v)) < 2.5 && std::abs(surface.vertices_mm(1, v)) < 3.0 &&
        std::abs(surface.vertices_mm(2, v) - ridge_top_mm) < 0.05)
      ++on_top;
  EXPECT_GT(on_top, 4) << "tracked vertices on the ridge's top";
  // The rest surface's edges are at most a cell diagonal (2 mm cells): nothing stretches across the ridge.
  EXPECT_LT(longest_edge_mm, 2.0 * std::sqrt(3.0) + 0.5);
}

/// The rod's fibres after its insertion bone turned by 0.5 rad about a joint 30 mm below its
/// middle, which shortens it, lifting off the joint or not; and how far each fibre sags below its
/// string then beyond its rest sag, seen along the turn axis (max over its points, mm).
struct ShortenedRod {
  Eigen::Matrix3Xd fibres;
  Eigen::VectorXd sag_beyond_rest_mm;
  double lift_move_max_mm = 0.0, outside = 0.0;
};
ShortenedRod shortenRod(bool lift_off) {
  const Eigen::Vector3d joint(0, -30, 0);
  PipelineSettings settings = fewFibres();
  settings.lattice.joint_centre_mm = joint;
  settings.lift_off = lift_off;
  MusclePipeline pipeline(makeRod(), settings);
  FrameInput input;
  input.bone_motion_M = {Eigen::Isometry3d::Identity(), test::makeRotationAbout(joint, Eigen::Vector3d::UnitZ(), 0.5)};
  pipeline.run(input);
  ShortenedRod out{pipeline.getState().fibre_points_mm, Eigen::VectorXd(settings.fibres),
                   reportValue(pipeline, "fibre_lift_move_max_mm"), reportValue(pipeline, "fibre_points_outside")};
  const Eigen::Matrix3Xd& rest = pipeline.getRestFibres()->points_mm;
  const int per = settings.fibre_segments + 1;
  const auto flat = [&](const Eigen::Matrix3Xd& points) { return Eigen::Matrix2Xd((points.colwise() - joint).topRows(2)); };
  for (int f = 0; f < settings.fibres; ++f)
    out.sag_beyond_rest_mm[f] = (calcStringSags(flat(out.fibres.middleCols(f * per, per))) -
                                 calcStringSags(flat(rest.middleCols(f * per, per))))
                                    .maxCoeff();
  return out;
}

TEST(MusclePipeline, AShortenedRodsFibresRiseTowardsTheirStringsInsideIt) {
  const ShortenedRod on_arcs = shortenRod(false), lifted = shortenRod(true);
  EXPECT_EQ(on_arcs.lift_move_max_mm, 0.0);
  EXPECT_GT(lifted.lift_move_max_mm, 0.5);
  EXPECT_EQ(lifted.outside, 0.0) << "as far as the muscle allows";
  ASSERT_GT(on_arcs.sag_beyond_rest_mm.maxCoeff(), 1.0) << "the map winds the fibres round the joint";
  for (Eigen::Index f = 0; f < lifted.sag_beyond_rest_mm.size(); ++f)
    EXPECT_LT(lifted.sag_beyond_rest_mm[f], on_arcs.sag_beyond_rest_mm[f] - 0.5) << "fibre " << f;
}

}  // namespace
}  // namespace rbfmuscle
