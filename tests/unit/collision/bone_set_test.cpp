// SPDX-License-Identifier: Apache-2.0
/// BoneSet against analytic bones: a cube and an icosphere, moved rigidly; broad phase
/// versus none; transforms without rebuilds; bad input.
#include "collision/bone_set.h"

#include <cmath>
#include <random>

#include <gtest/gtest.h>

#include "support/eigen_compare.h"
#include "unit/geometry/test_meshes.h"

namespace rbfmuscle {
namespace {

using test::isApprox;
constexpr double kInf = std::numeric_limits<double>::infinity();

/// A rigid pose with a rotation about a skew axis and a translation (mm).
Eigen::Isometry3d somePose(double angle_rad, const Eigen::Vector3d& t_mm) {
  Eigen::Isometry3d X = Eigen::Isometry3d::Identity();
  X.linear() = Eigen::AngleAxisd(angle_rad, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix();
  X.translation() = t_mm;
  return X;
}

/// Signed distance (mm) to the cube [−h, h]³ and its outward normal at the closest point
/// (gradient of the distance), for p not on a medial plane.
double cubeSignedDistance(const Eigen::Vector3d& p, double h, Eigen::Vector3d& normal) {
  const Eigen::Vector3d excess = p.cwiseAbs().array() - h;
  if ((excess.array() > 0).any()) {
    const Eigen::Vector3d out = excess.cwiseMax(0.0).cwiseProduct(p.cwiseSign());
    normal = out.normalized();
    return out.norm();
  }
  Eigen::Index axis;
  const double s = excess.maxCoeff(&axis);
  normal = Eigen::Vector3d::Unit(axis) * (p(axis) > 0 ? 1.0 : -1.0);
  return s;
}

/// Uniformly random points in the box [−a, a]³ (mm), fixed seed.
Eigen::Matrix3Xd randomPoints(int n, double a, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-a, a);
  Eigen::Matrix3Xd p(3, n);
  for (int i = 0; i < n; ++i) p.col(i) << u(rng), u(rng), u(rng);
  return p;
}

TEST(BoneSet, MovedCubeGivesAnalyticSignedDistanceClosestPointAndNormal) {
  const double h = 50.0, r = 20.0;
  BoneSet bones;
  bones.addBone("cube", test::makeCube(2 * h, -h));
  const Eigen::Isometry3d X_WB = somePose(0.7, {15.0, -40.0, 120.0});
  bones.setBoneTransforms({X_WB});

  const Eigen::Matrix3Xd p_B = randomPoints(2000, 80.0, 1);
  const Eigen::Matrix3Xd p_W = X_WB * p_B;
  std::vector<ContactQueryResult> out;
  bones.queryProbes(p_W, r, out);
  ASSERT_EQ(out.size(), 2000u);
  int near = 0, inside = 0;
  for (int i = 0; i < 2000; ++i) {
    Eigen::Vector3d n_B;
    const double s = cubeSignedDistance(p_B.col(i), h, n_B);
    const ContactQueryResult& res = out[std::size_t(i)];
    if (s > r) {
      EXPECT_EQ(res.bone, -1) << "probe " << i;
      EXPECT_EQ(res.signed_distance_mm, kInf);
      continue;
    }
    ++near;
    inside += s < 0;
    ASSERT_EQ(res.bone, 0) << "probe " << i;
    EXPECT_NEAR(res.signed_distance_mm, s, 1e-9) << "probe " << i << " at " << p_B.col(i).transpose();
    EXPECT_TRUE(isApprox(res.normal_W, X_WB.linear() * n_B, 0.0, 1e-9)) << "probe " << i;
    EXPECT_TRUE(isApprox(res.closest_W, p_W.col(i) - s * res.normal_W, 0.0, 1e-9)) << "probe " << i;
  }
  EXPECT_GT(near, 500);
  EXPECT_GT(inside, 200);
}

TEST(BoneSet, IcosphereGivesRadialDistanceWithinTessellationError) {
  const double R = 30.0, r = 20.0;
  const TriangleMesh sphere = test::makeIcosphere(R, 4);
  // Tessellation error bound: the largest gap between the sphere and a triangle's plane,
  // R − (distance from the centre to the plane), over all triangles.
  double sag = 0.0;
  for (int t = 0; t < sphere.countTriangles(); ++t) {
    const Eigen::Vector3d a = sphere.getCorner(t, 0), b = sphere.getCorner(t, 1), c = sphere.getCorner(t, 2);
    sag = std::max(sag, R - std::abs(a.dot((b - a).cross(c - a).normalized())));
  }
  ASSERT_LT(sag, 0.1);
  BoneSet bones;
  bones.addBone("ball", sphere);
  const Eigen::Isometry3d X_WB = somePose(-1.1, {-200.0, 5.0, 30.0});
  bones.setBoneTransforms({X_WB});

  std::mt19937 rng(2);
  std::normal_distribution<double> gauss;
  std::uniform_real_distribution<double> radius(R - 15.0, R + 15.0);
  Eigen::Matrix3Xd p_B(3, 1000);
  for (int i = 0; i < 1000; ++i)
    p_B.col(i) = radius(rng) * Eigen::Vector3d(gauss(rng), gauss(rng), gauss(rng)).normalized();
  std::vector<ContactQueryResult> out;
  bones.queryProbes(X_WB * p_B, r, out);
  for (int i = 0; i < 1000; ++i) {
    const ContactQueryResult& res = out[std::size_t(i)];
    const Eigen::Vector3d dir_W = X_WB.linear() * p_B.col(i).normalized();
    ASSERT_EQ(res.bone, 0);
    EXPECT_NEAR(res.signed_distance_mm, p_B.col(i).norm() - R, sag + 1e-12) << "probe " << i;
    EXPECT_NEAR(res.normal_W.norm(), 1.0, 1e-12);
    EXPECT_GT(res.normal_W.dot(dir_W), 0.99) << "probe " << i;
    EXPECT_NEAR((res.closest_W - X_WB.translation()).norm(), R, sag + 1e-12);
  }
}

/// Expects two query answers to be identical, field by field.
void expectSameAnswers(const std::vector<ContactQueryResult>& a, const std::vector<ContactQueryResult>& b) {
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t i = 0; i < a.size(); ++i) {
    ASSERT_EQ(a[i].bone, b[i].bone) << "probe " << i;
    EXPECT_EQ(a[i].signed_distance_mm, b[i].signed_distance_mm) << "probe " << i;
    if (a[i].bone < 0) continue;
    EXPECT_EQ(a[i].closest_W, b[i].closest_W) << "probe " << i;
    EXPECT_EQ(a[i].normal_W, b[i].normal_W) << "probe " << i;
  }
}

TEST(BoneSet, BroadPhaseSkipsFarBonesAndChangesNoAnswer) {
  BoneSet bones;
  bones.addBone("cube", test::makeCube(100.0, -50.0));
  bones.addBone("ball", test::makeIcosphere(30.0, 3));
  bones.addBone("far_cube", test::makeCube(100.0, -50.0));
  bones.setBoneTransforms({somePose(0.3, {0, 0, 0}), somePose(-0.4, {90, 10, 0}), somePose(1.0, {2000, 0, 0})});
  const Eigen::Matrix3Xd p_W = randomPoints(3000, 130.0, 3);

  std::vector<ContactQueryResult> culled, full;
  bones.queryProbes(p_W, 20.0, culled);
  const ProbeQueryStats stats = bones.getLastQueryStats();
  bones.setBroadPhaseEnabled(false);
  bones.queryProbes(p_W, 20.0, full);
  expectSameAnswers(culled, full);
  EXPECT_EQ(stats.bones_culled_by_box, 1);
  EXPECT_EQ(bones.getLastQueryStats().exact_queries, 3 * 3000);
  EXPECT_LT(stats.exact_queries, 2 * 3000);
  EXPECT_GT(stats.pairs_culled_by_box, 0);
  int cube = 0, ball = 0, none = 0;
  for (const auto& res : culled) (res.bone == 0 ? cube : res.bone == 1 ? ball : none)++;
  EXPECT_GT(cube, 100);
  EXPECT_GT(ball, 50);
  EXPECT_GT(none, 100);
}

// Found by the sanitized build (clang) on the hip bones: a probe inside a first bone was never
// checked against a second whose box holds it, though it lay deeper inside the second.
TEST(BoneSet, AProbeInsideTwoBonesIsAnsweredByTheOneItIsDeeperIn) {
  BoneSet bones;
  bones.addBone("small", test::makeCube(10.0, 0.0));   // [0, 10]³: the probe is 1 mm deep
  bones.addBone("large", test::makeCube(40.0, -20.0)); // [-20, 20]³: the probe is 15 mm deep
  Eigen::Matrix3Xd p_W(3, 1);
  p_W << 1.0, 5.0, 5.0;
  std::vector<ContactQueryResult> out;
  bones.queryProbes(p_W, 20.0, out);
  ASSERT_EQ(out.size(), 1u);
  EXPECT_EQ(out[0].bone, 1);
  EXPECT_NEAR(out[0].signed_distance_mm, -15.0, 1e-9);
}

TEST(BoneSet, FclSphereStageCullsBoneWhoseBoxOverlapsButSurfaceIsFar) {
  BoneSet bones;
  bones.addBone("ball", test::makeIcosphere(30.0, 3));
  // A tight cluster near the corner of the ball's box: the boxes overlap, the ball's
  // surface is 18 mm away.
  const Eigen::Matrix3Xd p_W = randomPoints(50, 1.0, 4).colwise() + Eigen::Vector3d(28, 28, 28);
  std::vector<ContactQueryResult> culled, full;
  bones.queryProbes(p_W, 5.0, culled);
  EXPECT_EQ(bones.getLastQueryStats().bones_culled_by_box, 0);
  EXPECT_EQ(bones.getLastQueryStats().bones_culled_by_fcl, 1);
  EXPECT_EQ(bones.getLastQueryStats().exact_queries, 0);
  bones.setBroadPhaseEnabled(false);
  bones.queryProbes(p_W, 5.0, full);
  expectSameAnswers(culled, full);
  for (const auto& res : culled) EXPECT_EQ(res.bone, -1);
}

TEST(BoneSet, FclSphereStageKeepsABoneLyingWhollyInsideTheProbeSphere) {
  BoneSet bones;
  bones.addBone("ball", test::makeIcosphere(30.0, 3));
  bones.setBoneTransforms({somePose(0.0, {50.0, 0.0, 0.0})});
  // The probes' bounding sphere (centre 0, radius ≈ 173 mm) contains the whole ball, and
  // its centre is outside the ball; probe 8 is 5 mm above the ball.
  Eigen::Matrix3Xd p_W(3, 9);
  for (int c = 0; c < 8; ++c) p_W.col(c) << (c & 1 ? 100 : -100), (c & 2 ? 100 : -100), (c & 4 ? 100 : -100);
  p_W.col(8) << 50.0, 0.0, 35.0;
  std::vector<ContactQueryResult> out;
  bones.queryProbes(p_W, 10.0, out);
  EXPECT_EQ(bones.getLastQueryStats().bones_culled_by_fcl, 0);
  ASSERT_EQ(out[8].bone, 0);
  EXPECT_NEAR(out[8].signed_distance_mm, 5.0, 0.5);
  for (int c = 0; c < 8; ++c) EXPECT_EQ(out[std::size_t(c)].bone, -1);
}

TEST(BoneSet, ProbesDeepInsideABoneAreReportedThoughNoSurfaceIsNear) {
  BoneSet bones;
  bones.addBone("big_cube", test::makeCube(1000.0, -500.0));
  const Eigen::Matrix3Xd p_W = randomPoints(50, 5.0, 5);
  std::vector<ContactQueryResult> culled, full;
  bones.queryProbes(p_W, 20.0, culled);
  EXPECT_EQ(bones.getLastQueryStats().bones_culled_by_fcl, 0);
  bones.setBroadPhaseEnabled(false);
  bones.queryProbes(p_W, 20.0, full);
  expectSameAnswers(culled, full);
  for (int i = 0; i < 50; ++i) {
    Eigen::Vector3d n;
    ASSERT_EQ(culled[std::size_t(i)].bone, 0);
    EXPECT_NEAR(culled[std::size_t(i)].signed_distance_mm, cubeSignedDistance(p_W.col(i), 500.0, n), 1e-9);
  }
}

TEST(BoneSet, TransformsMoveTheBoneWithoutRebuildingAndReuseBuffers) {
  const double h = 50.0;
  BoneSet bones;
  bones.addBone("cube", test::makeCube(2 * h, -h));
  const Eigen::Matrix3Xd p_B = randomPoints(500, 70.0, 6);
  std::vector<ContactQueryResult> out;
  bones.queryProbes(p_B, 20.0, out);
  const ContactQueryResult* buffer = out.data();
  for (int frame = 1; frame <= 5; ++frame) {
    const Eigen::Isometry3d X_WB = somePose(0.25 * frame, Eigen::Vector3d(7.0, -3.0, 11.0) * frame);
    bones.setBoneTransforms({X_WB});
    EXPECT_TRUE(isApprox(bones.getBoneTransform(0).matrix(), X_WB.matrix(), 0.0, 0.0));
    // The world box follows the bone: it holds every moved vertex.
    const Eigen::AlignedBox3d box_W = bones.getBoneWorldBox(0);
    for (int v = 0; v < 8; ++v)
      EXPECT_TRUE(box_W.exteriorDistance(X_WB * bones.getBoneMesh(0).vertices_mm.col(v)) < 1e-9);
    // Probes fixed in the bone give the same analytic answers in every frame.
    bones.queryProbes(X_WB * p_B, 20.0, out);
    for (int i = 0; i < 500; ++i) {
      Eigen::Vector3d n_B;
      const double s = cubeSignedDistance(p_B.col(i), h, n_B);
      if (s > 20.0) continue;
      EXPECT_NEAR(out[std::size_t(i)].signed_distance_mm, s, 1e-9) << "frame " << frame << " probe " << i;
      EXPECT_TRUE(isApprox(out[std::size_t(i)].normal_W, X_WB.linear() * n_B, 0.0, 1e-9));
    }
  }
  EXPECT_EQ(bones.countBvhBuilds(), 1);
  EXPECT_EQ(out.data(), buffer);
}

/// Runs `f`, expecting a CollisionError whose message contains every one of `parts`.
template <typename F>
void expectError(F f, std::initializer_list<const char*> parts) {
  try {
    f();
    ADD_FAILURE() << "no CollisionError thrown";
  } catch (const CollisionError& e) {
    for (const char* part : parts) EXPECT_NE(std::string(e.what()).find(part), std::string::npos) << e.what();
  }
}

TEST(BoneSet, BadInputNamesTheBoneOrArgument) {
  BoneSet bones;
  expectError([&] { bones.addBone("femur_r", TriangleMesh{}); }, {"femur_r", "no triangles"});
  TriangleMesh broken = test::makeCube(10.0);
  broken.vertices_mm(1, 3) = std::nan("");
  expectError([&] { bones.addBone("pelvis", broken); }, {"pelvis", "non-finite"});
  expectError([&] { bones.addBone("", test::makeCube(10.0)); }, {"non-empty name"});
  bones.addBone("cube", test::makeCube(10.0));
  expectError([&] { bones.addBone("cube", test::makeCube(10.0)); }, {"cube", "already used"});
  expectError([&] { bones.setBoneTransforms({}); }, {"0 poses", "(1)"});
  Eigen::Isometry3d bad = Eigen::Isometry3d::Identity();
  bad.translation().x() = kInf;
  expectError([&] { bones.setBoneTransforms({bad}); }, {"cube", "not finite"});
  std::vector<ContactQueryResult> out;
  expectError([&] { bones.queryProbes(Eigen::Matrix3Xd::Zero(3, 2), -1.0, out); }, {"radius", "-1"});
  Eigen::Matrix3Xd probes = Eigen::Matrix3Xd::Zero(3, 3);
  probes(2, 1) = std::nan("");
  expectError([&] { bones.queryProbes(probes, 1.0, out); }, {"probe 1", "not finite"});
  expectError([&] { bones.getBoneName(4); }, {"4", "out of range"});
  EXPECT_EQ(bones.countBones(), 1);
}

}  // namespace
}  // namespace rbfmuscle
