// SPDX-License-Identifier: Apache-2.0
#include "framework/frame_geometry.h"
#include "framework/reporter.h"
#include "framework/staged_directory.h"

#include "model/storage_file.h"
#include "throws_with.h"
#include "toy_components.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

namespace rbfmuscle {
namespace {

namespace fs = std::filesystem;
using test::throwsWith;

TEST(MatchesPattern, StarMatchesAnyRun) {
  EXPECT_TRUE(matchesPattern("*", ""));
  EXPECT_TRUE(matchesPattern("*", "a.b"));
  EXPECT_TRUE(matchesPattern("femur.*", "femur.x_mm"));
  EXPECT_FALSE(matchesPattern("femur.*", "femurs.x_mm"));
  EXPECT_TRUE(matchesPattern("*.x_mm", "femur.x_mm"));
  EXPECT_TRUE(matchesPattern("a*b*c", "aXXbYYbc"));
  EXPECT_FALSE(matchesPattern("a*b*c", "aXXbYYbcd"));
  EXPECT_FALSE(matchesPattern("femur.x_mm", "femur.x_mm2"));
}

/// Two finalized, connected toys ("a", "b", each with a 2-vector output) on
/// a fake two-body skeleton.
std::vector<std::unique_ptr<Component>> makeToys() {
  Registry registry;
  test::registerToyTypes(registry);
  std::vector<std::unique_ptr<Component>> components;
  for (const char* name : {"a", "b"}) {
    auto c = registry.create("ToyComponent");
    c->setName(name);
    auto& toy = dynamic_cast<test::ToyComponent&>(*c);
    toy.label.set("x");
    toy.count.set(2);
    toy.body.setTargetName("femur_r");
    components.push_back(std::move(c));
  }
  const ConnectionTargets targets({"pelvis", "femur_r"}, {components[0].get(), components[1].get()});
  for (auto& c : components) {
    c->finalizeProperties();
    c->connectSockets(targets);
  }
  return components;
}

TEST(Reporter, ColumnsAreTimeCoordinatesAndSelectedOutputs) {
  auto toys = makeToys();
  Reporter reporter("scene", {"q0", "q1"}, toys, {"a.*", "b.sum"}, {}, 2);
  EXPECT_EQ(reporter.getTable().column_labels,
            (std::vector<std::string>{"time", "q0", "q1", "a.sum", "a.values_0", "a.values_1", "b.sum"}));

  std::vector<Eigen::Isometry3d> X_GB(2, Eigen::Isometry3d::Identity());
  X_GB[1].translation() << 7, 8, 9;
  const std::vector<char> moved{1, 1};
  const Eigen::VectorXd q = Eigen::Vector2d(0.1, -0.2);
  for (int frame = 0; frame < 2; ++frame) {
    const FrameState state(frame, 0.5 * frame, q, X_GB, moved);
    for (auto& c : toys) c->update(state);
    reporter.record(0.5 * frame, q);
  }
  const StorageTable& table = reporter.getTable();
  ASSERT_EQ(table.rows.size(), 2u);
  EXPECT_EQ(table.rows[1], (std::vector<double>{0.5, 0.1, -0.2, 3.5, 7, 7, 3.5}));
  EXPECT_FALSE(table.in_degrees);
}

TEST(Reporter, PatternMatchingNothingNamesItAndListsOutputs) {
  auto toys = makeToys();
  EXPECT_TRUE(throwsWith(
      [&] { Reporter("s", {}, toys, {"a.*", "c.sum"}, {"m.xml", 9, "<reporter>"}, 1); },
      "m.xml:9: <reporter>: reporter pattern 'c.sum' matches no output (outputs: a.sum, a.values, "
      "b.sum, b.values)"));
  EXPECT_NO_THROW(Reporter("s", {"q"}, {}, {"*"}, {}, 1)) << "'*' may match nothing";
}

TEST(Reporter, WritesStorageThatReadsBack) {
  auto toys = makeToys();
  Reporter reporter("scene", {"q0"}, toys, {"b.values"}, {}, 1);
  std::vector<Eigen::Isometry3d> X_GB(2, Eigen::Isometry3d::Identity());
  X_GB[1].translation().x() = 1.0 / 3.0;
  const std::vector<char> moved{1, 1};
  const Eigen::VectorXd q = Eigen::VectorXd::Constant(1, 0.25);
  for (auto& c : toys) c->update(FrameState(0, 0.0, q, X_GB, moved));
  reporter.record(0.0, q);
  const fs::path dir = fs::path(RBFMUSCLE_BINARY_DIR) / "test_out" / "framework_reporter";
  fs::remove_all(dir);
  fs::create_directories(dir);
  reporter.write(dir.string());
  const StorageTable back = readStorage((dir / "outputs.sto").string());
  EXPECT_EQ(back.column_labels, (std::vector<std::string>{"time", "q0", "b.values_0", "b.values_1"}));
  ASSERT_EQ(back.rows.size(), 1u);
  EXPECT_EQ(back.rows[0][2], 1.0 / 3.0);
  EXPECT_TRUE(fs::exists(dir / "outputs.csv"));
}

TEST(StagedDirectory, NothingIsLeftWithoutCommitAndCommitReplacesEarlierOutput) {
  const fs::path root = fs::path(RBFMUSCLE_BINARY_DIR) / "test_out" / "framework_staged";
  fs::remove_all(root);
  const fs::path out = root / "nested" / "out";
  {
    StagedDirectory staged(out.string());
    std::ofstream(fs::path(staged.getStagingPath()) / "outputs.sto") << "half";
    EXPECT_TRUE(fs::exists(staged.getStagingPath()));
  }
  EXPECT_FALSE(fs::exists(out)) << "no commit: OUTDIR not created";
  EXPECT_TRUE(fs::is_empty(out.parent_path())) << "staging directory removed";
  for (const char* content : {"first", "second"}) {
    StagedDirectory staged(out.string() + "/");
    std::ofstream(fs::path(staged.getStagingPath()) / "summary.json") << content;
    staged.commit();
  }
  std::ifstream in(out / "summary.json");
  std::string text;
  in >> text;
  EXPECT_EQ(text, "second");
  EXPECT_EQ(std::distance(fs::directory_iterator(out.parent_path()), fs::directory_iterator()), 1);
}

TEST(StagedDirectory, RefusesToReplaceADirectoryThatIsNoOutput) {
  const fs::path root = fs::path(RBFMUSCLE_BINARY_DIR) / "test_out" / "framework_refuse";
  fs::remove_all(root);
  fs::create_directories(root);
  std::ofstream(root / "precious.txt") << "keep";
  EXPECT_TRUE(throwsWith([&] { StagedDirectory staged(root.string()); },
                         "is not an rbfmuscle output (no summary.json)"));
  EXPECT_TRUE(fs::exists(root / "precious.txt"));
}

TEST(FrameGeometry, VtpRejectsOutOfRangeIndices) {
  FrameGeometry geometry;
  geometry.name = "tri";
  geometry.vertices_mm = Eigen::Matrix3d::Identity();
  geometry.triangles.resize(3, 1);
  geometry.triangles << 0, 1, 3;
  EXPECT_TRUE(throwsWith([&] { writeVtp("/nonexistent/never.vtp", geometry); },
                         "geometry 'tri': vertex index 3 outside [0, 3)"));
}

// write → read gives back the same points (10 significant digits), triangles and polylines.
TEST(FrameGeometry, VtpReadsBackWhatWasWritten) {
  const fs::path dir = fs::path(RBFMUSCLE_BINARY_DIR) / "test_out" / "framework_vtp";
  fs::create_directories(dir);
  FrameGeometry geometry;
  geometry.name = "piece";
  geometry.vertices_mm.resize(3, 4);
  geometry.vertices_mm << 0.0, 1.0, 0.0, 812.3456789, 0.0, 0.0, 1.0, -3.25, 0.0, 0.0, 0.0, 1e-3;
  geometry.triangles.resize(3, 2);
  geometry.triangles << 0, 1, 2, 1, 3, 3;
  geometry.polylines = {{0, 3}, {2, 1, 0}};
  const std::string path = (dir / "piece.vtp").string();
  writeVtp(path, geometry);
  const FrameGeometry back = readVtp(path);
  EXPECT_EQ(back.name, "piece");
  ASSERT_EQ(back.vertices_mm.cols(), 4);
  EXPECT_LE((back.vertices_mm - geometry.vertices_mm).cwiseAbs().maxCoeff(), 1e-6);
  EXPECT_EQ(back.triangles, geometry.triangles);
  EXPECT_EQ(back.polylines, geometry.polylines);
}

TEST(FrameGeometry, VtpReaderNamesTheFileAndTheFault) {
  const fs::path dir = fs::path(RBFMUSCLE_BINARY_DIR) / "test_out" / "framework_vtp";
  fs::create_directories(dir);
  const std::string path = (dir / "bad.vtp").string();
  std::ofstream(path) << "<?xml version=\"1.0\"?>\n<VTKFile type=\"PolyData\"><PolyData><Piece>\n"
                      << "<Points><DataArray>0 0 0 1 0 0 0 1 0</DataArray></Points>\n"
                      << "<Polys><DataArray Name=\"connectivity\">0 1 7</DataArray>"
                      << "<DataArray Name=\"offsets\">3</DataArray></Polys>\n</Piece></PolyData></VTKFile>\n";
  EXPECT_TRUE(throwsWith([&] { readVtp(path); }, path + ": vertex index 7"));
  std::ofstream(path) << "<?xml version=\"1.0\"?>\n<VTKFile><Other/></VTKFile>\n";
  EXPECT_TRUE(throwsWith([&] { readVtp(path); }, path + ": expected VTKFile/PolyData/Piece"));
  EXPECT_TRUE(throwsWith([&] { readVtp((dir / "missing.vtp").string()); }, "missing.vtp: cannot read as XML"));
}

}  // namespace
}  // namespace rbfmuscle
