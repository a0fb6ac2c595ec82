// SPDX-License-Identifier: Apache-2.0
#include "fit/rbf_file.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <iterator>

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

/// Writes `text` as a .rbf file and returns the error message of reading it. The file is named
/// bad.rbf in a folder of the running test's own, so tests run in parallel do not share it.
std::string readError(const std::string& text) {
  const fs::path dir = testDir() / ::testing::UnitTest::GetInstance()->current_test_info()->name();
  fs::create_directories(dir);
  const fs::path path = dir / "bad.rbf";
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

/// Every part of two surfaces equal, bit for bit.
void expectSameSurface(const RbfSurface& read, const RbfSurface& expected) {
  EXPECT_EQ(read.field.getCentres(), expected.field.getCentres());
  EXPECT_EQ(read.field.getWeights(), expected.field.getWeights());
  EXPECT_EQ(read.field.getShapes(), expected.field.getShapes());
  EXPECT_EQ(read.field.getOffset(), expected.field.getOffset());
  EXPECT_EQ(read.field.getCutoff(), expected.field.getCutoff());
  EXPECT_EQ(read.frame_offset_mm, expected.frame_offset_mm);
  EXPECT_EQ(read.source_mesh, expected.source_mesh);
  EXPECT_EQ(read.source_hash, expected.source_hash);
  EXPECT_EQ(read.settings, expected.settings);
  EXPECT_EQ(read.metrics_json, expected.metrics_json);
}

TEST(RbfFile, RoundTripIsExact) {
  const RbfSurface written = makeSurface();
  const std::string path = (testDir() / "round_trip.rbf").string();
  writeRbfFile(path, written);
  expectSameSurface(readRbfFile(path), written);
  EXPECT_FALSE(fs::exists(path + ".partial"));
}

TEST(RbfFile, ParseFromMemoryEqualsReadingTheFile) {
  const std::string path = (testDir() / "from_memory.rbf").string();
  writeRbfFile(path, makeSurface());
  std::ifstream in(path);
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  expectSameSurface(parseRbfText(text, "memory.rbf"), readRbfFile(path));
  try {
    parseRbfText(validHeader(3), "memory.rbf");
    ADD_FAILURE() << "a file without its centre lines was accepted";
  } catch (const RbfFileError& e) {
    EXPECT_NE(std::string(e.what()).find("memory.rbf:"), std::string::npos) << e.what();
  }
}

TEST(RbfFile, WindowsLineEndsReadAsTheSameSurface) {
  const std::string path = (testDir() / "lf.rbf").string();
  writeRbfFile(path, makeSurface());
  std::ifstream in(path);
  std::string crlf;
  for (std::string line; std::getline(in, line);) crlf += line + "\r\n";
  expectSameSurface(parseRbfText(crlf, "crlf.rbf"), readRbfFile(path));
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

TEST(RbfFile, WeightOf1e308IsRefusedNamingTheLine) {
  // Read as is, one such weight made every frame's curvature cost NaN.
  EXPECT_NE(readError(validHeader(2) + "1 2 3 4 0.5\n1 2 3 1e308 0.5\n")
                .find("bad.rbf:12: centre 1: weight 1e+308 has a magnitude above 1e+06"),
            std::string::npos);
}

TEST(RbfFile, ImplausibleCoordinatesShapesAndOffsetsAreRefusedNamingTheLine) {
  EXPECT_NE(readError(validHeader(1) + "1e9 2 3 4 0.5\n").find(":11: centre 0: coordinate 1e+09 has a magnitude above"),
            std::string::npos);
  EXPECT_NE(readError(validHeader(1) + "1 2 3 4 1e-300\n").find(":11: shape of centre 0 is 1e-300 mm^-2, expected 1e-08"),
            std::string::npos);
  std::string header = validHeader(1);
  header.replace(header.find("offset -5"), 9, "offset -1e300");
  EXPECT_NE(readError(header + "1 2 3 4 0.5\n").find(":6: offset -1e+300 has a magnitude above"), std::string::npos);
}

TEST(RbfFile, MoreCentreLinesThanDeclaredAreRefusedNamingTheLine) {
  // 'centres 1' followed by two lines used to load one centre and ignore the rest.
  EXPECT_NE(readError(validHeader(1) + "1 2 3 4 0.5\n# comment\n5 6 7 8 0.5\n")
                .find("bad.rbf:13: more centre lines than the 1 declared by 'centres' on line 10"),
            std::string::npos);
  EXPECT_NE(readError(validHeader(3) + "1 2 3 4 0.5\n1 2 3 4 0.5\n").find("bad.rbf:12: file ends early"),
            std::string::npos);
}

TEST(RbfFile, ZeroCentresAreRefusedAsSuch) {
  // It used to load and then be blamed on the landmarks ("no centre attaches").
  EXPECT_NE(readError(validHeader(0)).find("bad.rbf:10: centre count must be a whole number from 1 to 10000000, got '0' "
                                           "(a surface needs at least one centre)"),
            std::string::npos);
}

TEST(RbfFile, HugeCentreCountIsRefusedBeforeAllocation) {
  // It used to end in a bare std::bad_alloc.
  const std::string header = validHeader(1);
  const std::string huge = header.substr(0, header.find("centres 1")) + "centres 9000000\n";
  EXPECT_NE(readError(huge + "1 2 3 4 0.5\n").find("bad.rbf:10: declares 9000000 centres, but the file ("),
            std::string::npos);
  const std::string beyond = header.substr(0, header.find("centres 1")) + "centres 2000000000\n";
  EXPECT_NE(readError(beyond).find("centre count must be a whole number from 1 to 10000000, got '2000000000'"),
            std::string::npos);
}

TEST(RbfFile, PathThatIsADeviceOrDirectoryIsRefusedWithoutReading) {
  for (const std::string& path : {std::string("/dev/zero"), testDir().string()}) {
    try {
      readRbfFile(path);
      ADD_FAILURE() << "no error for " << path;
    } catch (const RbfFileError& e) {
      EXPECT_NE(std::string(e.what()).find(path + ": cannot open the .rbf file: it is a"), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find("not a regular file"), std::string::npos) << e.what();
    }
  }
}

}  // namespace
}  // namespace rbfmuscle
