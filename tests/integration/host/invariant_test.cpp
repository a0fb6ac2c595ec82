// SPDX-License-Identifier: Apache-2.0
/// Invariants checked by the run loop, through the host and the test plugin: its
/// BodyOriginReporter promises x_mm >= x_min_mm, and --set raises x_min_mm so that the femur
/// point (whose x falls as the hip flexes) breaks the promise part way through the motion.
/// Without --strict the run warns once and counts; with it, the run fails at that frame.
#include "model/storage_file.h"
#include "support/run_host.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <string>

namespace rbfmuscle {
namespace {

namespace fs = std::filesystem;

const fs::path kModel = fs::path(RBFMUSCLE_SOURCE_DIR) / "tests/integration/host/data/femur_point.xml";
/// femur_knee's x falls from 137 mm at 0° to 94 mm at 80°; 120 mm is crossed near 20°.
const std::string kBreakingSet = " --set femur_knee.x_min_mm=120";

fs::path outputDir(const std::string& name) {
  const fs::path root = fs::path(RBFMUSCLE_BINARY_DIR) / "test_out" / "host_invariant" / name;
  fs::remove_all(root);
  fs::create_directories(root);
  return root / "out";
}

test::HostResult run(const fs::path& out, const std::string& extra, const std::string& name) {
  return test::runHost("run '" + kModel.string() + "' -o '" + out.string() + "' --quiet" + extra, "host_invariant", name);
}

std::size_t count(const std::string& text, const std::string& part) {
  std::size_t n = 0;
  for (std::size_t at = text.find(part); at != std::string::npos; at = text.find(part, at + 1)) ++n;
  return n;
}

/// The first frame whose femur_knee.x_mm is below 120 in an unbroken run, and the number of such
/// frames; `name` keeps the reference runs of tests running in parallel apart.
std::pair<int, int> framesBelow120(const std::string& name) {
  const fs::path out = outputDir(name);
  const test::HostResult r = run(out, "", name);
  EXPECT_EQ(r.exit_code, 0) << r.err;
  const StorageTable t = readStorage((out / "outputs.sto").string());
  const int column = t.findColumn("femur_knee.x_mm");
  EXPECT_GE(column, 0);
  int first = -1, frames = 0;
  for (std::size_t row = 0; row < t.rows.size() && column >= 0; ++row)
    if (t.rows[row][static_cast<std::size_t>(column)] < 120.0) {
      if (first < 0) first = static_cast<int>(row);
      ++frames;
    }
  return {first, frames};
}

TEST(HostInvariant, KeptInvariantsPrintNothingAndSummaryListsNone) {
  const fs::path out = outputDir("kept");
  const test::HostResult r = run(out, " --strict", "kept");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(r.err.find("warning"), std::string::npos) << r.err;
  const std::string summary = test::readText(out / "summary.json");
  EXPECT_NE(summary.find("\"invariants_broken\": [\n  ]"), std::string::npos) << summary;
}

TEST(HostInvariant, ABrokenInvariantWarnsOnceWithFrameAndComponentAndIsCounted) {
  const auto [first, frames] = framesBelow120("reference_warn");
  ASSERT_GT(first, 5) << "the motion should start within the invariant";
  ASSERT_LT(first + frames, 82);
  const fs::path out = outputDir("warn");
  const test::HostResult r = run(out, kBreakingSet, "warn");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(count(r.err, "rbfmuscle: warning: frame "), 1u) << r.err;
  const std::string first_warning = "frame " + std::to_string(first) + " (t = ";
  EXPECT_NE(r.err.find(first_warning), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("femur_knee.x_mm = "), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("P stays at x >= x_min_mm (expected a finite value of at least 120)"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("in " + std::to_string(frames) + " of 81 frames, first at frame " + std::to_string(first)),
            std::string::npos)
      << r.err;
  EXPECT_EQ(r.err.find("femur_origin"), std::string::npos) << "only the broken invariant is named: " << r.err;
  const std::string summary = test::readText(out / "summary.json");
  EXPECT_NE(summary.find("{\"output\": \"femur_knee.x_mm\", \"promise\": \"P stays at x >= x_min_mm\", \"frames\": " +
                         std::to_string(frames) + ", \"first_frame\": " + std::to_string(first) + "}"),
            std::string::npos)
      << summary;
}

TEST(HostInvariant, StrictFailsAtTheFirstBreakingFrameAndLeavesNoOutput) {
  const auto [first, frames] = framesBelow120("reference_strict");
  (void)frames;
  const fs::path out = outputDir("strict");
  const test::HostResult r = run(out, kBreakingSet + " --strict", "strict");
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_EQ(r.err.rfind("rbfmuscle: error: ", 0), 0u) << r.err;
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << "one line: " << r.err;
  for (const std::string& part : {std::string("femur_point.xml:"), std::string("<BodyOriginReporter name=\"femur_knee\">"),
                                  "frame " + std::to_string(first) + " (t = ", std::string("femur_knee.x_mm = "),
                                  std::string("breaks its invariant"), std::string("[--strict]")})
    EXPECT_NE(r.err.find(part), std::string::npos) << "missing '" << part << "' in: " << r.err;
  EXPECT_FALSE(fs::exists(out));
  EXPECT_TRUE(fs::is_empty(out.parent_path())) << "a staging directory was left behind";
}

}  // namespace
}  // namespace rbfmuscle
