// SPDX-License-Identifier: Apache-2.0
#include "framework/reporter.h"

#include <filesystem>

namespace rbfmuscle {

bool matchesPattern(const std::string& pattern, const std::string& text) {
  // Iterative wildcard match with backtracking to the last '*'.
  std::size_t p = 0, t = 0, star = std::string::npos, mark = 0;
  while (t < text.size()) {
    if (p < pattern.size() && pattern[p] == '*') {
      star = p++;
      mark = t;
    } else if (p < pattern.size() && pattern[p] == text[t]) {
      ++p;
      ++t;
    } else if (star != std::string::npos) {
      p = star + 1;
      t = ++mark;
    } else {
      return false;
    }
  }
  while (p < pattern.size() && pattern[p] == '*') ++p;
  return p == pattern.size();
}

Reporter::Reporter(std::string table_name, const std::vector<std::string>& coordinate_names,
                   const std::vector<std::unique_ptr<Component>>& components,
                   const std::vector<std::string>& patterns, const SourceLocation& where,
                   int expected_frames) {
  table_.name = std::move(table_name);
  table_.in_degrees = false;
  table_.column_labels.push_back("time");
  table_.column_labels.insert(table_.column_labels.end(), coordinate_names.begin(),
                              coordinate_names.end());
  std::vector<bool> used(patterns.size(), false);
  std::string available;
  for (const auto& component : components) {
    for (const AbstractOutput* output : component->getOutputs()) {
      const std::string label = component->getName() + "." + output->getName();
      available += (available.empty() ? "" : ", ") + label;
      bool chosen = false;
      for (std::size_t i = 0; i < patterns.size(); ++i)
        if (matchesPattern(patterns[i], label)) chosen = used[i] = true;
      if (!chosen) continue;
      const int size = output->getSize();
      const bool scalar = std::string(output->getTypeName()) == "double";
      if (scalar) {
        table_.column_labels.push_back(label);
      } else {
        for (int k = 0; k < size; ++k) table_.column_labels.push_back(label + "_" + std::to_string(k));
      }
      selected_.push_back({output, size, label});
    }
  }
  for (std::size_t i = 0; i < patterns.size(); ++i)
    if (!used[i] && patterns[i] != "*")
      throwAt(where, "reporter pattern '" + patterns[i] + "' matches no output (outputs: " +
                         (available.empty() ? "none" : available) + ")");
  table_.rows.reserve(static_cast<std::size_t>(std::max(expected_frames, 0)));
}

void Reporter::record(double time_s, const Eigen::VectorXd& q_rad) {
  std::vector<double> row;
  row.reserve(table_.column_labels.size());
  row.push_back(time_s);
  row.insert(row.end(), q_rad.data(), q_rad.data() + q_rad.size());
  for (const Selected& s : selected_) {
    const std::size_t before = row.size();
    s.output->appendValues(row);
    if (row.size() - before != static_cast<std::size_t>(s.size))
      throw FrameworkError("output '" + s.label + "' changed size from " +
                           std::to_string(s.size) + " to " + std::to_string(row.size() - before) +
                           " during the run");
  }
  if (row.size() != table_.column_labels.size())
    throw FrameworkError("reporter: row of " + std::to_string(row.size()) + " values for " +
                         std::to_string(table_.column_labels.size()) + " columns");
  table_.rows.push_back(std::move(row));
}

void Reporter::write(const std::string& directory) const {
  const std::filesystem::path dir(directory);
  writeStorage((dir / "outputs.sto").string(), table_);
  writeCsv((dir / "outputs.csv").string(), table_);
}

}  // namespace rbfmuscle
