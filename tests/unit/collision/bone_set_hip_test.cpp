// SPDX-License-Identifier: Apache-2.0
/// BoneSet on the real hip bones (femur_r, pelvis_r_proxy): signs agree with MeshDistance,
/// the nearest bone is the one of least signed distance, answers are invariant under a
/// rigid motion of bones and probes together.
#include <random>

#include <gtest/gtest.h>

#include "collision/bone_set.h"
#include "geometry/mesh_distance.h"
#include "geometry/mesh_io.h"
#include "support/eigen_compare.h"

namespace rbfmuscle {
namespace {

std::string hipMesh(const std::string& file) {
  return std::string(RBFMUSCLE_SOURCE_DIR) + "/models/hip/meshes/" + file;
}

/// Fixture: both bones loaded once, 1000 probes within 10 mm of their surfaces
/// (a random vertex of either bone plus a random offset of length ≤ 10 mm).
class HipBones : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    meshes_ = new std::vector<TriangleMesh>{loadMesh(hipMesh("femur_r.ply")),
                                            loadMesh(hipMesh("pelvis_r_proxy.ply"))};
    distances_ = new std::vector<MeshDistance>{MeshDistance((*meshes_)[0]), MeshDistance((*meshes_)[1])};
    std::mt19937 rng(7);
    std::normal_distribution<double> gauss;
    std::uniform_real_distribution<double> length(0.0, 10.0);
    probes_ = new Eigen::Matrix3Xd(3, 1000);
    for (int i = 0; i < 1000; ++i) {
      const TriangleMesh& m = (*meshes_)[std::size_t(i % 2)];
      const int v = std::uniform_int_distribution<int>(0, m.countVertices() - 1)(rng);
      const Eigen::Vector3d dir = Eigen::Vector3d(gauss(rng), gauss(rng), gauss(rng)).normalized();
      probes_->col(i) = m.vertices_mm.col(v) + length(rng) * dir;
    }
  }
  static void TearDownTestSuite() {
    delete meshes_;
    delete distances_;
    delete probes_;
  }
  static BoneSet makeBones() {
    BoneSet bones;
    bones.addBone("femur_r", (*meshes_)[0]);
    bones.addBone("pelvis_r_proxy", (*meshes_)[1]);
    return bones;
  }
  static std::vector<TriangleMesh>* meshes_;
  static std::vector<MeshDistance>* distances_;
  static Eigen::Matrix3Xd* probes_;
};
std::vector<TriangleMesh>* HipBones::meshes_ = nullptr;
std::vector<MeshDistance>* HipBones::distances_ = nullptr;
Eigen::Matrix3Xd* HipBones::probes_ = nullptr;

TEST_F(HipBones, SignsAndDistancesAgreeWithMeshDistance) {
  BoneSet bones = makeBones();
  std::vector<ContactQueryResult> out;
  bones.queryProbes(*probes_, 20.0, out);
  int inside = 0;
  for (int i = 0; i < 1000; ++i) {
    const Eigen::Vector3d p = probes_->col(i);
    const ContactQueryResult& res = out[std::size_t(i)];
    const double s0 = (*distances_)[0].calcSignedDistance(p), s1 = (*distances_)[1].calcSignedDistance(p);
    const int expected_bone = s0 <= s1 ? 0 : 1;
    ASSERT_GE(res.bone, 0) << "probe " << i << " is within 10 mm of a bone";
    EXPECT_NEAR(res.signed_distance_mm, std::min(s0, s1), 1e-9) << "probe " << i;
    if (std::abs(s0 - s1) > 1e-9) {
      EXPECT_EQ(res.bone, expected_bone) << "probe " << i;
    }
    EXPECT_EQ(res.signed_distance_mm < 0, (*distances_)[std::size_t(res.bone)].isInside(p)) << "probe " << i;
    inside += res.signed_distance_mm < 0;
    EXPECT_NEAR(res.normal_W.norm(), 1.0, 1e-12);
    EXPECT_TRUE(test::isApprox(res.closest_W, p - res.signed_distance_mm * res.normal_W, 0.0, 1e-9));
    EXPECT_NEAR((*distances_)[std::size_t(res.bone)].calcUnsignedDistance(res.closest_W), 0.0, 1e-9);
  }
  EXPECT_GT(inside, 200);
  EXPECT_LT(inside, 800);
}

TEST_F(HipBones, AnswersAreInvariantUnderARigidMotion) {
  BoneSet bones = makeBones();
  std::vector<ContactQueryResult> rest, moved;
  bones.queryProbes(*probes_, 20.0, rest);
  Eigen::Isometry3d X = Eigen::Isometry3d::Identity();
  X.linear() = Eigen::AngleAxisd(0.9, Eigen::Vector3d(0.2, -1.0, 0.4).normalized()).toRotationMatrix();
  X.translation() << 120.0, -35.0, 60.0;
  bones.setBoneTransforms({X, X});
  bones.queryProbes(X * (*probes_), 20.0, moved);
  for (int i = 0; i < 1000; ++i) {
    const ContactQueryResult &a = rest[std::size_t(i)], &b = moved[std::size_t(i)];
    if (std::abs(a.signed_distance_mm) > 1e-6) {
      ASSERT_EQ(a.bone, b.bone) << "probe " << i;
    }
    EXPECT_NEAR(a.signed_distance_mm, b.signed_distance_mm, 1e-9) << "probe " << i;
    EXPECT_TRUE(test::isApprox(X * a.closest_W, b.closest_W, 0.0, 1e-8)) << "probe " << i;
  }
  EXPECT_EQ(bones.countBvhBuilds(), 2);
}

TEST_F(HipBones, MovingTheFemurAwayLeavesOnlyPelvisAnswers) {
  BoneSet bones = makeBones();
  Eigen::Isometry3d away = Eigen::Isometry3d::Identity();
  away.translation() << 0.0, 0.0, 5000.0;
  bones.setBoneTransforms({away, Eigen::Isometry3d::Identity()});
  std::vector<ContactQueryResult> out;
  bones.queryProbes(*probes_, 20.0, out);
  EXPECT_EQ(bones.getLastQueryStats().bones_culled_by_box, 1);
  for (int i = 0; i < 1000; ++i) {
    const double s1 = (*distances_)[1].calcSignedDistance(probes_->col(i));
    if (s1 <= 20.0) {
      EXPECT_EQ(out[std::size_t(i)].bone, 1) << "probe " << i;
      EXPECT_NEAR(out[std::size_t(i)].signed_distance_mm, s1, 1e-9);
    } else {
      EXPECT_EQ(out[std::size_t(i)].bone, -1) << "probe " << i;
    }
  }
}

}  // namespace
}  // namespace rbfmuscle
