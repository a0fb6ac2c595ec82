// SPDX-License-Identifier: Apache-2.0
#include "framework/model_document.h"

#include "throws_with.h"

#include <gtest/gtest.h>

namespace rbfmuscle {
namespace {

using test::throwsWith;

ModelDocument parse(const std::string& text) { return parseModelDocument(text, "/m/scene.xml"); }

TEST(ModelDocument, ReadsEveryPart) {
  const ModelDocument doc = parse(
      "<RBFMuscleModel version=\"1\" name=\"hip\">\n"
      "  <skeleton file=\"hip_r.urdf\"/>\n"
      "  <plugin file=\"libp.so\"/>\n"
      "  <motion file=\"motions/flex.mot\"/>\n"
      "  <components>\n"
      "    <ToyComponent name=\"a\">\n"
      "      <stiffness> 3 </stiffness>\n"
      "      <socket_body>femur_r</socket_body>\n"
      "    </ToyComponent>\n"
      "    <ToyReader name=\"b\"><socket_bodies> pelvis\n femur_r </socket_bodies></ToyReader>\n"
      "  </components>\n"
      "  <reporter outputs=\"a.* b.twice_sum\"/>\n"
      "</RBFMuscleModel>\n");
  EXPECT_EQ(doc.name, "hip");
  EXPECT_EQ(doc.version, 1);
  EXPECT_EQ(doc.directory, "/m");
  EXPECT_EQ(doc.skeleton.path, "/m/hip_r.urdf");
  EXPECT_EQ(doc.motion.path, "/m/motions/flex.mot");
  EXPECT_EQ(doc.motion.location.line, 4);
  ASSERT_EQ(doc.plugins.size(), 1u);
  EXPECT_EQ(doc.plugins[0].path, "libp.so") << "plugins are searched, not resolved";
  ASSERT_EQ(doc.components.size(), 2u);
  const ComponentSpec& a = doc.components[0];
  EXPECT_EQ(a.class_name, "ToyComponent");
  EXPECT_EQ(a.name, "a");
  EXPECT_EQ(a.location.line, 6);
  ASSERT_EQ(a.properties.size(), 1u);
  EXPECT_EQ(a.properties[0].name, "stiffness");
  EXPECT_EQ(a.properties[0].text, " 3 ");
  EXPECT_EQ(a.properties[0].location.line, 7);
  ASSERT_EQ(a.sockets.size(), 1u);
  EXPECT_EQ(a.sockets[0].name, "body");
  EXPECT_EQ(a.sockets[0].target, "femur_r");
  EXPECT_EQ(doc.components[1].sockets[0].target, "pelvis femur_r");
  EXPECT_EQ(doc.reporter_patterns, (std::vector<std::string>{"a.*", "b.twice_sum"}));
}

TEST(ModelDocument, DefaultsNameToFileStemAndReportsEverything) {
  const ModelDocument doc = parse(
      "<RBFMuscleModel version=\"1\"><skeleton file=\"/abs/s.urdf\"/><motion file=\"m.mot\"/>"
      "</RBFMuscleModel>");
  EXPECT_EQ(doc.name, "scene");
  EXPECT_EQ(doc.skeleton.path, "/abs/s.urdf");
  EXPECT_TRUE(doc.components.empty());
  EXPECT_EQ(doc.reporter_patterns, std::vector<std::string>{"*"});
  EXPECT_EQ(doc.skeleton_rest_pose, RestPose::kDefault);
}

// An OpenSim skeleton, and the rest pose the skeleton element may set.
TEST(ModelDocument, SkeletonMayBeAnOsimModelWithItsRestPose) {
  ModelDocument doc = parse(
      "<RBFMuscleModel version=\"1\"><skeleton file=\"osim/LHDL_hip_r.osim\" rest_pose=\"bodies_at_ground\"/>"
      "<motion file=\"m.mot\"/></RBFMuscleModel>");
  EXPECT_EQ(doc.skeleton.path, "/m/osim/LHDL_hip_r.osim");
  EXPECT_EQ(doc.skeleton_rest_pose, RestPose::kBodiesAtGround);
  doc = parse("<RBFMuscleModel version=\"1\"><skeleton file=\"s.urdf\" rest_pose=\"default\"/><motion file=\"m.mot\"/>"
              "</RBFMuscleModel>");
  EXPECT_EQ(doc.skeleton_rest_pose, RestPose::kDefault);
  EXPECT_TRUE(throwsWith([] { parse("<RBFMuscleModel version=\"1\">\n<skeleton file=\"s.osim\" rest_pose=\"ct\"/>"
                                    "<motion file=\"m.mot\"/></RBFMuscleModel>"); },
                         "/m/scene.xml:2: <skeleton>: rest_pose 'ct' (expected default or bodies_at_ground)"));
  EXPECT_TRUE(throwsWith([] { parse("<RBFMuscleModel version=\"1\">\n<skeleton file=\"s.osim\"/>\n"
                                    "<motion file=\"m.mot\" rest_pose=\"default\"/></RBFMuscleModel>"); },
                         "/m/scene.xml:3: <motion>: unknown attribute 'rest_pose'"));
}

const char* kHead = "<RBFMuscleModel version=\"1\">\n<skeleton file=\"s.urdf\"/>\n<motion file=\"m.mot\"/>\n";

TEST(ModelDocument, ErrorsNameFileLineAndElement) {
  EXPECT_TRUE(throwsWith([] { parse("<RBFMuscleModel version=\"1\">\n<skeleton file=\"s\"/>\n<oops/></RBFMuscleModel>"); },
                         "/m/scene.xml:3: <oops>: unknown element (expected skeleton, plugin"));
  EXPECT_TRUE(throwsWith([] { parse("<RBFMuscleModel>\n</RBFMuscleModel>"); },
                         "/m/scene.xml:1: <RBFMuscleModel>: missing attribute 'version'"));
  EXPECT_TRUE(throwsWith([] { parse("<RBFMuscleModel version=\"2\"/>"); },
                         "unsupported version '2' (this build reads version 1)"));
  EXPECT_TRUE(throwsWith([] { parse("<Model version=\"1\"/>"); }, "expected root element <RBFMuscleModel>"));
  EXPECT_TRUE(throwsWith([] { parse("<RBFMuscleModel version=\"1\">\n\n<skeleton file=\"s\">\n"); },
                         "/m/scene.xml:"));
  EXPECT_TRUE(throwsWith([] { parse("<RBFMuscleModel version=\"1\">\n\n<skeleton file=\"s\">\n"); },
                         "XML syntax error"));
  EXPECT_TRUE(throwsWith([] { parse("<RBFMuscleModel version=\"1\">\n<motion file=\"m\"/></RBFMuscleModel>"); },
                         "missing <skeleton file=\"...\"/>"));
  EXPECT_TRUE(throwsWith([] { parse(std::string(kHead) + "<skeleton file=\"t.urdf\"/></RBFMuscleModel>"); },
                         "/m/scene.xml:4: <skeleton>: given twice"));
  EXPECT_TRUE(throwsWith([] { parse(std::string(kHead) + "<plugin path=\"x\"/></RBFMuscleModel>"); },
                         "/m/scene.xml:4: <plugin>: unknown attribute 'path' (expected: file)"));
  EXPECT_TRUE(throwsWith([] { parse(std::string(kHead) + "<plugin/></RBFMuscleModel>"); },
                         "/m/scene.xml:4: <plugin>: missing attribute 'file'"));
}

TEST(ModelDocument, ComponentElementErrors) {
  const std::string head = std::string(kHead) + "<components>\n";
  EXPECT_TRUE(throwsWith([&] { parse(head + "<ToyComponent/></components></RBFMuscleModel>"); },
                         "/m/scene.xml:5: <ToyComponent>: missing attribute 'name'"));
  EXPECT_TRUE(throwsWith([&] { parse(head + "<ToyComponent name=\"a.b\"/></components></RBFMuscleModel>"); },
                         "may not contain '.'"));
  EXPECT_TRUE(throwsWith(
      [&] { parse(head + "<A name=\"x\"/>\n<B name=\"x\"/></components></RBFMuscleModel>"); },
      "/m/scene.xml:6: <B name=\"x\">: duplicate component name 'x'"));
  EXPECT_TRUE(throwsWith(
      [&] { parse(head + "<A name=\"x\">\n<k>1</k>\n<k>2</k></A></components></RBFMuscleModel>"); },
      "/m/scene.xml:7: <k> in <A name=\"x\">: given twice"));
  EXPECT_TRUE(throwsWith(
      [&] { parse(head + "<A name=\"x\">\n<socket_k><v/></socket_k></A></components></RBFMuscleModel>"); },
      "/m/scene.xml:6: <socket_k> in <A name=\"x\">: expected text only, found child element <v>"));
  EXPECT_TRUE(throwsWith(
      [&] { parse(head + "<A name=\"x\">\n<k><v>1</v><v>2</v></k></A></components></RBFMuscleModel>"); },
      "/m/scene.xml:6: <v> in <k>: given twice"));
}

TEST(ModelDocument, ElementsHoldingElementsAreSubcomponents) {
  const ModelDocument doc = parse(std::string(kHead) +
                                  "<components>\n<A name=\"x\"><p>1</p>\n<filter>\n<order>2</order>\n"
                                  "<band><low>3</low></band></filter></A></components></RBFMuscleModel>");
  ASSERT_EQ(doc.components.size(), 1u);
  const ComponentSpec& a = doc.components[0];
  ASSERT_EQ(a.properties.size(), 1u);
  ASSERT_EQ(a.subcomponents.size(), 1u);
  const ComponentSpec& filter = a.subcomponents[0];
  EXPECT_EQ(filter.name, "filter");
  EXPECT_EQ(filter.location.line, 6);
  ASSERT_EQ(filter.properties.size(), 1u);
  EXPECT_EQ(filter.properties[0].name, "order");
  EXPECT_EQ(filter.properties[0].text, "2");
  EXPECT_EQ(filter.properties[0].location.line, 7);
  ASSERT_EQ(filter.subcomponents.size(), 1u);
  EXPECT_EQ(filter.subcomponents[0].properties[0].text, "3");
}

TEST(ModelDocument, ModelPathThatIsADeviceOrDirectoryIsRefusedWithoutReading) {
  // `rbfmuscle run /dev/zero` used to read forever.
  EXPECT_TRUE(test::throwsWith([] { readModelDocument("/dev/zero"); },
                               "model file /dev/zero: is a character device, not a regular file (expected a model XML file)"));
  EXPECT_TRUE(test::throwsWith([] { readModelDocument(RBFMUSCLE_SOURCE_DIR); }, "is a directory, not a regular file"));
  EXPECT_TRUE(test::throwsWith([] { readModelDocument("/nonexistent/scene.xml"); },
                               "model file /nonexistent/scene.xml: cannot open it"));
}

}  // namespace
}  // namespace rbfmuscle
