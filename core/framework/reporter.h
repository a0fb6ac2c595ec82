// SPDX-License-Identifier: Apache-2.0
#pragma once
/// @file
/// The reporter: one row per frame of time (s), every skeleton coordinate
/// (rad; column = coordinate name) and every selected component output
/// (`COMPONENT.OUTPUT`, or `COMPONENT.OUTPUT_i` per element of a vector output).
#include "framework/component.h"
#include "framework/framework_error.h"
#include "model/storage_file.h"

#include <Eigen/Core>

#include <memory>
#include <string>
#include <vector>

namespace rbfmuscle {

/// True when `text` matches `pattern`, where '*' matches any run of characters
/// (including none) and every other character matches itself.
bool matchesPattern(const std::string& pattern, const std::string& text);

class Reporter {
 public:
  /// Selects the outputs whose `COMPONENT.OUTPUT` matches one of `patterns`;
  /// call after the components were initialized (vector sizes are fixed then).
  /// @throws FrameworkError at `where` for a pattern that matches no output
  ///   (except "*", which may match none), listing the available outputs.
  Reporter(std::string table_name, const std::vector<std::string>& coordinate_names,
           const std::vector<std::unique_ptr<Component>>& components,
           const std::vector<std::string>& patterns, const SourceLocation& where,
           int expected_frames);

  /// Appends one row: time, coordinates, then the selected outputs' current values.
  /// @throws FrameworkError when a vector output changed size since construction.
  void record(double time_s, const Eigen::VectorXd& q_rad);

  const StorageTable& getTable() const { return table_; }
  /// Writes DIR/outputs.sto (OpenSim storage, inDegrees=no) and DIR/outputs.csv.
  void write(const std::string& directory) const;

 private:
  struct Selected {
    const AbstractOutput* output;
    int size;
    std::string label;  ///< COMPONENT.OUTPUT
  };
  StorageTable table_;
  std::vector<Selected> selected_;
};

}  // namespace rbfmuscle
