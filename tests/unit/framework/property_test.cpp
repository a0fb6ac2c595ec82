// SPDX-License-Identifier: Apache-2.0
#include "throws_with.h"
#include "toy_components.h"

#include <gtest/gtest.h>

#include <cmath>

namespace rbfmuscle {
namespace {

using test::throwsWith;
using test::ToyComponent;

TEST(Property, DefaultsAreSetAndListedInDeclarationOrder) {
  ToyComponent toy;
  EXPECT_EQ(toy.stiffness.get(), 2.5);
  EXPECT_EQ(toy.count.get(), 3);
  EXPECT_TRUE(toy.enabled.get());
  EXPECT_EQ(toy.offset_mm.get(), Eigen::Vector3d(1, 2, 3));
  EXPECT_FALSE(toy.label.hasValue());
  EXPECT_TRUE(toy.label.isRequired());
  ASSERT_EQ(toy.getProperties().size(), 5u);
  EXPECT_EQ(toy.getProperties()[0]->getName(), "stiffness");
  EXPECT_EQ(toy.getProperties()[4]->getName(), "offset_mm");
  EXPECT_EQ(toy.findProperty("count"), &toy.count);
  EXPECT_EQ(toy.findProperty("nope"), nullptr);
  EXPECT_EQ(toy.stiffness.formatDefault(), "2.5");
  EXPECT_EQ(toy.offset_mm.formatDefault(), "1 2 3");
  EXPECT_EQ(toy.stiffness.formatRange(), "[0, 10]");
  EXPECT_EQ(toy.enabled.formatRange(), "");
}

TEST(Property, ReadsEachTypeFromText) {
  ToyComponent toy;
  toy.stiffness.read(" 7.25e0\n");
  toy.count.read("42");
  toy.enabled.read("false");
  toy.label.read("  knee  ");
  toy.offset_mm.read("-1.5 0  2e1");
  EXPECT_EQ(toy.stiffness.get(), 7.25);
  EXPECT_EQ(toy.count.get(), 42);
  EXPECT_FALSE(toy.enabled.get());
  EXPECT_EQ(toy.label.get(), "knee");
  EXPECT_EQ(toy.offset_mm.get(), Eigen::Vector3d(-1.5, 0, 20));
  EXPECT_TRUE(toy.stiffness.wasRead());
  EXPECT_NO_THROW(toy.finalizeProperties());
}

TEST(Property, WrongTypedTextNamesExpectationAndText) {
  ToyComponent toy;
  EXPECT_TRUE(throwsWith([&] { toy.stiffness.read("abc"); }, "expected a number, got 'abc'"));
  EXPECT_TRUE(throwsWith([&] { toy.stiffness.read("1.5mm"); }, "got '1.5mm'"));
  EXPECT_TRUE(throwsWith([&] { toy.count.read("2.5"); }, "expected an integer, got '2.5'"));
  EXPECT_TRUE(throwsWith([&] { toy.enabled.read("yes"); }, "expected true or false, got 'yes'"));
  EXPECT_TRUE(throwsWith([&] { toy.offset_mm.read("1 2"); }, "expected three numbers"));
  EXPECT_TRUE(throwsWith([&] { toy.offset_mm.read("1 2 3 4"); }, "got '1 2 3 4'"));
  EXPECT_TRUE(throwsWith([&] { toy.offset_mm.read("1 x 3"); }, "expected three numbers"));
  EXPECT_EQ(toy.stiffness.get(), 2.5) << "a failed read keeps the value";
}

TEST(Property, FinalizeChecksRangeRequiredAndFiniteness) {
  ToyComponent toy;
  toy.setSourceLocation({"model.xml", 12, "<ToyComponent name=\"t\">"});
  EXPECT_TRUE(throwsWith([&] { toy.finalizeProperties(); },
                         "model.xml:12: <ToyComponent name=\"t\">: property 'label' (string) is required"));
  toy.label.read("x");
  toy.stiffness.read("10.5");
  EXPECT_TRUE(throwsWith([&] { toy.finalizeProperties(); },
                         "property 'stiffness': value 10.5 is outside the allowed range [0, 10]"));
  toy.stiffness.read("10");
  EXPECT_NO_THROW(toy.finalizeProperties()) << "range is closed";
  toy.count.read("0");
  EXPECT_TRUE(throwsWith([&] { toy.finalizeProperties(); }, "property 'count': value 0"));
  toy.count.read("1");
  toy.offset_mm.read("nan 0 0");
  EXPECT_TRUE(throwsWith([&] { toy.finalizeProperties(); }, "property 'offset_mm': value nan 0 0 is not finite"));
}

}  // namespace
}  // namespace rbfmuscle
