// SPDX-License-Identifier: Apache-2.0
#include "model/attachment_areas.h"

#include "model_test_support.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <string>
#include <vector>

namespace rbfmuscle {
namespace {

using test::expectModelError;

const std::string kHipDir = std::string(RBFMUSCLE_SOURCE_DIR) + "/models/hip";
const std::string kRealFile = kHipDir + "/landmarks/attachment_areas.json";

/// Attachment areas test scratch file holding `text`.
class JsonFile : public test::TempFile {
 public:
  JsonFile(const std::string& name, const std::string& text)
      : test::TempFile("areas_" + name + ".json") {
    write(text);
  }
};

/// A file with units "mm" and the given "clouds" object text.
std::string withClouds(const std::string& clouds) {
  return "{\"units\": \"mm\", \"frame\": \"test\", \"clouds\": " + clouds + "}";
}

// ---- the real file ----------------------------------------------------------

TEST(AttachmentAreas, RealFileGivesEveryCloudWithItsPointCountInTheOrderAsked) {
  const std::vector<std::pair<std::string, long>> expected = {
      {"LC_SET_Ins_1_R_M090_Psoas_maj", 7},  {"BL_R_Thigh_Ref_system", 4},
      {"LC_SET_Ori_1_R_M081_Glut_Max", 21},  {"LC_SET_Ori_2_R_M081_Glut_Max", 22},
      {"LC_SET_Ins_1_R_M081_Glut_Max", 11},  {"LC_SET_Ins_2_R_M081_Glut_Max", 6},
      {"LC_SET_Ori_1_R_M091_Iliacus", 40},   {"LC_SET_Ins_1_R_M091_Iliacus", 7},
      {"LC_SET_Ori_1_R_M090_Psoas_maj", 5},  {"LC_SET_Ori_2_R_M090_Psoas_maj", 7},
      {"LC_SET_Ori_3_R_M090_Psoas_maj", 8},  {"LC_SET_Ori_4_R_M090_Psoas_maj", 6}};
  std::vector<std::string> names;
  for (const auto& e : expected) names.push_back(e.first);
  const auto areas = readAttachmentAreas(kRealFile, names);
  ASSERT_EQ(areas.size(), expected.size());
  for (std::size_t i = 0; i < expected.size(); ++i) {
    EXPECT_EQ(areas[i].name, expected[i].first);
    EXPECT_EQ(areas[i].points_mm.cols(), expected[i].second) << expected[i].first;
  }
}

TEST(AttachmentAreas, IliacusOriginFirstPointIsItsCtCoordinatesInMm) {
  const auto areas = readAttachmentAreas(kRealFile, {"LC_SET_Ori_1_R_M091_Iliacus"});
  ASSERT_EQ(areas.size(), 1u);
  ASSERT_EQ(areas[0].points_mm.cols(), 40);
  EXPECT_DOUBLE_EQ(areas[0].points_mm(0, 0), 122.397);
  EXPECT_DOUBLE_EQ(areas[0].points_mm(1, 0), 192.971);
  EXPECT_DOUBLE_EQ(areas[0].points_mm(2, 0), -344.129);
}

TEST(AttachmentAreas, EmptyNameListChecksTheFileAndReadsNothing) {
  EXPECT_TRUE(readAttachmentAreas(kRealFile, {}).empty());
  expectModelError([] { readAttachmentAreas(kHipDir + "/nope.json", {}); }, {"nope.json"});
}

// ---- the spec grammar -------------------------------------------------------

TEST(AttachmentAreaSpec, FileReferenceIsRelativeToBaseDirectoryAndKeepsTheOrder) {
  const auto areas = parseAttachmentAreaSpec(
      "landmarks/attachment_areas.json: LC_SET_Ori_2_R_M081_Glut_Max, LC_SET_Ori_1_R_M081_Glut_Max",
      kHipDir);
  ASSERT_EQ(areas.size(), 2u);
  EXPECT_EQ(areas[0].name, "LC_SET_Ori_2_R_M081_Glut_Max");
  EXPECT_EQ(areas[0].points_mm.cols(), 22);
  EXPECT_EQ(areas[1].name, "LC_SET_Ori_1_R_M081_Glut_Max");
  EXPECT_EQ(areas[1].points_mm.cols(), 21);
}

TEST(AttachmentAreaSpec, FileReferenceAllowsLineBreaksAndSpacesAroundTokens) {
  const auto areas = parseAttachmentAreaSpec(
      "\n   landmarks/attachment_areas.json :\n\tLC_SET_Ins_1_R_M091_Iliacus ,\n"
      "   LC_SET_Ori_1_R_M091_Iliacus\n  ",
      kHipDir);
  ASSERT_EQ(areas.size(), 2u);
  EXPECT_EQ(areas[0].points_mm.cols(), 7);
  EXPECT_EQ(areas[1].points_mm.cols(), 40);
}

TEST(AttachmentAreaSpec, AbsoluteFileIgnoresBaseDirectory) {
  const auto areas =
      parseAttachmentAreaSpec(kRealFile + ": LC_SET_Ins_1_R_M091_Iliacus", "/no/such/dir");
  ASSERT_EQ(areas.size(), 1u);
  EXPECT_EQ(areas[0].points_mm.cols(), 7);
}

TEST(AttachmentAreaSpec, InlinePointsAreOneAreaNamedInlineWithOneColumnPerPoint) {
  const auto areas = parseAttachmentAreaSpec(" 1 2 3;\n 4.5  -6e1\t7 ; -0.25 0 1e4; ", "");
  ASSERT_EQ(areas.size(), 1u);
  EXPECT_EQ(areas[0].name, "inline");
  Eigen::Matrix3Xd expected(3, 3);
  expected << 1, 4.5, -0.25, 2, -60, 0, 3, 7, 1e4;
  EXPECT_EQ(areas[0].points_mm, expected);
}

TEST(AttachmentAreaSpec, EmptySpecIsRefusedWithBothFormsShown) {
  expectModelError([] { parseAttachmentAreaSpec(" \n\t ", ""); },
                   {"spec is empty", "FILE: NAME, NAME", "x y z; x y z"});
}

TEST(AttachmentAreaSpec, FileReferenceWithoutFileOrNamesIsRefused) {
  expectModelError([] { parseAttachmentAreaSpec(": A, B", kHipDir); }, {"no file before ':'"});
  expectModelError([] { parseAttachmentAreaSpec("landmarks/attachment_areas.json:  ", kHipDir); },
                   {"landmarks/attachment_areas.json:", "no cloud names after ':'"});
}

TEST(AttachmentAreaSpec, EmptyCloudNameIsRefusedWithItsPosition) {
  expectModelError([] { parseAttachmentAreaSpec("f.json: A,, B", kHipDir); },
                   {"\"f.json: A,, B\"", "cloud name 2 of 3 is empty"});
  expectModelError([] { parseAttachmentAreaSpec("f.json: A, B,", kHipDir); },
                   {"cloud name 3 of 3 is empty"});
}

TEST(AttachmentAreaSpec, FileErrorsNameTheResolvedPath) {
  expectModelError([] { parseAttachmentAreaSpec("landmarks/missing.json: A", kHipDir); },
                   {"attachment areas file " + kHipDir + "/landmarks/missing.json", "no such file"});
  expectModelError([] { parseAttachmentAreaSpec("landmarks/attachment_areas.json: Iliacus", kHipDir); },
                   {"attachment_areas.json", "no cloud \"Iliacus\""});
}

TEST(AttachmentAreaSpec, InlinePointWithWrongCountIsRefusedWithItsIndex) {
  expectModelError([] { parseAttachmentAreaSpec("1 2 3; 4 5; 6 7 8", ""); },
                   {"inline point 2 of 3 has 2 values", "\"4 5\"", "expected 3 numbers"});
  expectModelError([] { parseAttachmentAreaSpec("1 2 3 4", ""); },
                   {"inline point 1 of 1 has 4 values"});
}

TEST(AttachmentAreaSpec, InlineStrayOrMissingSemicolonIsRefused) {
  expectModelError([] { parseAttachmentAreaSpec("1 2 3;; 4 5 6", ""); },
                   {"inline point 2 of 3 is empty"});
  expectModelError([] { parseAttachmentAreaSpec("1 2 3 4 5 6", ""); }, {"has 6 values"});
}

TEST(AttachmentAreaSpec, InlineWordIsNotANumberAndHintsAtTheFileForm) {
  expectModelError([] { parseAttachmentAreaSpec("1 2 3; 4 five 6", ""); },
                   {"inline point 2 of 2: \"five\" is not a number", "FILE: NAME, NAME"});
  expectModelError([] { parseAttachmentAreaSpec("1,2,3", ""); },
                   {"inline point 1 of 1: \"1,2,3\" is not a number"});
  expectModelError(
      [] { parseAttachmentAreaSpec("landmarks/attachment_areas.json LC_SET_Ori_1_R_M091_Iliacus", ""); },
      {"\"landmarks/attachment_areas.json\" is not a number", "FILE: NAME, NAME"});
}

TEST(AttachmentAreaSpec, InlineNanAndInfinityAreRefused) {
  expectModelError([] { parseAttachmentAreaSpec("nan 2 3", ""); },
                   {"inline point 1 of 1: coordinate x \"nan\" is not finite"});
  expectModelError([] { parseAttachmentAreaSpec("1 2 3; 1 -inf 3", ""); },
                   {"inline point 2 of 2: coordinate y \"-inf\" is not finite"});
  expectModelError([] { parseAttachmentAreaSpec("1 2 1e400", ""); },
                   {"coordinate z \"1e400\" is not finite"});
}

TEST(AttachmentAreaSpec, InlineImplausibleMagnitudeIsRefused) {
  expectModelError([] { parseAttachmentAreaSpec("1 2 3; 1 2 -2e5", ""); },
                   {"inline point 2 of 2: coordinate z = -200000 mm is implausible",
                    "magnitude above 100000 mm"});
}

// ---- file errors ------------------------------------------------------------

TEST(AttachmentAreas, MissingFileIsNamed) {
  expectModelError([] { readAttachmentAreas("/no/such/areas.json", {"A"}); },
                   {"attachment areas file /no/such/areas.json: no such file"});
}

TEST(AttachmentAreas, DirectoryIsNotARegularFile) {
  expectModelError([] { readAttachmentAreas(kHipDir, {"A"}); },
                   {kHipDir, "not a regular file (a directory)"});
}

TEST(AttachmentAreas, FileAboveSizeLimitIsRefusedBeforeReading) {
  test::TempFile big("areas_big.json");
  big.write("{}");
  std::filesystem::resize_file(big.path(), kMaxAttachmentAreasFileBytes + 1);  // sparse
  expectModelError([&] { readAttachmentAreas(big.path(), {"A"}); },
                   {big.path(), "67108865 bytes", "64 MiB"});
}

TEST(AttachmentAreas, TextThatIsNotJsonGivesLineAndColumn) {
  const JsonFile f("syntax", "{\"units\": \"mm\",\n \"clouds\": {\"A\": [1, 2,]}}");
  expectModelError([&] { readAttachmentAreas(f.path(), {"A"}); },
                   {f.path(), "not valid JSON", "line 2, column", "byte"});
}

TEST(AttachmentAreas, NanLiteralIsNotJsonAndSaysSo) {
  const JsonFile f("nan", withClouds("{\"A\": [{\"name\": \"1\", \"mm\": [1, NaN, 3]}]}"));
  expectModelError([&] { readAttachmentAreas(f.path(), {"A"}); },
                   {f.path(), "not valid JSON", "line 1", "JSON has no NaN or Infinity"});
}

TEST(AttachmentAreas, NumberBeyondDoubleIsRefused) {
  const JsonFile f("overflow", withClouds("{\"A\": [{\"mm\": [1, 2, 1e400]}]}"));
  expectModelError([&] { readAttachmentAreas(f.path(), {"A"}); },
                   {f.path(), "not valid JSON", "1e400", "line 1", "finite number"});
}

TEST(AttachmentAreas, TopValueMustBeAnObject) {
  const JsonFile f("top", "[1, 2, 3]");
  expectModelError([&] { readAttachmentAreas(f.path(), {"A"}); },
                   {f.path(), "the top value is an array"});
}

TEST(AttachmentAreas, UnitsMustBeMillimetres) {
  const JsonFile metres("metres", "{\"units\": \"m\", \"clouds\": {}}");
  expectModelError([&] { readAttachmentAreas(metres.path(), {"A"}); },
                   {metres.path(), "\"units\" is \"m\"; only \"mm\" is read"});
  const JsonFile none("no_units", "{\"clouds\": {}}");
  expectModelError([&] { readAttachmentAreas(none.path(), {"A"}); },
                   {none.path(), "no \"units\" member"});
}

TEST(AttachmentAreas, CloudsMustBeAnObject) {
  const JsonFile none("no_clouds", "{\"units\": \"mm\"}");
  expectModelError([&] { readAttachmentAreas(none.path(), {"A"}); },
                   {none.path(), "no \"clouds\" object"});
  const JsonFile array("clouds_array", withClouds("[]"));
  expectModelError([&] { readAttachmentAreas(array.path(), {"A"}); },
                   {array.path(), "\"clouds\" is an array; expected an object"});
}

TEST(AttachmentAreas, UnknownCloudListsAvailableNamesSortedAndTheClosest) {
  const JsonFile f("unknown", withClouds("{\"Zeta\": [{\"mm\": [0, 0, 0]}], "
                                         "\"Ori_Iliacus\": [{\"mm\": [0, 0, 0]}], "
                                         "\"Alpha\": [{\"mm\": [0, 0, 0]}]}"));
  expectModelError([&] { readAttachmentAreas(f.path(), {"Alpha", "Ori_Illiacus"}); },
                   {f.path(), "no cloud \"Ori_Illiacus\"", "did you mean \"Ori_Iliacus\"?",
                    "its 3 clouds: Alpha, Ori_Iliacus, Zeta"});
}

TEST(AttachmentAreas, UnknownPartOfACloudNameSuggestsTheNamesContainingIt) {
  expectModelError([] { readAttachmentAreas(kRealFile, {"iliacus"}); },
                   {"no cloud \"iliacus\" (did you mean \"LC_SET_Ins_1_R_M091_Iliacus\" or "
                    "\"LC_SET_Ori_1_R_M091_Iliacus\"?)",
                    "its 12 clouds: BL_R_Thigh_Ref_system, LC_SET_Ins_1_R_M081_Glut_Max"});
}

TEST(AttachmentAreas, UnknownCloudAmongManyListsTheTenClosest) {
  std::string clouds = "{";
  for (int i = 0; i < 30; ++i)
    clouds += std::string(i ? ", " : "") + "\"cloud_" + std::to_string(i) + "\": [{\"mm\": [0, 0, 0]}]";
  const JsonFile f("many", withClouds(clouds + ", \"Glut_Max_Ori\": [{\"mm\": [0, 0, 0]}]}"));
  expectModelError([&] { readAttachmentAreas(f.path(), {"Glut_Max_Ori_1"}); },
                   {"did you mean \"Glut_Max_Ori\"?", "the 10 closest of its 31 clouds: "});
}

TEST(AttachmentAreas, CloudAskedTwiceIsRefused) {
  expectModelError(
      [] {
        readAttachmentAreas(kRealFile, {"LC_SET_Ori_1_R_M091_Iliacus", "BL_R_Thigh_Ref_system",
                                        "LC_SET_Ori_1_R_M091_Iliacus"});
      },
      {kRealFile, "cloud \"LC_SET_Ori_1_R_M091_Iliacus\" is asked twice (names 1 and 3"});
}

TEST(AttachmentAreas, CloudDefinedTwiceInTheFileIsRefused) {
  const JsonFile f("defined_twice", withClouds("{\"A\": [{\"mm\": [0, 0, 0]}], "
                                               "\"A\": [{\"mm\": [1, 1, 1]}]}"));
  expectModelError([&] { readAttachmentAreas(f.path(), {"A"}); },
                   {f.path(), "cloud \"A\" is defined twice"});
}

TEST(AttachmentAreas, EmptyCloudOrNonArrayCloudIsRefused) {
  const JsonFile f("empty", withClouds("{\"A\": [], \"B\": {\"mm\": [0, 0, 0]}}"));
  expectModelError([&] { readAttachmentAreas(f.path(), {"A"}); },
                   {f.path(), "cloud \"A\" is empty"});
  expectModelError([&] { readAttachmentAreas(f.path(), {"B"}); },
                   {f.path(), "cloud \"B\" is an object; expected an array of points"});
}

TEST(AttachmentAreas, BadPointNamesCloudIndexAndPointName) {
  const JsonFile f("bad_points", withClouds(
      "{\"short\": [{\"name\": \"1\", \"mm\": [0, 0, 0]}, {\"name\": \"p2\", \"mm\": [1, 2]}],"
      " \"string\": [{\"mm\": [0, 0, 0]}, {\"mm\": [0, 0, 0]}, {\"name\": \"3\", \"mm\": [1, \"2\", 3]}],"
      " \"null\": [{\"mm\": [null, 0, 0]}],"
      " \"bare\": [[1, 2, 3]],"
      " \"no_mm\": [{\"name\": \"only\", \"xyz\": [1, 2, 3]}],"
      " \"huge\": [{\"mm\": [0, 0, 0]}, {\"name\": \"2\", \"mm\": [0, 150000, 0]}]}"));
  const auto expect = [&](const std::string& cloud, std::initializer_list<std::string> parts) {
    SCOPED_TRACE(cloud);
    expectModelError([&] { readAttachmentAreas(f.path(), {cloud}); }, parts);
  };
  expect("short", {f.path(), "cloud \"short\", point 2 of 2 (name \"p2\"): \"mm\" is [1,2]",
                   "expected 3 numbers [x, y, z]"});
  expect("string", {"cloud \"string\", point 3 of 3 (name \"3\"): coordinate y is \"2\"",
                    "expected a number"});
  expect("null", {"cloud \"null\", point 1 of 1: coordinate x is null"});
  expect("bare", {"cloud \"bare\", point 1 of 1: expected an object with \"mm\": [x, y, z]"});
  expect("no_mm", {"cloud \"no_mm\", point 1 of 1 (name \"only\"): expected an object with \"mm\""});
  expect("huge", {"cloud \"huge\", point 2 of 2 (name \"2\"): coordinate y = 150000 mm is implausible",
                  "magnitude above 100000 mm"});
}

}  // namespace
}  // namespace rbfmuscle
