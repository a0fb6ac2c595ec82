// SPDX-License-Identifier: Apache-2.0
// Skeletons from OpenSim models: the subject's LHDL model (3.x layout) against an independent
// computation from the file's own numbers, a 4.x layout model, the rest pose with every body at
// ground, and the constructs the reader refuses.
#include <gtest/gtest.h>
#include <tinyxml2.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <iterator>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "model/skeleton.h"
#include "model_test_support.h"

namespace rbfmuscle {
namespace {

using test::expectModelError;

constexpr double kPi = 3.141592653589793238462643383279502884;
constexpr double kDeg = kPi / 180.0;
const std::string kHipDir = std::string(RBFMUSCLE_SOURCE_DIR) + "/models/hip";
const std::string kOsim = kHipDir + "/osim/LHDL_hip_r.osim";
const std::string kData = std::string(RBFMUSCLE_SOURCE_DIR) + "/tests/unit/model/data/osim/";

// ---------------------------------------------------------------- independent computation
// Reads the numbers of a 3.x CustomJoint straight from the XML (tinyxml2 here, not the
// project's reader) and composes the transforms with Eigen (not Simbody).

std::vector<double> numbersOf(const tinyxml2::XMLElement* e) {
  std::vector<double> out;
  std::istringstream in(e && e->GetText() ? e->GetText() : "");
  double v;
  while (in >> v) out.push_back(v);
  return out;
}

Eigen::Vector3d vec3Of(const tinyxml2::XMLElement& parent, const char* name) {
  const std::vector<double> v = numbersOf(parent.FirstChildElement(name));
  EXPECT_EQ(v.size(), 3u) << name;
  return {v.at(0), v.at(1), v.at(2)};
}

/// Pose from metres and OpenSim's body-fixed XYZ angles: Rx(a)·Ry(b)·Rz(c), translation in mm.
Eigen::Isometry3d poseOf(const Eigen::Vector3d& location_m, const Eigen::Vector3d& xyz) {
  Eigen::Isometry3d X = Eigen::Isometry3d::Identity();
  X.linear() = (Eigen::AngleAxisd(xyz.x(), Eigen::Vector3d::UnitX()) * Eigen::AngleAxisd(xyz.y(), Eigen::Vector3d::UnitY()) *
                Eigen::AngleAxisd(xyz.z(), Eigen::Vector3d::UnitZ()))
                   .toRotationMatrix();
  X.translation() = 1000.0 * location_m;
  return X;
}

/// One 3.x CustomJoint as the file gives it.
struct FileJoint {
  std::string parent;
  Eigen::Isometry3d X_PF, X_BM;       ///< joint frames in parent and child (mm)
  Eigen::Vector3d axis[6];            ///< rotation1–3, translation1–3
  std::string coordinate[6];          ///< "" for a constant axis
  double constant[6] = {0, 0, 0, 0, 0, 0};  ///< the Constant's value (m for translations)

  /// X_FM at the coordinate values `q` (rad, m), as OpenSim defines a CustomJoint: body-fixed
  /// rotations about the three axes in order, then the translations along theirs (in F).
  Eigen::Isometry3d X_FM(const std::map<std::string, double>& q) const {
    const auto value = [&](int i) { return coordinate[i].empty() ? constant[i] : q.at(coordinate[i]); };
    Eigen::Isometry3d X = Eigen::Isometry3d::Identity();
    for (int i = 0; i < 3; ++i) X.linear() = X.linear() * Eigen::AngleAxisd(value(i), axis[i].normalized()).toRotationMatrix();
    for (int i = 3; i < 6; ++i) X.translation() += 1000.0 * value(i) * axis[i].normalized();
    return X;
  }
  Eigen::Isometry3d X_PB(const std::map<std::string, double>& q) const { return X_PF * X_FM(q) * X_BM.inverse(); }
};

FileJoint readFileJoint(const std::string& body_name) {
  tinyxml2::XMLDocument doc;
  EXPECT_EQ(doc.LoadFile(kOsim.c_str()), tinyxml2::XML_SUCCESS);
  const tinyxml2::XMLElement* body = doc.RootElement()->FirstChildElement("Model")->FirstChildElement("BodySet")
                                         ->FirstChildElement("objects")->FirstChildElement("Body");
  while (body && std::string(body->Attribute("name")) != body_name) body = body->NextSiblingElement("Body");
  const tinyxml2::XMLElement* joint = body->FirstChildElement("Joint")->FirstChildElement("CustomJoint");
  FileJoint j;
  j.parent = joint->FirstChildElement("parent_body")->GetText();
  j.X_PF = poseOf(vec3Of(*joint, "location_in_parent"), vec3Of(*joint, "orientation_in_parent"));
  j.X_BM = poseOf(vec3Of(*joint, "location"), vec3Of(*joint, "orientation"));
  int i = 0;
  for (const tinyxml2::XMLElement* a = joint->FirstChildElement("SpatialTransform")->FirstChildElement("TransformAxis"); a;
       a = a->NextSiblingElement("TransformAxis"), ++i) {
    j.axis[i] = vec3Of(*a, "axis");
    const char* c = a->FirstChildElement("coordinates")->GetText();
    j.coordinate[i] = c ? c : "";
    const tinyxml2::XMLElement* f = a->FirstChildElement("function")->FirstChildElement();
    if (std::string(f->Name()) == "Constant") {
      j.constant[i] = numbersOf(f->FirstChildElement("value")).at(0);
    } else {  // this model's LinearFunctions are the identity: value = 1·q + 0
      EXPECT_EQ(std::string(f->Name()), "LinearFunction");
      EXPECT_EQ(numbersOf(f->FirstChildElement("coefficients")), (std::vector<double>{1, 0}));
    }
  }
  EXPECT_EQ(i, 6);
  return j;
}

/// Corners of the femur's bounding box in the CT frame (mm, from its VTP geometry): points
/// spanning the whole bone, from the femoral head to the condyles.
std::vector<Eigen::Vector3d> femurBoxCorners() {
  const Eigen::Vector3d lo(79.38, 220.08, -855.17), hi(167.50, 314.69, -409.73);
  std::vector<Eigen::Vector3d> corners;
  for (int k = 0; k < 8; ++k) corners.emplace_back(k & 1 ? hi.x() : lo.x(), k & 2 ? hi.y() : lo.y(), k & 4 ? hi.z() : lo.z());
  return corners;
}

/// Largest distance between the femur points placed by two poses (mm).
double femurPlacementError(const Eigen::Isometry3d& a, const Eigen::Isometry3d& b) {
  double worst = 0.0;
  for (const Eigen::Vector3d& p : femurBoxCorners()) worst = std::max(worst, (a * p - b * p).norm());
  return worst;
}

class LhdlOsim : public ::testing::Test {
 protected:
  static void SetUpTestSuite() { skeleton_ = new Skeleton(Skeleton::fromOsim(kOsim)); }
  static void TearDownTestSuite() { delete skeleton_; }

  /// Sets the named coordinates (rad, mm), the others 0.
  static void set(const std::map<std::string, double>& values) {
    Eigen::VectorXd q = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(skeleton_->getCoordinateNames().size()));
    for (const auto& [name, v] : values) q[skeleton_->findCoordinateIndex(name)] = v;
    skeleton_->setCoordinateValues(q);
  }
  static Eigen::Isometry3d pose(const char* body) { return skeleton_->getBodyTransform(skeleton_->findBodyIndex(body)); }

  static Skeleton* skeleton_;
};
Skeleton* LhdlOsim::skeleton_ = nullptr;

TEST_F(LhdlOsim, NamesBodiesCoordinatesAndGeometry) {
  const Skeleton& s = *skeleton_;
  EXPECT_EQ(s.getName(), "LHDL_hip_model_v2.1");
  EXPECT_EQ(s.getModelPath(), kOsim);
  EXPECT_EQ(s.getBodyNames(), (std::vector<std::string>{"ground", "pelvis", "femur_r"}));
  EXPECT_EQ(s.getCoordinateNames(),
            (std::vector<std::string>{"pelvis_tilt", "pelvis_list", "pelvis_rotation", "pelvis_tx", "pelvis_ty",
                                      "pelvis_tz", "hip_flexion_r", "hip_adduction_r", "hip_rotation_r"}));
  const auto& c = s.getCoordinates();
  EXPECT_EQ(c[3].motion, CoordinateMotion::kTranslational);
  EXPECT_DOUBLE_EQ(c[3].range_min, -2500.0);  // ±2.5 m
  EXPECT_EQ(c[6].motion, CoordinateMotion::kRotational);
  EXPECT_EQ(c[6].joint, "hip_r");
  EXPECT_DOUBLE_EQ(c[6].range_min, -0.174532925199433);
  EXPECT_DOUBLE_EQ(c[6].range_max, 1.5707963267949);
  EXPECT_EQ(s.getDefaultCoordinateValues(), Eigen::VectorXd::Zero(9));
  // .\geometry\LHDL_femur_r.vtp, VisibleObject scale 0.001 of a metre model: the mesh is in mm.
  const auto& meshes = s.getBodyMeshes(s.findBodyIndex("femur_r"));
  ASSERT_EQ(meshes.size(), 1u);
  EXPECT_EQ(meshes[0].path, kHipDir + "/osim/geometry/LHDL_femur_r.vtp");
  EXPECT_EQ(meshes[0].scale_to_mm, Eigen::Vector3d::Ones());
  EXPECT_TRUE(meshes[0].X_BM.matrix().isIdentity(0.0));
  EXPECT_FALSE(meshes[0].collision);
  EXPECT_EQ(s.getBodyMeshes(s.findBodyIndex("pelvis"))[0].path, kHipDir + "/osim/geometry/LHDL_pelvis.vtp");
  EXPECT_TRUE(s.getBodyMeshes(s.findBodyIndex("ground")).empty());
}

// The femur at q = 0 and at 45° hip flexion, to 0.01 mm of the independent computation (8 points
// spanning the bone).
TEST_F(LhdlOsim, PlacesTheFemurAsTheFileSays) {
  const FileJoint pelvis_joint = readFileJoint("pelvis"), hip = readFileJoint("femur_r");
  ASSERT_EQ(pelvis_joint.parent, "ground");
  ASSERT_EQ(hip.parent, "pelvis");
  for (const double flexion_deg : {0.0, 45.0}) {
    std::map<std::string, double> q = {{"pelvis_tilt", 0}, {"pelvis_list", 0}, {"pelvis_rotation", 0},
                                       {"pelvis_tx", 0},   {"pelvis_ty", 0},   {"pelvis_tz", 0},
                                       {"hip_flexion_r", flexion_deg * kDeg}, {"hip_adduction_r", 0},
                                       {"hip_rotation_r", 0}};
    set({{"hip_flexion_r", flexion_deg * kDeg}});
    const Eigen::Isometry3d expected_pelvis = pelvis_joint.X_PB(q);
    const Eigen::Isometry3d expected_femur = expected_pelvis * hip.X_PB(q);
    const double pelvis_error = femurPlacementError(pose("pelvis"), expected_pelvis);
    const double femur_error = femurPlacementError(pose("femur_r"), expected_femur);
    std::printf("hip flexion %4.1f deg: femur placed %.2e mm from the independent computation (pelvis %.2e mm)\n",
                flexion_deg, femur_error, pelvis_error);
    EXPECT_LT(femur_error, 0.01) << flexion_deg << " deg";
    EXPECT_LT(pelvis_error, 0.01);
  }
  // A combined pose, pelvis translated too (coordinates in mm here, metres in the file).
  std::map<std::string, double> q = {{"pelvis_tilt", 0.2}, {"pelvis_list", -0.1}, {"pelvis_rotation", 0.3},
                                     {"pelvis_tx", 0.05},  {"pelvis_ty", 0.9},    {"pelvis_tz", -0.02},
                                     {"hip_flexion_r", 0.7}, {"hip_adduction_r", -0.2}, {"hip_rotation_r", 0.15}};
  std::map<std::string, double> q_mm = q;
  for (const char* t : {"pelvis_tx", "pelvis_ty", "pelvis_tz"}) q_mm[t] *= 1000.0;
  set(q_mm);
  const Eigen::Isometry3d expected = pelvis_joint.X_PB(q) * hip.X_PB(q);
  EXPECT_LT(femurPlacementError(pose("femur_r"), expected), 0.01);
}

// The rest pose: the bodies of this model are all given in the CT frame, so the pose where every
// body frame is at ground puts the bones where the meshes were segmented.
TEST_F(LhdlOsim, RestPoseWithEveryBodyAtGround) {
  const Eigen::VectorXd rest = skeleton_->solveBodiesAtGround();
  skeleton_->setCoordinateValues(rest);
  EXPECT_TRUE(pose("pelvis").matrix().isApprox(Eigen::Matrix4d::Identity(), 1e-12)) << pose("pelvis").matrix();
  // location_in_parent and location of hip_r differ by 1 µm (z −0.43267 against −0.432669 m);
  // the hip has no translational coordinate to take it up.
  const double femur_offset = femurPlacementError(pose("femur_r"), Eigen::Isometry3d::Identity());
  std::printf("rest pose: femur %.2e mm from its CT position\n", femur_offset);
  EXPECT_LT(femur_offset, 0.0011);
  const auto deg = [&](const char* name) { return rest[skeleton_->findCoordinateIndex(name)] / kDeg; };
  std::printf("rest pose: hip_flexion_r %.6f, hip_adduction_r %.6f, hip_rotation_r %.6f deg; pelvis tilt %.4f, list "
              "%.4f, rotation %.4f deg, tx %.3f, ty %.3f, tz %.3f mm\n",
              deg("hip_flexion_r"), deg("hip_adduction_r"), deg("hip_rotation_r"), deg("pelvis_tilt"),
              deg("pelvis_list"), deg("pelvis_rotation"), rest[3], rest[4], rest[5]);
  EXPECT_NEAR(deg("hip_flexion_r"), 1.5760, 1e-3);
  EXPECT_NEAR(deg("hip_adduction_r"), -4.7269, 1e-3);
  EXPECT_NEAR(deg("hip_rotation_r"), -5.2899, 1e-3);
  EXPECT_NEAR(rest[skeleton_->findCoordinateIndex("pelvis_tx")], 238.855, 1e-9);
  EXPECT_NEAR(rest[skeleton_->findCoordinateIndex("pelvis_ty")], 180.177, 1e-9);
  EXPECT_NEAR(rest[skeleton_->findCoordinateIndex("pelvis_tz")], -357.605, 1e-9);
  // Set as the rest pose, it is what setRestCoordinateValues keeps.
  skeleton_->setRestCoordinateValues(rest);
  EXPECT_EQ(skeleton_->getRestCoordinateValues(), rest);
  EXPECT_THROW(skeleton_->setRestCoordinateValues(Eigen::VectorXd::Zero(2)), std::invalid_argument);
}

// Flexion from the rest pose turns the femur about the osim's flexion axis (Z of hip_r's parent
// frame) through the joint centre. That axis lies 6.99° from the URDF scene's flexion axis (Z of
// the pelvis frame of models/hip/landmarks/hip_frame.json).
TEST_F(LhdlOsim, FlexionTurnsTheFemurAboutTheHipFrameZ) {
  const FileJoint hip = readFileJoint("femur_r");
  const Eigen::Vector3d axis = hip.X_PF.linear().col(2);  // pelvis = ground = CT at rest
  const Eigen::Vector3d centre = hip.X_PF.translation();
  Eigen::VectorXd q = skeleton_->solveBodiesAtGround();
  const Eigen::Isometry3d rest_femur = [&] {
    skeleton_->setCoordinateValues(q);
    return pose("femur_r");
  }();
  q[skeleton_->findCoordinateIndex("hip_flexion_r")] += 80 * kDeg;
  skeleton_->setCoordinateValues(q);
  Eigen::Isometry3d turn = Eigen::Isometry3d::Identity();
  turn.linear() = Eigen::AngleAxisd(80 * kDeg, axis).toRotationMatrix();
  turn.translation() = centre - turn.linear() * centre;
  EXPECT_LT(femurPlacementError(pose("femur_r"), turn * rest_femur), 1e-6);

  const Eigen::Vector3d urdf_axis = Eigen::Vector3d(-0.9924778435393229, 0.11879490607095865, 0.029588855590025775).normalized();
  const double angle_deg = std::acos(std::min(1.0, axis.dot(urdf_axis))) / kDeg;
  std::printf("flexion axes, URDF scene against the subject's osim: %.3f deg apart\n", angle_deg);
  EXPECT_NEAR(angle_deg, 6.99, 0.01);
}

TEST_F(LhdlOsim, FromFileDispatchesOnTheExtension) {
  EXPECT_EQ(Skeleton::fromFile(kOsim).getBodyNames().size(), 3u);
  EXPECT_EQ(Skeleton::fromFile(kHipDir + "/hip_r.urdf").getBodyNames().front(), "pelvis");
  expectModelError([] { Skeleton::fromFile("model.xml"); }, {"model.xml", "'.xml'", "expected .urdf or .osim"});
}

// ---------------------------------------------------------------- 4.x layout

TEST(OsimV4, FramesPinWeldAndCustomJointFollowTheFile) {
  Skeleton s = Skeleton::fromOsim(kData + "three_bodies_v4.osim");
  EXPECT_EQ(s.getBodyNames(), (std::vector<std::string>{"ground", "pelvis", "thigh", "shank"}));
  EXPECT_EQ(s.getCoordinateNames(), (std::vector<std::string>{"hip_flexion", "knee_angle", "knee_slide"}));
  EXPECT_EQ(s.getCoordinates()[2].motion, CoordinateMotion::kTranslational);
  EXPECT_DOUBLE_EQ(s.getCoordinates()[2].default_value, 4.0);  // 0.004 m
  EXPECT_DOUBLE_EQ(s.getCoordinates()[2].range_max, 20.0);
  // Starts at the default values.
  EXPECT_TRUE(s.getCoordinateValues().isApprox(Eigen::Vector3d(0.25, -0.3, 4.0)));
  const auto& mesh = s.getBodyMeshes(s.findBodyIndex("thigh"));
  ASSERT_EQ(mesh.size(), 1u);  // the sphere is not a mesh
  EXPECT_EQ(mesh[0].path, kHipDir + "/osim/geometry/LHDL_femur_r.vtp");
  EXPECT_TRUE(mesh[0].scale_to_mm.isApprox(Eigen::Vector3d::Ones(), 1e-15));

  const double hip = 0.6, knee = -0.9, slide_mm = 7.0;
  s.setCoordinateValues(Eigen::Vector3d(hip, knee, slide_mm));
  const Eigen::Isometry3d X_G_pelvis = poseOf({0, 0.9, 0}, {0, 0.3, 0});
  const Eigen::Isometry3d X_pelvis_F = poseOf({0.1, -0.05, 0.07}, {0.1, 0.2, 0.3}) * poseOf({0, 0, 0.02}, {0, 0, -0.4});
  const Eigen::Isometry3d X_thigh_M = poseOf({0, 0.2, 0}, {-0.2, 0, 0.1});
  Eigen::Isometry3d pin = Eigen::Isometry3d::Identity();
  pin.linear() = Eigen::AngleAxisd(hip, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  const Eigen::Isometry3d X_G_thigh = X_G_pelvis * X_pelvis_F * pin * X_thigh_M.inverse();
  Eigen::Isometry3d knee_FM = Eigen::Isometry3d::Identity();
  knee_FM.linear() = (Eigen::AngleAxisd(0.5 * (knee + 0.05), Eigen::Vector3d::UnitZ()) *
                      Eigen::AngleAxisd(0.1, Eigen::Vector3d::UnitX()))
                         .toRotationMatrix();
  knee_FM.translation() = Eigen::Vector3d(10.0, 2.0 * slide_mm - 400.0, 0.0);
  const Eigen::Isometry3d X_G_shank = X_G_thigh * poseOf({0, -0.4, 0}, {0, 0, 0}) * knee_FM;
  EXPECT_TRUE(s.getBodyTransform(1).isApprox(X_G_pelvis, 1e-12));
  EXPECT_LT(femurPlacementError(s.getBodyTransform(2), X_G_thigh), 1e-9);
  EXPECT_LT(femurPlacementError(s.getBodyTransform(3), X_G_shank), 1e-9);

  // Every body at ground: the weld cannot (it holds the pelvis 900 mm up and turned).
  expectModelError([&] { s.solveBodiesAtGround(); },
                   {"three_bodies_v4.osim", "joint 'ground_pelvis' cannot put body 'pelvis' there", "900 mm"});
}

// 3.x geometry: VisibleObject transform and scale compose with the DisplayGeometry's; Windows
// separators in the file name; a 3.x CustomJoint with one rotation.
TEST(OsimV3, GeometryTransformsAndScalesCompose) {
  const Skeleton s = Skeleton::fromOsim(kData + "geometry_transform.osim");
  const auto& meshes = s.getBodyMeshes(s.findBodyIndex("tibia"));
  ASSERT_EQ(meshes.size(), 1u);
  EXPECT_EQ(meshes[0].path, kHipDir + "/osim/geometry/LHDL_femur_r.vtp");
  const Eigen::Isometry3d expected = poseOf({0.01, 0, 0}, {0.1, 0, 0}) * poseOf({0, 0.02, 0}, {0, 0.2, 0});
  EXPECT_TRUE(meshes[0].X_BM.isApprox(expected, 1e-15));
  EXPECT_TRUE(meshes[0].scale_to_mm.isApprox(Eigen::Vector3d(2, 1, 1), 1e-15));
  EXPECT_EQ(s.getCoordinateNames(), std::vector<std::string>{"knee_angle"});
}

// ---------------------------------------------------------------- refused constructs

TEST(OsimErrors, NegativeMassIsRefusedNamingTheBodyAndLineAndZeroIsMassless) {
  std::ifstream in(kData + "three_bodies_v4.osim");
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  std::string negative = text, zero = text;
  negative.replace(negative.find("<mass>10</mass>"), 15, "<mass>-7</mass>");
  expectModelError([&] { Skeleton::fromOsimText(negative, kData + "negative_mass.osim"); },
                   {kData + "negative_mass.osim, line 14: <mass>: body 'pelvis': mass -7 kg: expected a finite mass from 0"});
  zero.replace(zero.find("<mass>10</mass>"), 15, "<mass>0</mass>");
  EXPECT_NO_THROW(Skeleton::fromOsimText(zero, kData + "zero_mass.osim"));
}

TEST(OsimErrors, MoreBodiesThanASkeletonMayHaveAreRefused) {
  // A chain of 50 000 welded bodies ran for minutes; a skeleton has tens.
  std::string bodies, joints;
  for (int i = 0; i < 1001; ++i) {
    const std::string n = std::to_string(i);
    bodies += "<Body name=\"b" + n + "\"><mass>1</mass></Body>\n";
    joints += "<WeldJoint name=\"j" + n + "\"><socket_parent_frame>" + (i ? "/bodyset/b" + std::to_string(i - 1) : "/ground") +
              "</socket_parent_frame><socket_child_frame>/bodyset/b" + n + "</socket_child_frame></WeldJoint>\n";
  }
  const std::string text = "<OpenSimDocument Version=\"40000\"><Model name=\"m\"><Ground name=\"ground\"/>\n"
                           "<BodySet name=\"bodyset\"><objects>\n" + bodies + "</objects></BodySet>\n"
                           "<JointSet name=\"jointset\"><objects>\n" + joints + "</objects></JointSet></Model></OpenSimDocument>";
  expectModelError([&] { Skeleton::fromOsimText(text, "chain.osim"); },
                   {"chain.osim, line 1002: <Body name=\"b999\">: more than the 1000 bodies a skeleton may have"});
}

TEST(OsimErrors, RefusedConstructsNameTheElementAndLine) {
  const auto path = [](const char* file) { return kData + file; };
  expectModelError([&] { Skeleton::fromOsim(path("simm_spline.osim")); },
                   {path("simm_spline.osim") + ", line 36: <SimmSpline>: in <TransformAxis name=\"translation1\">: function "
                                               "type SimmSpline is not supported (expected LinearFunction or Constant, "
                                               "also inside a MultiplierFunction)"});
  expectModelError([&] { Skeleton::fromOsim(path("multiplier_spline.osim")); },
                   {path("multiplier_spline.osim") + ", line 37: <SimmSpline>: in <TransformAxis name=\"translation1\">: a "
                                                     "MultiplierFunction of a SimmSpline couples its coordinate non-linearly"});
  expectModelError([&] { Skeleton::fromOsim(path("coupled_two_axes.osim")); },
                   {path("coupled_two_axes.osim") + ", line 32: <TransformAxis name=\"translation1\">: coordinate "
                                                    "'knee_angle' also drives TransformAxis rotation1 (line 23): a coordinate "
                                                    "coupled into two transform axes is not supported"});
  expectModelError([&] { Skeleton::fromOsim(path("constraint.osim")); },
                   {path("constraint.osim") + ", line 49: <CoordinateCouplerConstraint name=\"patella_coupler\">: "
                                              "constraints are not supported"});
  expectModelError([&] { Skeleton::fromOsim(path("unknown_joint.osim")); },
                   {path("unknown_joint.osim") + ", line 13: <BallJoint name=\"knee\">: joint type BallJoint is not "
                                                 "supported (expected CustomJoint, PinJoint or WeldJoint)"});
  expectModelError([&] { Skeleton::fromOsim(path("two_coordinates.osim")); },
                   {path("two_coordinates.osim") + ", line 24: <TransformAxis name=\"rotation1\">: is driven by 2 "
                                                   "coordinates; at most one per axis is supported"});
  expectModelError([&] { Skeleton::fromOsim(path("missing_geometry.osim")); },
                   {path("missing_geometry.osim") + ", line 15: <DisplayGeometry>: geometry file "
                                                    "'.\\geometry\\tibia_missing.vtp' not found (looked for ",
                    "/geometry/tibia_missing.vtp"});
  // Found by fuzz_osim: the pelvis of three_bodies_v4.osim with Iyz = 1 (Ixx = Iyy = Izz = 0.1),
  // principal moments -0.9, 0.1, 1.1; Simbody threw an exception of its own while building.
  expectModelError([&] { Skeleton::fromOsim(path("fuzz_negative_principal_inertia.osim")); },
                   {path("fuzz_negative_principal_inertia.osim") + ", line 12: <Body name=\"pelvis\">: body 'pelvis': "
                                                                   "inertia about the mass centre has principal moments -0.9"});
  // Found by fuzz_osim: a geometry file name longer than the system allows made the file-system
  // query throw std::filesystem::filesystem_error ("File name too long") out of the reader.
  expectModelError([&] { Skeleton::fromOsim(path("fuzz_geometry_name_too_long.osim")); },
                   {path("fuzz_geometry_name_too_long.osim") + ", line 16: <DisplayGeometry>: geometry file '",
                    "not found (looked for "});
  expectModelError([] { Skeleton::fromOsim("/nonexistent/model.osim"); },
                   {"OpenSim model /nonexistent/model.osim: cannot open it: no such file"});
  test::TempFile broken("broken.osim");
  broken.write("<?xml version=\"1.0\"?>\n<OpenSimDocument Version=\"30000\">\n<Model name=\"m\">\n<BodySet>\n");
  expectModelError([&] { Skeleton::fromOsim(broken.path()); }, {broken.path() + ", line ", "not well-formed XML"});
}

}  // namespace
}  // namespace rbfmuscle
