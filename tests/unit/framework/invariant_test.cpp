// SPDX-License-Identifier: Apache-2.0
/// InvariantChecker: a component's declared promises about its outputs, checked after each
/// frame; a break warns once per invariant with the frame, or throws under strict.
#include "framework/invariant.h"

#include "framework/component.h"
#include "throws_with.h"

#include <gtest/gtest.h>

#include <Eigen/Core>

#include <cmath>
#include <limits>
#include <memory>
#include <string>
#include <vector>

namespace rbfmuscle::test {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();

/// A component whose outputs the test sets directly, with invariants on them.
class Promiser final : public Component {
 public:
  double ratio = 1.0;
  double depth = kNaN;
  Eigen::VectorXd lengths = Eigen::VectorXd::Constant(3, 10.0);
  Output ratio_output{this, "ratio", "1", "kept near 1", [this] { return ratio; }};
  Output depth_output{this, "depth_mm", "mm", "computed on demand", [this] { return depth; }};
  VectorOutput lengths_output{this, "lengths_mm", "mm", "positive",
                              [this]() -> const Eigen::VectorXd& { return lengths; }};

  Promiser() {
    setName("m");
    setClassName("Promiser");
    setSourceLocation(SourceLocation{"model.xml", 7});
    declareInvariant({"ratio", 0.999, 1.001, "ratio near 1"});
    declareInvariant({"depth_mm", -kInf, 0.001, "shallow", true});
    declareInvariant({"lengths_mm", 0.0, kInf, "lengths positive"});
  }
  void declare(Invariant invariant) { declareInvariant(std::move(invariant)); }
  void update(const FrameState&) override {}
};

struct Fixture {
  std::vector<std::unique_ptr<Component>> components;
  Promiser* promiser;
  std::vector<std::string> warnings;
  Fixture() {
    auto p = std::make_unique<Promiser>();
    promiser = p.get();
    components.push_back(std::move(p));
  }
  InvariantChecker checker(bool strict) {
    return InvariantChecker(components, strict, [this](const std::string& line) { warnings.push_back(line); });
  }
};

TEST(Invariant, KeptInvariantsAndAbsentValuesPassSilently) {
  Fixture f;
  InvariantChecker checker = f.checker(false);
  for (int frame = 0; frame < 3; ++frame) checker.check(frame, frame * 0.1);
  f.promiser->depth = 0.0005;  // computed and within its bound
  checker.check(3, 0.3);
  EXPECT_TRUE(f.warnings.empty());
  EXPECT_TRUE(checker.getBreaks().empty());
}

TEST(Invariant, BreakWarnsOnceWithFrameComponentAndBoundsThenCounts) {
  Fixture f;
  InvariantChecker checker = f.checker(false);
  checker.check(0, 0.0);
  f.promiser->ratio = 0.97;
  checker.check(1, 0.1);
  checker.check(2, 0.2);
  f.promiser->ratio = 1.0;
  checker.check(3, 0.3);
  f.promiser->ratio = 1.2;
  checker.check(4, 0.4);
  ASSERT_EQ(f.warnings.size(), 1u);
  const std::string& w = f.warnings[0];
  for (const char* part : {"frame 1", "t = 0.1 s", "m.ratio = 0.97", "ratio near 1", "from 0.999 to 1.001"})
    EXPECT_NE(w.find(part), std::string::npos) << part << " missing in: " << w;
  ASSERT_EQ(checker.getBreaks().size(), 1u);
  EXPECT_EQ(checker.getBreaks()[0].first_frame, 1);
  EXPECT_EQ(checker.getBreaks()[0].frames, 3);
}

TEST(Invariant, NonFiniteValuesBreakEvenWithoutBounds) {
  Fixture f;
  InvariantChecker checker = f.checker(false);
  f.promiser->ratio = kNaN;  // a required value that is missing
  f.promiser->depth = kInf;  // NaN may mean absent, infinity never does
  f.promiser->lengths[2] = kNaN;
  checker.check(5, 0.5);
  ASSERT_EQ(f.warnings.size(), 3u);
  EXPECT_NE(f.warnings[0].find("m.ratio = nan"), std::string::npos) << f.warnings[0];
  EXPECT_NE(f.warnings[1].find("m.depth_mm = inf"), std::string::npos) << f.warnings[1];
  EXPECT_NE(f.warnings[2].find("m.lengths_mm_2 = nan"), std::string::npos) << f.warnings[2];
}

TEST(Invariant, EveryElementOfAVectorOutputIsChecked) {
  Fixture f;
  InvariantChecker checker = f.checker(false);
  f.promiser->lengths[1] = -1.0;
  checker.check(0, 0.0);
  ASSERT_EQ(f.warnings.size(), 1u);
  EXPECT_NE(f.warnings[0].find("m.lengths_mm_1 = -1"), std::string::npos) << f.warnings[0];
  EXPECT_NE(f.warnings[0].find("of at least 0"), std::string::npos) << f.warnings[0];
}

TEST(Invariant, StrictThrowsAtTheComponentsLocationOnTheFirstBreak) {
  Fixture f;
  InvariantChecker checker = f.checker(true);
  checker.check(0, 0.0);
  f.promiser->depth = 0.5;
  EXPECT_TRUE(throwsWith([&] { checker.check(1, 0.1); }, "model.xml:7"));
  EXPECT_TRUE(throwsWith([&] { checker.check(1, 0.1); }, "frame 1 (t = 0.1 s): m.depth_mm = 0.5 breaks its invariant"));
  EXPECT_TRUE(f.warnings.empty());
}

TEST(Invariant, AnInvariantOnAnOutputTheComponentLacksIsRefused) {
  Fixture f;
  f.promiser->declare({"volume", 0.0, 1.0, "volume kept"});
  EXPECT_TRUE(throwsWith([&] { f.checker(false); }, "invariant on output 'volume', which it does not have"));
}

}  // namespace
}  // namespace rbfmuscle::test
