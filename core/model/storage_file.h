// SPDX-License-Identifier: Apache-2.0
#pragma once
/// @file
/// OpenSim storage files (.sto/.mot): header lines, `endheader`, one row of
/// column labels, then tab-separated rows whose first column is time (s).
/// Also CSV output of the same table.
///
/// Header lines read: a first line without '=' is the table's name; `version=1`,
/// `nRows=N`, `nColumns=N`, `inDegrees=yes|no` (any case; keys and values may be quoted,
/// `"inDegrees"="yes"`); SIMM's `datarows N` and `datacolumns N`; any other line (free text
/// such as `Units are S.I. units (second, meters, Newtons, ...)`, quoted or not, or other
/// keys such as `DataType=double`) is skipped. Counts given are checked against the data.
#include <string>
#include <vector>

#include "model/model_error.h"

namespace rbfmuscle {

/// A table of numbers with labelled columns, as in an OpenSim storage file.
struct StorageTable {
  std::string name;                         ///< first header line
  bool in_degrees = false;                  ///< header `inDegrees=yes|no` (default no)
  std::vector<std::string> column_labels;   ///< column_labels[0] == "time"
  std::vector<std::vector<double>> rows;    ///< each row has column_labels.size() values
  std::vector<int> row_lines;               ///< 1-based file line of each row (readStorage; may be empty)

  /// Index of a column, or -1 when there is none of that label.
  int findColumn(const std::string& label) const;
};

/// Largest storage file read (bytes): 1 GiB, a million frames of a hundred coordinates.
constexpr unsigned long long kMaxStorageFileBytes = 1ull << 30;

/// Reads a .sto/.mot file. @throws ModelError naming the file and line for a
/// missing file or one that is not a regular file (a device, FIFO or directory is refused
/// before it is read), a file over kMaxStorageFileBytes, a missing `endheader`, a row of the
/// wrong length or a value that is not a number.
StorageTable readStorage(const std::string& path);

/// Parses the text of a storage file held in memory (what readStorage does after opening the
/// file); `path` only names the file in errors. @throws ModelError as readStorage.
StorageTable parseStorageText(const std::string& text, const std::string& path);

/// Writes a .sto file (OpenSim storage version 1). Writes to a temporary file
/// beside `path` and renames it, so a failure never leaves a half-written file.
void writeStorage(const std::string& path, const StorageTable& table);

/// Writes the same table as CSV (header row of labels), atomically.
void writeCsv(const std::string& path, const StorageTable& table);

}  // namespace rbfmuscle
