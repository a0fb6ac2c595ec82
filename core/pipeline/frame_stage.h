// SPDX-License-Identifier: Apache-2.0
#pragma once
/// @file
/// One step of a muscle's frame, with one interface: (state, input) → report.
#include "pipeline/muscle_state.h"

#include <Eigen/Core>

#include <limits>
#include <string>
#include <vector>

namespace rbfmuscle {

/// Name, unit and meaning of one reported figure: an output of the muscle component.
struct ReportField {
  std::string name;         ///< output name, snake_case with its unit (e.g. "volume_ratio")
  std::string unit;         ///< "mm", "mm^3", "1", …
  std::string description;  ///< one line, with frame and unit where they matter
};

/// One row of a stage's report table: the field's description and where its value lives in
/// the stage's Report struct. Tables are static, so a component can list its outputs before
/// any stage exists, and a value cannot be read from the wrong field.
template <class Report>
struct ReportEntry {
  const char* name;
  const char* unit;
  const char* description;
  double Report::*value;
};

/// The descriptions of a report table.
template <class Report, size_t N>
std::vector<ReportField> describeTable(const ReportEntry<Report> (&table)[N]) {
  std::vector<ReportField> fields;
  for (const ReportEntry<Report>& e : table) fields.push_back({e.name, e.unit, e.description});
  return fields;
}

/// Appends the values of `report` in table order.
template <class Report, size_t N>
void appendTable(const ReportEntry<Report> (&table)[N], const Report& report, std::vector<double>& values) {
  for (const ReportEntry<Report>& e : table) values.push_back(report.*(e.value));
}

/// A stage of the frame pipeline. Stages run in a fixed order; each reads what the earlier
/// ones wrote into MuscleState, writes its own part, and keeps a report of its last run
/// (NaN before the first, and when it did not run).
class FrameStage {
 public:
  static constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
  virtual ~FrameStage() = default;
  /// Whether the stage has work this frame (a surface nobody asked for is not tracked).
  virtual bool isNeeded(const FrameInput& input) const {
    (void)input;
    return true;
  }
  /// Runs the stage.
  virtual void run(MuscleState& state, const FrameInput& input) = 0;
  /// Appends the last run's report values, in the order of the stage type's table.
  virtual void appendReport(std::vector<double>& values) const = 0;
};

}  // namespace rbfmuscle
