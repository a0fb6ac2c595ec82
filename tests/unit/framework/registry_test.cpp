// SPDX-License-Identifier: Apache-2.0
#include "framework/model.h"
#include "framework/registry.h"

#include "throws_with.h"
#include "toy_components.h"

#include <gtest/gtest.h>

namespace rbfmuscle {
namespace {

using test::throwsWith;

Registry toyRegistry() {
  Registry registry;
  test::registerToyTypes(registry);
  return registry;
}

ModelDocument document(const std::string& components) {
  return parseModelDocument("<RBFMuscleModel version=\"1\">\n<skeleton file=\"s.urdf\"/>\n"
                            "<motion file=\"m.mot\"/>\n<components>\n" +
                                components + "</components></RBFMuscleModel>",
                            "/m/scene.xml");
}

TEST(Registry, CreatesRegisteredTypesAndListsThemForUnknownOnes) {
  const Registry registry = toyRegistry();
  EXPECT_EQ(registry.listTypeNames(), "ToyComponent, ToyReader");
  const auto toy = registry.create("ToyComponent");
  ASSERT_NE(dynamic_cast<test::ToyComponent*>(toy.get()), nullptr);
  EXPECT_EQ(toy->getClassName(), "ToyComponent");
  EXPECT_TRUE(throwsWith([&] { registry.create("Muscle"); },
                         "unknown component class 'Muscle' (registered: ToyComponent, ToyReader)"));
  EXPECT_TRUE(throwsWith([] { Registry().create("Muscle"); }, "registered: none"));
}

TEST(Registry, RejectsDuplicateAndInvalidNames) {
  Registry registry = toyRegistry();
  registry.setCurrentOrigin("/lib/libtwo.so");
  EXPECT_TRUE(throwsWith([&] { registry.addType<test::ToyReader>("ToyReader", ""); },
                         "plugin /lib/libtwo.so: component class 'ToyReader' is already registered"));
  EXPECT_TRUE(throwsWith([&] { registry.addType<test::ToyReader>("Toy Reader", ""); },
                         "is not a valid XML element name"));
}

TEST(Registry, DescribesPropertiesSocketsAndOutputs) {
  const Registry registry = toyRegistry();
  const std::string text = registry.describeType(*registry.findType("ToyComponent"));
  EXPECT_NE(text.find("stiffness (double, default 2.5, range [0, 10]): toy stiffness (N/mm)"), std::string::npos) << text;
  EXPECT_NE(text.find("label (string, required): required label"), std::string::npos) << text;
  EXPECT_NE(text.find("socket_body (body): body read each frame"), std::string::npos) << text;
  EXPECT_NE(text.find("values (vector of double, mm): count values"), std::string::npos) << text;
  const std::string reader = registry.describeType(*registry.findType("ToyReader"));
  EXPECT_NE(reader.find("socket_source (component ToyComponent)"), std::string::npos) << reader;
  EXPECT_NE(reader.find("socket_bodies (list of bodies)"), std::string::npos) << reader;
}

TEST(CreateComponents, AppliesPropertiesAndSocketTargets) {
  const auto components = createComponents(
      document("<ToyComponent name=\"t\"><label>x</label><count>5</count>"
               "<socket_body>femur_r</socket_body></ToyComponent>\n"),
      toyRegistry());
  ASSERT_EQ(components.size(), 1u);
  const auto& toy = dynamic_cast<const test::ToyComponent&>(*components[0]);
  EXPECT_EQ(toy.getName(), "t");
  EXPECT_EQ(toy.count.get(), 5);
  EXPECT_EQ(toy.stiffness.get(), 2.5);
  EXPECT_EQ(toy.body.getTargetName(), "femur_r");
  EXPECT_EQ(toy.getSourceLocation().line, 5);
}

TEST(CreateComponents, ErrorsNameFileLineElementAndCulprit) {
  const Registry registry = toyRegistry();
  EXPECT_TRUE(throwsWith([&] { createComponents(document("<Muscle name=\"m\"/>\n"), registry); },
                         "/m/scene.xml:5: <Muscle name=\"m\">: unknown component class 'Muscle' "
                         "(registered: ToyComponent, ToyReader)"));
  EXPECT_TRUE(throwsWith(
      [&] { createComponents(document("<ToyComponent name=\"t\">\n<label>x</label>\n<stiffnes>1</stiffnes></ToyComponent>"), registry); },
      "/m/scene.xml:7: <stiffnes> in <ToyComponent name=\"t\">: unknown property 'stiffnes' "
      "(ToyComponent has properties: stiffness, count, enabled, label, offset_mm; sockets: socket_body)"));
  EXPECT_TRUE(throwsWith(
      [&] { createComponents(document("<ToyComponent name=\"t\">\n<stiffness>abc</stiffness></ToyComponent>"), registry); },
      "/m/scene.xml:6: <stiffness> in <ToyComponent name=\"t\">: double property: expected a number, got 'abc'"));
  EXPECT_TRUE(throwsWith(
      [&] { createComponents(document("<ToyComponent name=\"t\">\n<label>x</label><stiffness>11</stiffness></ToyComponent>"), registry); },
      "/m/scene.xml:5: <ToyComponent name=\"t\">: property 'stiffness': value 11 is outside the allowed range [0, 10]"));
  EXPECT_TRUE(throwsWith(
      [&] { createComponents(document("<ToyComponent name=\"t\"/>"), registry); },
      "/m/scene.xml:5: <ToyComponent name=\"t\">: property 'label' (string) is required"));
  EXPECT_TRUE(throwsWith(
      [&] { createComponents(document("<ToyComponent name=\"t\">\n<socket_bone>x</socket_bone></ToyComponent>"), registry); },
      "/m/scene.xml:6: <socket_bone> in <ToyComponent name=\"t\">: unknown socket 'socket_bone' "
      "(ToyComponent has sockets: socket_body)"));
}

TEST(CreateComponents, SubcomponentPropertiesComeFromTheirElement) {
  Registry registry;
  registry.addType<test::ToyFiltered>("ToyFiltered", "toy with a subcomponent");
  const auto components = createComponents(
      document("<ToyFiltered name=\"f\"><gain>2</gain>\n<filter><order>4</order></filter></ToyFiltered>\n"
               "<ToyFiltered name=\"g\"/>\n"),
      registry);
  const auto& f = dynamic_cast<const test::ToyFiltered&>(*components[0]);
  EXPECT_EQ(f.gain.get(), 2.0);
  EXPECT_EQ(f.filter.order.get(), 4);
  EXPECT_EQ(f.filter.cutoff_hz.get(), 6.0);
  EXPECT_EQ(f.filter.getSourceLocation().line, 6);
  ASSERT_EQ(f.getSubcomponents().size(), 1u);
  EXPECT_EQ(f.findSubcomponent("filter"), &f.filter);
  EXPECT_EQ(dynamic_cast<const test::ToyFiltered&>(*components[1]).filter.order.get(), 2);  // defaults

  EXPECT_TRUE(throwsWith(
      [&] { createComponents(document("<ToyFiltered name=\"f\">\n<filter><order>5</order></filter></ToyFiltered>"), registry); },
      "/m/scene.xml:6: <filter> in <ToyFiltered name=\"f\">: property 'order': value 5 is outside the allowed range [1, 4]"));
  EXPECT_TRUE(throwsWith(
      [&] { createComponents(document("<ToyFiltered name=\"f\">\n<filter><oder>3</oder></filter></ToyFiltered>"), registry); },
      "/m/scene.xml:6: <oder> in <filter>: unknown property 'oder' (filter has properties: order, cutoff_hz"));
  EXPECT_TRUE(throwsWith(
      [&] { createComponents(document("<ToyFiltered name=\"f\">\n<filtre><order>3</order></filtre></ToyFiltered>"), registry); },
      "/m/scene.xml:6: <filtre> in <ToyFiltered name=\"f\">: unknown subcomponent <filtre> (ToyFiltered has "
      "subcomponents: <filter>; properties: gain)"));
  EXPECT_TRUE(throwsWith(
      [&] { createComponents(document("<ToyFiltered name=\"f\">\n<filter>3</filter></ToyFiltered>"), registry); },
      "'filter' is a subcomponent: give its properties inside, as <filter><PROPERTY>value</PROPERTY></filter> "
      "(its properties: order, cutoff_hz)"));
  const std::string described = registry.describeType(*registry.findType("ToyFiltered"));
  EXPECT_NE(described.find("  <filter>: toy low-pass filter\n    filter/order (int, default 2, range [1, 4]): filter order"),
            std::string::npos)
      << described;
}

TEST(ConnectSockets, ResolvesBodiesAndComponentsByNameOrListsCandidates) {
  const Registry registry = toyRegistry();
  auto components = createComponents(
      document("<ToyComponent name=\"t\"><label>x</label><socket_body>femur_r</socket_body></ToyComponent>\n"
               "<ToyReader name=\"r\"><socket_source>t</socket_source>"
               "<socket_bodies>femur_r pelvis</socket_bodies></ToyReader>\n"
               "<ToyReader name=\"bad\"><socket_source>r</socket_source>"
               "<socket_bodies>pelvis</socket_bodies></ToyReader>\n"
               "<ToyReader name=\"ghost\"><socket_source>nobody</socket_source>"
               "<socket_bodies>pelvis</socket_bodies></ToyReader>\n"
               "<ToyComponent name=\"tibia\"><label>x</label><socket_body>tibia_r</socket_body></ToyComponent>\n"
               "<ToyComponent name=\"unset\"><label>x</label></ToyComponent>\n"),
      registry);
  std::vector<Component*> pointers;
  for (const auto& c : components) pointers.push_back(c.get());
  const ConnectionTargets targets({"pelvis", "femur_r"}, pointers);
  components[0]->connectSockets(targets);
  components[1]->connectSockets(targets);
  const auto& toy = dynamic_cast<const test::ToyComponent&>(*components[0]);
  const auto& reader = dynamic_cast<const test::ToyReader&>(*components[1]);
  EXPECT_EQ(toy.body.getBodyIndex(), 1);
  EXPECT_EQ(&reader.source.get(), &toy);
  EXPECT_EQ(reader.bodies.getBodyIndices(), (std::vector<int>{1, 0}));
  EXPECT_TRUE(throwsWith([&] { components[2]->connectSockets(targets); },
                         "/m/scene.xml:7: <ToyReader name=\"bad\">: socket 'source' names component "
                         "'r', which is not a ToyComponent"));
  EXPECT_TRUE(throwsWith([&] { components[3]->connectSockets(targets); },
                         "socket 'source' names unknown component 'nobody' (components: t, r, bad, "
                         "ghost, tibia, unset)"));
  EXPECT_TRUE(throwsWith([&] { components[4]->connectSockets(targets); },
                         "/m/scene.xml:9: <ToyComponent name=\"tibia\">: socket 'body' names unknown "
                         "body 'tibia_r' (skeleton bodies: pelvis, femur_r)"));
  EXPECT_TRUE(throwsWith([&] { components[5]->connectSockets(targets); },
                         "socket 'body' is not connected: expected a <socket_body> element"));
}

}  // namespace
}  // namespace rbfmuscle
