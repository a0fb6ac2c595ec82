// SPDX-License-Identifier: Apache-2.0
#include "model/storage_file.h"

#include "model_test_support.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <limits>
#include <string>

namespace rbfmuscle {
namespace {

using test::expectModelError;

/// Storage test scratch file.
class TempFile : public test::TempFile {
 public:
  explicit TempFile(const std::string& name) : test::TempFile("storage_" + name) {}
};

std::string readAll(const std::string& path) {
  std::ifstream in(path);
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

StorageTable sampleTable() {
  StorageTable t;
  t.name = "fibre lengths";
  t.in_degrees = true;
  t.column_labels = {"time", "hip_flexion_r", "muscle/fiber_length"};
  t.rows = {{0.0, 1.0 / 3.0, 123.456789012345678},
            {1.0 / 30.0, -std::numeric_limits<double>::min(), 1e300},
            {2.0 / 30.0, std::nan(""), -0.1}};
  return t;
}

TEST(StorageFile, WriteThenReadIsExact) {
  TempFile f("roundtrip.sto");
  const StorageTable t = sampleTable();
  writeStorage(f.path(), t);
  const StorageTable r = readStorage(f.path());
  EXPECT_EQ(r.name, t.name);
  EXPECT_TRUE(r.in_degrees);
  EXPECT_EQ(r.column_labels, t.column_labels);
  ASSERT_EQ(r.rows.size(), t.rows.size());
  for (std::size_t i = 0; i < t.rows.size(); ++i)
    for (std::size_t j = 0; j < t.rows[i].size(); ++j) {
      if (std::isnan(t.rows[i][j])) EXPECT_TRUE(std::isnan(r.rows[i][j]));
      else EXPECT_EQ(r.rows[i][j], t.rows[i][j]) << "row " << i << " column " << j;
    }
  EXPECT_EQ(r.findColumn("muscle/fiber_length"), 2);
  EXPECT_EQ(r.findColumn("nope"), -1);
}

TEST(StorageFile, ParseFromMemoryEqualsReadingTheFile) {
  TempFile f("from_memory.sto");
  writeStorage(f.path(), sampleTable());
  const StorageTable read = readStorage(f.path());
  const StorageTable parsed = parseStorageText(readAll(f.path()), "memory.sto");
  EXPECT_EQ(parsed.column_labels, read.column_labels);
  EXPECT_EQ(parsed.row_lines, read.row_lines);
  ASSERT_EQ(parsed.rows.size(), read.rows.size());
  EXPECT_EQ(parsed.rows[1], read.rows[1]);
  expectModelError([] { parseStorageText("name\nendheader\ntime x\n0 1 2\n", "memory.sto"); },
                   {"memory.sto, line 4", "3 values, expected 2"});
}

TEST(StorageFile, WrittenHeaderIsOpenSimStorage) {
  TempFile f("header.sto");
  writeStorage(f.path(), sampleTable());
  const std::string text = readAll(f.path());
  EXPECT_EQ(text.rfind("fibre lengths\nversion=1\nnRows=3\nnColumns=3\ninDegrees=yes\nendheader\n"
                       "time\thip_flexion_r\tmuscle/fiber_length\n0\t",
                       0),
            0u)
      << text;
}

TEST(StorageFile, ReadsForeignHeaderLines) {
  TempFile f("foreign.mot");
  f.write("Coordinates\r\nversion=1\r\nnRows=2\r\nnColumns=2\r\ninDegrees=no\r\n\r\n"
          "Units are S.I. units (second, meters, Newtons, ...)\r\nendheader\r\n"
          "time\tknee angle\r\n 0.0   1.5\r\n\r\n0.1\t-2e-3\r\n");
  const StorageTable r = readStorage(f.path());
  EXPECT_EQ(r.name, "Coordinates");
  EXPECT_FALSE(r.in_degrees);
  ASSERT_EQ(r.column_labels.size(), 2u);
  EXPECT_EQ(r.column_labels[1], "knee angle");
  ASSERT_EQ(r.rows.size(), 2u);
  EXPECT_EQ(r.rows[1][1], -2e-3);
}

// OpenSim 4's header as it writes it, quoted keys and values, and the header counts checked.
TEST(StorageFile, ReadsOpenSim4AndQuotedHeaderLines) {
  TempFile f("opensim4.sto");
  f.write("Coordinates\nversion=1\nnRows=2\nnColumns=3\ninDegrees=Yes\nDataType=double\n"
          "OpenSimVersion=4.4\n\"Units are S.I. units (second, meters, Newtons, ...)\"\n"
          "If the header above contains a line with 'inDegrees', this indicates whether rotational "
          "values are in degrees (yes) or radians (no).\n\nendheader\n"
          "time\t/jointset/hip_r/hip_flexion_r/value\t/jointset/hip_r/hip_flexion_r/speed\n0\t1\t0\n0.5\t2\t0\n");
  const StorageTable r = readStorage(f.path());
  EXPECT_TRUE(r.in_degrees);
  EXPECT_EQ(r.rows.size(), 2u);
  TempFile q("quoted.mot");
  q.write("m\n\"inDegrees\" = \"no\"\n\"nRows\"=\"1\"\nendheader\ntime\ta\n0\t1\n");
  EXPECT_FALSE(readStorage(q.path()).in_degrees);
  q.write("m\n\"nColumns\"=\"3\"\nendheader\ntime\ta\n0\t1\n");
  expectModelError([&] { readStorage(q.path()); }, {q.path() + ", line 2", "nColumns=3", "2 labels"});
}

// SIMM's motion header: datacolumns / datarows, a range line, no '='.
TEST(StorageFile, ReadsSimmDataRowsAndColumns) {
  TempFile f("simm.mot");
  f.write("hip motion\ndatacolumns 2\ndatarows 3\nrange 0 1\nendheader\ntime hip_flexion_r\n0 0\n0.5 10\n1 20\n");
  const StorageTable r = readStorage(f.path());
  EXPECT_EQ(r.name, "hip motion");
  EXPECT_FALSE(r.in_degrees);
  ASSERT_EQ(r.rows.size(), 3u);
  EXPECT_EQ(r.rows[2][1], 20.0);
  f.write("hip motion\ndatacolumns 2\ndatarows 4\nendheader\ntime hip_flexion_r\n0 0\n");
  expectModelError([&] { readStorage(f.path()); }, {f.path() + ", line 3", "nRows=4", "1 data rows"});
}

TEST(StorageFile, CsvHasLabelRowAndExactNumbers) {
  TempFile f("table.csv");
  StorageTable t;
  t.column_labels = {"time", "a,b"};
  t.rows = {{0.5, 0.1}};
  writeCsv(f.path(), t);
  EXPECT_EQ(readAll(f.path()), "time,\"a,b\"\n0.5,0.10000000000000001\n");
}

TEST(StorageFile, MissingFileNamesFile) {
  expectModelError([] { readStorage("/nonexistent/dir/x.sto"); }, {"/nonexistent/dir/x.sto"});
}

TEST(StorageFile, MissingEndheaderNamesFile) {
  TempFile f("noend.sto");
  f.write("name\nversion=1\ntime\ta\n0\t1\n");
  expectModelError([&] { readStorage(f.path()); }, {f.path(), "endheader"});
}

TEST(StorageFile, ShortRowNamesFileAndLine) {
  TempFile f("short.sto");
  f.write("name\ninDegrees=no\nendheader\ntime\ta\tb\n0\t1\t2\n0.1\t1\n");
  expectModelError([&] { readStorage(f.path()); }, {f.path(), "line 6", "2 values, expected 3"});
}

TEST(StorageFile, BadNumberNamesLineAndColumn) {
  TempFile f("badnum.sto");
  f.write("name\nendheader\ntime\ta\n0\t1x\n");
  expectModelError([&] { readStorage(f.path()); }, {f.path(), "line 4", "'1x'", "'a'"});
}

TEST(StorageFile, HeaderCountsMustMatch) {
  TempFile f("counts.sto");
  f.write("name\nnRows=3\nendheader\ntime\ta\n0\t1\n");
  expectModelError([&] { readStorage(f.path()); }, {f.path(), "line 2", "nRows=3", "1 data rows"});
}

TEST(StorageFile, FirstColumnMustBeTime) {
  TempFile f("notime.sto");
  f.write("name\nendheader\nt\ta\n0\t1\n");
  expectModelError([&] { readStorage(f.path()); }, {f.path(), "line 3", "'time'"});
}

TEST(StorageFile, WriteRejectsRaggedRowAndLeavesNoFile) {
  TempFile f("ragged.sto");
  StorageTable t;
  t.column_labels = {"time", "a"};
  t.rows = {{0.0}};
  expectModelError([&] { writeStorage(f.path(), t); }, {f.path(), "row 0"});
  EXPECT_FALSE(std::ifstream(f.path()).good());
}

TEST(StorageFile, WriteToMissingDirectoryNamesFile) {
  expectModelError([] { writeStorage("/nonexistent/dir/out.sto", sampleTable()); },
                   {"/nonexistent/dir/out.sto"});
}

}  // namespace
}  // namespace rbfmuscle
