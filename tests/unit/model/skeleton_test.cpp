// SPDX-License-Identifier: Apache-2.0
#include "model/skeleton.h"
#include "model/skeleton_description.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <iterator>
#include <string>

#include "model_test_support.h"
#include "support/eigen_compare.h"

namespace rbfmuscle {
namespace {

using test::expectModelError;
using test::isApprox;
using test::TempFile;

constexpr double kDeg = 3.141592653589793238462643383279502884 / 180.0;
const std::string kHipDir = std::string(RBFMUSCLE_SOURCE_DIR) + "/models/hip";
const std::string kHipUrdf = kHipDir + "/hip_r.urdf";

/// Hip joint centre and pelvis anatomical frame in CT, copied from
/// models/hip/landmarks/hip_frame.json (independent of the URDF generator).
const Eigen::Vector3d kHjc_mm(143.225, 243.37, -432.499);

/// R_GP = [X Y Z]: X anterior, Y superior, Z right, Gram–Schmidt in that order.
Eigen::Matrix3d pelvisAxes() {
  const Eigen::Vector3d x = Eigen::Vector3d(-0.12145290859160308, -0.9857994507985134,
                                            -0.11596824479136207).normalized();
  const Eigen::Vector3d y_raw(0.015392240843200008, -0.11868956608287738, 0.9928120999589415);
  const Eigen::Vector3d y = (y_raw - y_raw.dot(x) * x).normalized();
  Eigen::Matrix3d R;
  R << x, y, x.cross(y);
  return R;
}

/// Analytic femur motion in CT: p ↦ c + R_GP Rz(f) Rx(a) Ry(r) R_GPᵀ (p − c).
Eigen::Isometry3d analyticFemurMotion(double flex_rad, double add_rad, double rot_rad) {
  const Eigen::Matrix3d R_GP = pelvisAxes();
  const Eigen::Matrix3d R_q = (Eigen::AngleAxisd(flex_rad, Eigen::Vector3d::UnitZ()) *
                               Eigen::AngleAxisd(add_rad, Eigen::Vector3d::UnitX()) *
                               Eigen::AngleAxisd(rot_rad, Eigen::Vector3d::UnitY()))
                                  .toRotationMatrix();
  Eigen::Isometry3d X = Eigen::Isometry3d::Identity();
  X.linear() = R_GP * R_q * R_GP.transpose();
  X.translation() = kHjc_mm - X.linear() * kHjc_mm;
  return X;
}

/// The femur mesh's vertices in ground at the skeleton's current coordinates.
Eigen::Matrix3Xd femurVerticesInGround(const Skeleton& s, const Eigen::Matrix3Xd& v_M) {
  const int femur = s.findBodyIndex("femur_r");
  const BodyMesh& mesh = s.getBodyMeshes(femur).front();
  const Eigen::Isometry3d X_GM = s.getBodyTransform(femur) * mesh.X_BM;
  return X_GM * (mesh.scale_to_mm.asDiagonal() * v_M);
}

class HipSkeleton : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    skeleton_ = new Skeleton(Skeleton::fromUrdf(kHipUrdf));
    femur_ct_ = new Eigen::Matrix3Xd(test::readPlyVertices(kHipDir + "/meshes/femur_r.ply"));
  }
  static void TearDownTestSuite() {
    delete skeleton_;
    delete femur_ct_;
  }

  /// Sets (flexion, adduction, rotation) and checks every femur vertex against
  /// the analytic rotation about the hip joint centre, to 1e-9 mm.
  void expectFemurFollowsAnalyticMotion(double flex_deg, double add_deg, double rot_deg) {
    Skeleton& s = *skeleton_;
    Eigen::VectorXd q(3);
    q[s.findCoordinateIndex("hip_flexion_r")] = flex_deg * kDeg;
    q[s.findCoordinateIndex("hip_adduction_r")] = add_deg * kDeg;
    q[s.findCoordinateIndex("hip_rotation_r")] = rot_deg * kDeg;
    s.setCoordinateValues(q);
    const Eigen::Matrix3Xd expected =
        analyticFemurMotion(flex_deg * kDeg, add_deg * kDeg, rot_deg * kDeg) * *femur_ct_;
    EXPECT_TRUE(isApprox(femurVerticesInGround(s, *femur_ct_), expected, 0.0, 1e-9))
        << "flexion " << flex_deg << ", adduction " << add_deg << ", rotation " << rot_deg;
    // The hip joint centre is a fixed point: the femur frame origin stays on it.
    EXPECT_TRUE(isApprox(s.getBodyTransform(s.findBodyIndex("femur_r")).translation(), kHjc_mm,
                         0.0, 1e-9));
    // The pelvis is ground: identity whatever the coordinates.
    EXPECT_TRUE(isApprox(s.getBodyTransform(s.findBodyIndex("pelvis")).matrix(),
                         Eigen::Matrix4d::Identity(), 0.0, 1e-15));
  }

  static Skeleton* skeleton_;
  static Eigen::Matrix3Xd* femur_ct_;
};
Skeleton* HipSkeleton::skeleton_ = nullptr;
Eigen::Matrix3Xd* HipSkeleton::femur_ct_ = nullptr;

TEST_F(HipSkeleton, NamesCoordinatesAndBodiesInTreeOrder) {
  EXPECT_EQ(skeleton_->getName(), "hip_r");
  EXPECT_EQ(skeleton_->getCoordinateNames(),
            (std::vector<std::string>{"hip_flexion_r", "hip_adduction_r", "hip_rotation_r"}));
  EXPECT_EQ(skeleton_->getBodyNames(), (std::vector<std::string>{"pelvis", "femur_r_flexion",
                                                                 "femur_r_adduction", "femur_r"}));
  EXPECT_EQ(skeleton_->findCoordinateIndex("knee_angle_r"), -1);
  EXPECT_EQ(skeleton_->findBodyIndex("tibia_r"), -1);
}

TEST_F(HipSkeleton, FromUrdfTextEqualsReadingTheFile) {
  std::ifstream in(kHipUrdf);
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  Skeleton from_text = Skeleton::fromUrdfText(text, kHipUrdf);
  EXPECT_EQ(from_text.getCoordinateNames(), skeleton_->getCoordinateNames());
  EXPECT_EQ(from_text.getBodyNames(), skeleton_->getBodyNames());
  const Eigen::Vector3d q(0.3, -0.2, 0.1);
  from_text.setCoordinateValues(q);
  skeleton_->setCoordinateValues(q);
  const int femur = skeleton_->findBodyIndex("femur_r");
  EXPECT_TRUE(from_text.getBodyTransform(femur).isApprox(skeleton_->getBodyTransform(femur), 0.0));
  skeleton_->setCoordinateValues(Eigen::Vector3d::Zero());
  // Meshes resolve beside the path given: elsewhere they are missing, and the error says so.
  expectModelError([&] { Skeleton::fromUrdfText(text, "/nonexistent/hip_r.urdf"); },
                         {"URDF /nonexistent/hip_r.urdf", "does not exist"});
}

TEST_F(HipSkeleton, MeshesResolveBesideUrdfWithMmScale) {
  // femur: one visual and one collision mesh; pelvis: the right ilium and the sacrum as both,
  // the left ilium as a visual only (it touches no muscle of the right hip).
  const std::pair<const char*, std::vector<std::pair<std::string, bool>>> expected[] = {
      {"femur_r", {{"femur_r.ply", false}, {"femur_r.ply", true}}},
      {"pelvis",
       {{"pelvis_iliac_r.ply", false}, {"pelvis_iliac_r.ply", true}, {"pelvis_sacrum.ply", false},
        {"pelvis_sacrum.ply", true}, {"pelvis_iliac_l.ply", false}}}};
  for (const auto& [body, parts] : expected) {
    std::vector<std::pair<std::string, bool>> found, wanted;
    for (const BodyMesh& mesh : skeleton_->getBodyMeshes(skeleton_->findBodyIndex(body))) {
      found.emplace_back(mesh.path, mesh.collision);
      EXPECT_TRUE(isApprox(mesh.scale_to_mm, Eigen::Vector3d::Ones(), 1e-15));
    }
    for (const auto& [file, collision] : parts) wanted.emplace_back(kHipDir + "/meshes/" + file, collision);
    std::sort(found.begin(), found.end());
    std::sort(wanted.begin(), wanted.end());
    EXPECT_EQ(found, wanted) << body;
  }
}

TEST_F(HipSkeleton, FemurMeshSitsAtItsCtPositionAtZero) { expectFemurFollowsAnalyticMotion(0, 0, 0); }
TEST_F(HipSkeleton, Flexion80) { expectFemurFollowsAnalyticMotion(80, 0, 0); }
TEST_F(HipSkeleton, Adduction30) { expectFemurFollowsAnalyticMotion(0, 30, 0); }
TEST_F(HipSkeleton, RotationMinus30) { expectFemurFollowsAnalyticMotion(0, 0, -30); }
TEST_F(HipSkeleton, CombinedAngles) {
  expectFemurFollowsAnalyticMotion(35, -7, 12);
  expectFemurFollowsAnalyticMotion(-10, 25, -28);
}

TEST_F(HipSkeleton, FlexionMovesTheKneeAnteriorly) {
  // hip_frame.json: positive flexion moves the knee toward −y in CT. Take the
  // lowest femur vertex (distal end, smallest z) as the knee.
  Eigen::Index distal = 0;
  femur_ct_->row(2).minCoeff(&distal);
  skeleton_->setCoordinateValues(Eigen::Vector3d(0, 0, 0));
  const double y0 = femurVerticesInGround(*skeleton_, *femur_ct_)(1, distal);
  skeleton_->setCoordinateValues(Eigen::Vector3d(30 * kDeg, 0, 0));
  const double y30 = femurVerticesInGround(*skeleton_, *femur_ct_)(1, distal);
  EXPECT_LT(y30, y0 - 100.0);  // a ~40 cm femur: the knee moves ~20 cm forward
}

TEST_F(HipSkeleton, RejectsWrongSizeOrNonFiniteCoordinates) {
  EXPECT_THROW(skeleton_->setCoordinateValues(Eigen::VectorXd::Zero(2)), std::invalid_argument);
  EXPECT_THROW(skeleton_->setCoordinateValues(Eigen::Vector3d(0, std::nan(""), 0)),
               std::invalid_argument);
  EXPECT_THROW(skeleton_->getBodyTransform(4), std::out_of_range);
}

/// Rz(y) Ry(p) Rx(r): the URDF rpy convention.
Eigen::Matrix3d rpy(double r, double p, double y) {
  return (Eigen::AngleAxisd(y, Eigen::Vector3d::UnitZ()) * Eigen::AngleAxisd(p, Eigen::Vector3d::UnitY()) *
          Eigen::AngleAxisd(r, Eigen::Vector3d::UnitX()))
      .toRotationMatrix();
}

TEST(Skeleton, ArbitraryAxisContinuousAndFixedJointsFollowUrdfKinematics) {
  TempFile f("arm.urdf");
  f.write(R"(<robot name="arm">
    <link name="base"/>
    <joint name="swing" type="continuous">
      <parent link="base"/><child link="upper"/>
      <origin xyz="0.1 0.2 0.3" rpy="0.3 -0.2 0.5"/>
      <axis xyz="1 -2 0.5"/>
    </joint>
    <link name="upper"><inertial><mass value="2"/><origin xyz="0 0 0.1" rpy="0.1 0 0"/>
      <inertia ixx="0.02" ixy="0" ixz="0" iyy="0.02" iyz="0" izz="0.01"/></inertial></link>
    <joint name="tip_weld" type="fixed">
      <parent link="upper"/><child link="tip"/>
      <origin xyz="0 0 0.05" rpy="0 0.4 0"/>
    </joint>
    <link name="tip"/>
  </robot>)");
  Skeleton s = Skeleton::fromUrdf(f.path());
  ASSERT_EQ(s.getCoordinateNames(), std::vector<std::string>{"swing"});
  const double q = 1.1;
  s.setCoordinateValues(Eigen::VectorXd::Constant(1, q));

  Eigen::Isometry3d X_GJ = Eigen::Isometry3d::Identity();
  X_GJ.linear() = rpy(0.3, -0.2, 0.5);
  X_GJ.translation() = Eigen::Vector3d(100, 200, 300);  // mm
  const Eigen::Isometry3d X_GU = X_GJ * Eigen::AngleAxisd(q, Eigen::Vector3d(1, -2, 0.5).normalized());
  Eigen::Isometry3d X_UT = Eigen::Isometry3d::Identity();
  X_UT.linear() = rpy(0, 0.4, 0);
  X_UT.translation() = Eigen::Vector3d(0, 0, 50);
  EXPECT_TRUE(isApprox(s.getBodyTransform(s.findBodyIndex("upper")).matrix(), X_GU.matrix(), 0, 1e-12));
  EXPECT_TRUE(isApprox(s.getBodyTransform(s.findBodyIndex("tip")).matrix(), (X_GU * X_UT).matrix(), 0,
                       1e-12));
  EXPECT_TRUE(s.getBodyMeshes(0).empty());
}

TEST(Skeleton, UrdfAxisOfHugeComponentsIsTheSameDirection) {
  // Its plain norm overflows to infinity; the axis was NaN and Simbody refused its own inertia.
  const auto makeArm = [](const std::string& axis) {
    TempFile f("axis_" + std::to_string(axis.size()) + ".urdf");
    f.write(R"(<robot name="arm"><link name="base"/><link name="upper"/>
      <joint name="swing" type="continuous"><parent link="base"/><child link="upper"/>
        <axis xyz=")" + axis + R"("/></joint></robot>)");
    Skeleton s = Skeleton::fromUrdf(f.path());
    s.setCoordinateValues(Eigen::VectorXd::Constant(1, 0.7));
    return s.getBodyTransform(s.findBodyIndex("upper"));
  };
  EXPECT_TRUE(isApprox(makeArm("1e300 -2e300 0").matrix(), makeArm("1 -2 0").matrix(), 0, 1e-15));
}

TEST(SkeletonErrors, UrdfElementUrdfdomCannotReadIsRefusedNotLeftOut) {
  // urdfdom reports an unreadable origin, then returns the model without the link's collision
  // (or visual) elements: the bone silently left the contacts.
  for (const std::string& element : std::vector<std::string>{"collision", "visual"})
    for (const char* origin : {R"(rpy="nan 0 0")", R"(xyz="abc")"}) {
      TempFile f("unreadable_" + element + ".urdf");
      f.write("<robot name=\"r\"><link name=\"bone\"><" + element + "><origin " + origin +
              "/><geometry><mesh filename=\"" + kHipDir + "/meshes/femur_r.ply\" scale=\"0.001 0.001 0.001\"/>" +
              "</geometry></" + element + "></link></robot>");
      expectModelError([&] { Skeleton::fromUrdf(f.path()); },
                       {f.path(), "urdfdom left out what it could not read",
                        "Could not parse " + element + " element for Link [bone]"});
    }
}

TEST(SkeletonErrors, MissingUrdfNamesFile) {
  expectModelError([] { Skeleton::fromUrdf("/nonexistent/hip.urdf"); }, {"/nonexistent/hip.urdf"});
}

TEST(SkeletonErrors, MalformedUrdfNamesFile) {
  TempFile f("malformed.urdf");
  f.write("<robot name=\"broken\"><link name=\"a\"></robot>");
  expectModelError([&] { Skeleton::fromUrdf(f.path()); }, {f.path(), "line 1: not well-formed XML"});
}

TEST(SkeletonErrors, DeeplyNestedUrdfIsRefusedBeforeUrdfdomRecursesThroughIt) {
  // urdfdom's TinyXML parses recursively: 200 000 nested elements overflowed the stack (signal 11).
  const int depth = 200000;
  std::string text = "<robot name=\"r\"><link name=\"a\"/>";
  for (int i = 0; i < depth; ++i) text += "<x>";
  for (int i = 0; i < depth; ++i) text += "</x>";
  text += "</robot>";
  expectModelError([&] { Skeleton::fromUrdfText(text, "deep.urdf"); },
                   {"URDF deep.urdf: line 1: not well-formed XML", "Element nesting is too deep"});
}

TEST(SkeletonErrors, PrismaticJointNamesJoint) {
  TempFile f("prismatic.urdf");
  f.write(R"(<robot name="slider"><link name="a"/><link name="b"/>
    <joint name="slide_x" type="prismatic"><parent link="a"/><child link="b"/>
      <axis xyz="1 0 0"/><limit lower="0" upper="1" effort="1" velocity="1"/></joint></robot>)");
  expectModelError([&] { Skeleton::fromUrdf(f.path()); }, {f.path(), "'slide_x'", "prismatic"});
}

TEST(SkeletonErrors, MissingMeshNamesUrdfLinkAndMesh) {
  TempFile f("missing_mesh.urdf");
  f.write(R"(<robot name="r"><link name="bone"><visual><geometry>
    <mesh filename="meshes/no_such_bone.ply" scale="0.001 0.001 0.001"/></geometry></visual></link></robot>)");
  expectModelError([&] { Skeleton::fromUrdf(f.path()); },
                   {f.path(), "'bone'", "meshes/no_such_bone.ply"});
}

TEST(SkeletonErrors, PackageUriIsRejectedWithAdvice) {
  TempFile f("package_uri.urdf");
  f.write(R"(<robot name="r"><link name="bone"><visual><geometry>
    <mesh filename="package://hip/meshes/femur_r.ply"/></geometry></visual></link></robot>)");
  expectModelError([&] { Skeleton::fromUrdf(f.path()); }, {f.path(), "'bone'", "package://"});
}

const char* const kRevoluteLimit = R"(<axis xyz="0 0 1"/><limit lower="-1" upper="1" effort="1" velocity="1"/>)";

TEST(SkeletonErrors, UrdfWithAJointCycleIsRefusedNamingTheLinks) {
  // base → a → b → a: urdfdom accepts it (the root is base), following the links never ends
  // (a stack overflow), and a has two parents; the loop is refused before urdfdom reads it.
  TempFile f("cycle.urdf");
  f.write(std::string(R"(<robot name="cycle"><link name="base"/><link name="a"/><link name="b"/>
    <joint name="j_base_a" type="revolute"><parent link="base"/><child link="a"/>)") + kRevoluteLimit + R"(</joint>
    <joint name="j_a_b" type="revolute"><parent link="a"/><child link="b"/>)" + kRevoluteLimit + R"(</joint>
    <joint name="j_b_a" type="revolute"><parent link="b"/><child link="a"/>)" + kRevoluteLimit + R"(</joint></robot>)");
  expectModelError([&] { Skeleton::fromUrdf(f.path()); },
                   {f.path(), "'j_a_b', 'j_b_a'", "closed loop of links ('a' → 'b' → 'a')", "must form a tree"});
}

TEST(SkeletonErrors, UrdfLoopApartFromTheRootIsRefusedNamingTheLink) {
  // a → b → a beside the root: no link has two parents, but a and b hang on nothing.
  TempFile f("loop_apart.urdf");
  f.write(std::string(R"(<robot name="apart"><link name="base"/><link name="a"/><link name="b"/><link name="c"/>
    <joint name="j_base_c" type="fixed"><parent link="base"/><child link="c"/></joint>
    <joint name="j_a_b" type="revolute"><parent link="a"/><child link="b"/>)") + kRevoluteLimit + R"(</joint>
    <joint name="j_b_a" type="revolute"><parent link="b"/><child link="a"/>)" + kRevoluteLimit + R"(</joint></robot>)");
  try {
    Skeleton::fromUrdf(f.path());
    ADD_FAILURE() << "expected an error";
  } catch (const std::exception& e) {
    // urdfdom itself may refuse it (two roots); either way a clear error naming the file.
    EXPECT_NE(std::string(e.what()).find(f.path()), std::string::npos) << e.what();
  }
}

TEST(SkeletonErrors, UrdfWhoseLinksAllHangInALoopIsRefusedNamingTheJoints) {
  // a → b → a and nothing else: urdfdom finds no root and drops a model whose links hold each
  // other (a leak under the sanitizers); the loop is refused before urdfdom reads it.
  TempFile f("loop_only.urdf");
  f.write(std::string(R"(<robot name="loop"><link name="a"/><link name="b"/>
    <joint name="j_a_b" type="revolute"><parent link="a"/><child link="b"/>)") + kRevoluteLimit + R"(</joint>
    <joint name="j_b_a" type="revolute"><parent link="b"/><child link="a"/>)" + kRevoluteLimit + R"(</joint></robot>)");
  expectModelError([&] { Skeleton::fromUrdf(f.path()); },
                   {f.path(), "'j_a_b'", "'j_b_a'", "form a closed loop of links", "must form a tree"});
}

TEST(SkeletonErrors, UrdfJointWhoseParentIsItsChildIsRefusedBesideALinkWithTwoParents) {
  // j_a_a hangs a on itself; a also hangs on the missing b. urdfdom links a into a before it
  // finds b missing (a leak under the sanitizers, found by the fuzzer): refused before it reads.
  TempFile f("self_loop.urdf");
  f.write(std::string(R"(<robot name="loop"><link name="a"/>
    <joint name="j_a_a" type="revolute"><parent link="a"/><child link="a"/>)") + kRevoluteLimit + R"(</joint>
    <joint name="j_b_a" type="revolute"><parent link="b"/><child link="a"/>)" + kRevoluteLimit + R"(</joint></robot>)");
  expectModelError([&] { Skeleton::fromUrdf(f.path()); },
                   {f.path(), "'j_a_a'", "closed loop of links ('a' → 'a')", "must form a tree"});
}

TEST(SkeletonErrors, UrdfJointLinkWithAnUnknownEntityIsRefused) {
  // "&a" is "&a" to the loop check's XML reader and the link a to urdfdom's, which then closes
  // the loop a → b → a that the check did not see (a leak under the sanitizers, found by the fuzzer).
  TempFile f("entity_loop.urdf");
  f.write(std::string(R"(<robot name="loop"><link name="a"/><link name="b"/>
    <joint name="j_a_b" type="revolute"><parent link="&a"/><child link="b"/>)") + kRevoluteLimit + R"(</joint>
    <joint name="j_b_a" type="revolute"><parent link="b"/><child link="a"/>)" + kRevoluteLimit + R"(</joint></robot>)");
  expectModelError([&] { Skeleton::fromUrdf(f.path()); }, {f.path(), "joint 'j_a_b'", "'&a'", "without '&'"});
}

TEST(SkeletonErrors, UrdfMeshScaleOfZeroIsRefusedNamingTheLinkAndMesh) {
  TempFile f("scale_zero.urdf");
  f.write("<robot name=\"r\"><link name=\"bone\"><visual><geometry><mesh filename=\"" + kHipDir +
          "/meshes/femur_r.ply\" scale=\"0 0.001 0.001\"/></geometry></visual></link></robot>");
  expectModelError([&] { Skeleton::fromUrdf(f.path()); },
                   {f.path(), "link 'bone'", "femur_r.ply", "has scale 0 0.001 0.001", "expected each factor from 1e-06"});
}

TEST(SkeletonErrors, UrdfNegativeMeshScaleIsRefused) {
  TempFile f("scale_negative.urdf");
  f.write("<robot name=\"r\"><link name=\"bone\"><visual><geometry><mesh filename=\"" + kHipDir +
          "/meshes/femur_r.ply\" scale=\"-0.001 0.001 0.001\"/></geometry></visual></link></robot>");
  expectModelError([&] { Skeleton::fromUrdf(f.path()); }, {f.path(), "link 'bone'", "mirror"});
}

TEST(SkeletonErrors, UrdfJointOriginFarAwayIsRefusedNamingTheJoint) {
  TempFile f("far_origin.urdf");
  f.write(std::string(R"(<robot name="far"><link name="a"/><link name="b"/>
    <joint name="j" type="revolute"><origin xyz="1e9 0 0"/><parent link="a"/><child link="b"/>)") + kRevoluteLimit +
          "</joint></robot>");
  expectModelError([&] { Skeleton::fromUrdf(f.path()); }, {f.path(), "joint 'j'", "origin xyz 1e+09 0 0 m"});
}

// Found by fuzz_urdf: the hip URDF with the pelvis's ixx raised to 1.1 (iyy = izz = 0.1). No
// rigid body has such moments; Simbody threw an exception of its own from deep in its build.
// The fuzzer also put a control character into the femur's inertial origin ("0 -\x10.17 0"); urdfdom
// cannot read that and left the inertial out without failing, so the input is now refused for that first.
TEST(SkeletonErrors, UrdfInertiaNoBodyCanHaveIsRefusedNamingTheLink) {
  const std::string path = std::string(RBFMUSCLE_SOURCE_DIR) + "/tests/unit/model/data/fuzz/inertia_breaks_triangle_inequality.urdf";
  expectModelError([&] { Skeleton::fromUrdf(path); },
                   {"URDF " + path, "urdfdom left out what it could not read",
                    "Could not parse inertial element for Link [femur_r]"});
  std::ifstream in(path);
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  text.replace(text.find("\"0 -\x10.17 0\""), 11, "\"0 -0.17 0\"");
  expectModelError([&] { Skeleton::fromUrdfText(text, path); },
                   {"URDF " + path, "link 'pelvis': <inertial> inertia about the mass centre has principal moments",
                    "below the sum of the other two"});
}

// Found by fuzz_urdf: a light link of the hip URDF with iyy = 0 (ixx = izz = 1e-9 kg·m²) behind a
// joint axis of (1, 5, 0). Simbody built the system, then threw its own exception from deep in
// posing it: turned with its body, the inertia's diagonal rounded to −4.5e-13 kg·mm².
TEST(SkeletonErrors, UrdfInertiaWithAZeroPrincipalMomentIsRefusedNamingTheLink) {
  const std::string path =
      std::string(RBFMUSCLE_SOURCE_DIR) + "/tests/unit/model/data/fuzz/inertia_with_a_zero_principal_moment.urdf";
  expectModelError([&] { Skeleton::fromUrdf(path); },
                   {"URDF " + path, "link 'femur_r_adduction': <inertial> inertia about the mass centre has principal moments",
                    "expected each above 0"});
}

TEST(SkeletonErrors, InertiaMustClearZeroAndTheTriangleInequalityByAMargin) {
  using detail::findMassPropertiesProblem;
  const auto inertia = [](double a, double b, double c) { return Eigen::Vector3d(a, b, c).asDiagonal().toDenseMatrix(); };
  EXPECT_EQ(findMassPropertiesProblem(1.0, inertia(1, 1, 1)), "");
  EXPECT_EQ(findMassPropertiesProblem(0.0, inertia(0, 0, 0)), "");          // a massless point
  EXPECT_EQ(findMassPropertiesProblem(1.0, inertia(1, 1e-8, 1)), "");       // a thin rod, not a line
  EXPECT_NE(findMassPropertiesProblem(1.0, inertia(1, 0, 1)), "");          // a line
  EXPECT_NE(findMassPropertiesProblem(1.0, inertia(1, 1e-12, 1)), "");      // within rounding of one
  EXPECT_EQ(findMassPropertiesProblem(1.0, inertia(1, 1, 2 - 1e-8)), "");   // a thin plate
  EXPECT_NE(findMassPropertiesProblem(1.0, inertia(1, 1, 2)), "");          // a flat plate
  EXPECT_NE(findMassPropertiesProblem(1.0, inertia(1, 1, 2.1)), "");        // no body
}

// Found by fuzz_urdf: the hip URDF cut inside a name of UTF-8 lead bytes. urdfdom's TinyXML read
// past the end of the text (a heap overflow under AddressSanitizer).
TEST(SkeletonErrors, UrdfEndingInsideAUtf8CharacterIsRefusedBeforeUrdfdomReadsIt) {
  const std::string path = std::string(RBFMUSCLE_SOURCE_DIR) + "/tests/unit/model/data/fuzz/utf8_lead_byte_at_the_end.urdf";
  expectModelError([&] { Skeleton::fromUrdf(path); }, {"URDF " + path, "is not valid UTF-8"});
}

TEST(SkeletonErrors, UrdfNegativeOrHugeMassAndFarInertialOriginAreRefused) {
  TempFile f("bad_mass.urdf");
  f.write(R"(<robot name="r"><link name="a"><inertial><mass value="-1"/><inertia ixx="1" ixy="0" ixz="0" iyy="1" iyz="0" izz="1"/></inertial></link></robot>)");
  expectModelError([&] { Skeleton::fromUrdf(f.path()); }, {f.path(), "link 'a'", "mass -1 kg: expected a finite mass from 0"});
  f.write(R"(<robot name="r"><link name="a"><inertial><mass value="1e300"/><inertia ixx="1" ixy="0" ixz="0" iyy="1" iyz="0" izz="1"/></inertial></link></robot>)");
  expectModelError([&] { Skeleton::fromUrdf(f.path()); }, {f.path(), "link 'a'", "mass 1e+300 kg"});
  f.write(R"(<robot name="r"><link name="a"><inertial><origin xyz="0 1e300 0"/><mass value="1"/><inertia ixx="1" ixy="0" ixz="0" iyy="1" iyz="0" izz="1"/></inertial></link></robot>)");
  expectModelError([&] { Skeleton::fromUrdf(f.path()); }, {f.path(), "link 'a': <inertial>: origin xyz 0 1e+300 0 m"});
}

// As fuzz_osim found for OpenSim geometry: a mesh name longer than the system allows is a
// missing mesh, not a std::filesystem exception.
TEST(SkeletonErrors, UrdfMeshNameLongerThanTheSystemAllowsIsAMissingMesh) {
  TempFile f("long_mesh_name.urdf");
  const std::string name = std::string(5000, 'm') + ".ply";
  f.write("<robot name=\"r\"><link name=\"bone\"><visual><geometry><mesh filename=\"" + name +
          "\"/></geometry></visual></link></robot>");
  expectModelError([&] { Skeleton::fromUrdf(f.path()); }, {f.path(), "link 'bone'", "does not exist"});
}

TEST(SkeletonErrors, UrdfPathThatIsADeviceIsRefusedWithoutReading) {
  expectModelError([] { Skeleton::fromUrdf("/dev/zero"); }, {"/dev/zero", "is a character device, not a regular file"});
}

}  // namespace
}  // namespace rbfmuscle
