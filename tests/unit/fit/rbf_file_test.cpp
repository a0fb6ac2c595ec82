#include "fit/rbf_file.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

namespace rbfmuscle {
namespace {

namespace fs = std::filesystem;

fs::path testDir() {
  const fs::path dir = fs::path(RBFMUSCLE_BINARY_DIR) / "test_out/rbf_file";
  fs::create_directories(dir);
  return dir;
}

RbfSurface makeSurface() {
  Eigen::Matrix3Xd centres(3, 3);
  centres << 0.1, -2.0 / 3.0, 5, 1e-9, 2, 3, -4, 0, 1.0 / 7.0;
  RbfSurface s;
  s.field = GaussianField(-5.0, centres, Eigen::Vector3d(1.5, -0.25, 3.0 / 11.0),
                          Eigen::Vector3d(0.01, 0.5, 1e-4), 1e-8);
  s.frame_offset_mm = Eigen::Vector3d(143.225, 243.37, -432.499);
  s.source_mesh = "muscle.ply";
  s.source_hash = "0123456789abcdef";
  s.settings = "max_centres=3";
  s.metrics_json = "{\"jaccard\": 0.9}";
  return s;
}

/// Writes `text` as a .rbf file and returns the error message of reading it.
std::string readError(const std::string& text) {
  const fs::path path = testDir() / "bad.rbf";
  std::ofstream(path) << text;
  try {
    readRbfFile(path.string());
  } catch (const RbfFileError& e) {
    return e.what();
  }
  return "no error";
}

std::string validHeader(int centres) {
  return "rbfmuscle_rbf 1\nunits mm\nsource_mesh m.ply\nsource_hash 00\nframe_offset_mm 0 0 0\n"
         "offset -5\ncutoff 1e-8\nsettings x=1\nmetrics {}\ncentres " + std::to_string(centres) + "\n";
}

TEST(RbfFile, RoundTripIsExact) {
  const RbfSurface written = makeSurface();
  const std::string path = (testDir() / "round_trip.rbf").string();
  writeRbfFile(path, written);
  const RbfSurface read = readRbfFile(path);
  EXPECT_EQ(read.field.getCentres(), written.field.getCentres());
  EXPECT_EQ(read.field.getWeights(), written.field.getWeights());
  EXPECT_EQ(read.field.getShapes(), written.field.getShapes());
  EXPECT_EQ(read.field.getOffset(), written.field.getOffset());
  EXPECT_EQ(read.field.getCutoff(), written.field.getCutoff());
  EXPECT_EQ(read.frame_offset_mm, written.frame_offset_mm);
  EXPECT_EQ(read.source_mesh, written.source_mesh);
  EXPECT_EQ(read.source_hash, written.source_hash);
  EXPECT_EQ(read.settings, written.settings);
  EXPECT_EQ(read.metrics_json, written.metrics_json);
  EXPECT_FALSE(fs::exists(path + ".partial"));
}

TEST(RbfFile, ErrorsNameFileAndLine) {
  EXPECT_NE(readError("").find("bad.rbf:0: file ends before 'rbfmuscle_rbf'"), std::string::npos);
  EXPECT_NE(readError("rbfmuscle_rbf 2\n").find("bad.rbf:1: unsupported version '2'"), std::string::npos);
  EXPECT_NE(readError("rbfmuscle_rbf 1\nunits m\n").find(":2: units must be 'mm'"), std::string::npos);
  EXPECT_NE(readError(validHeader(1) + "1 2 x 4 5\n").find(":11: 'x' is not a finite number"),
            std::string::npos);
  EXPECT_NE(readError(validHeader(2) + "1 2 3 4 5\n").find("file ends early"), std::string::npos);
  EXPECT_NE(readError(validHeader(1) + "1 2 3 4 -5\n").find(":11: shape of centre 0 must be > 0"),
            std::string::npos);
  EXPECT_NE(readError(validHeader(1) + "1 2 3 4 5 6\n").find("unexpected '6'"), std::string::npos);
  try {
    readRbfFile((testDir() / "missing.rbf").string());
    FAIL() << "no error";
  } catch (const RbfFileError& e) {
    EXPECT_NE(std::string(e.what()).find("missing.rbf: cannot open"), std::string::npos);
  }
}

TEST(RbfFile, UnwritablePathLeavesNothing) {
  const std::string path = (testDir() / "no_such_dir" / "x.rbf").string();
  EXPECT_THROW(writeRbfFile(path, makeSurface()), RbfFileError);
  EXPECT_FALSE(fs::exists(path));
}

}  // namespace
}  // namespace rbfmuscle
