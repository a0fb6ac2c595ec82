// SPDX-License-Identifier: Apache-2.0
#include "model/motion.h"

#include <cmath>
#include <sstream>

#include "model/skeleton.h"
#include "model/storage_file.h"

namespace rbfmuscle {
namespace {
constexpr double kPi = 3.141592653589793238462643383279502884;
constexpr double kMetresToMm = 1000.0;  ///< translational coordinates in .mot files are in metres
}  // namespace

Motion Motion::fromFile(const std::string& path, const Skeleton& skeleton) {
  return fromTable(readStorage(path), path, skeleton);
}

Motion Motion::fromTable(const StorageTable& table, const std::string& path, const Skeleton& skeleton) {
  const auto& labels = table.column_labels;
  const auto& names = skeleton.getCoordinateNames();

  // Column c of the file feeds coordinate column_to_q[c] (-1 for time and skipped columns).
  std::vector<int> column_to_q(labels.size(), -1);
  std::vector<int> fed_by(names.size(), -1);
  for (std::size_t c = 1; c < labels.size(); ++c) {
    std::string name = labels[c];
    // OpenSim 4 state paths: /jointset/hip_r/hip_flexion_r/value (and .../speed).
    if (name.size() > 1 && name[0] == '/') {
      const auto last = name.rfind('/');
      const std::string leaf = name.substr(last + 1);
      if (leaf == "speed") continue;
      const auto previous = last == 0 ? std::string::npos : name.rfind('/', last - 1);
      if (leaf == "value" && previous != std::string::npos) name = name.substr(previous + 1, last - previous - 1);
    }
    const int q = skeleton.findCoordinateIndex(name);
    if (q < 0) {
      std::string list;
      for (const auto& n : names) list += (list.empty() ? "" : ", ") + n;
      throw ModelError("motion " + path + ": column '" + labels[c] +
                       "' is not a coordinate of skeleton " + skeleton.getName() +
                       " (coordinates: " + list + ")");
    }
    if (fed_by[q] >= 0)
      throw ModelError("motion " + path + ": columns '" + labels[fed_by[q]] + "' and '" + labels[c] +
                       "' both give coordinate '" + names[q] + "'");
    fed_by[q] = static_cast<int>(c);
    column_to_q[c] = q;
  }
  if (table.rows.empty()) throw ModelError("motion " + path + ": the file has no frames (no data rows)");

  // Per column: degrees or rad → rad for rotational coordinates, m → mm for translational ones.
  const double to_rad = table.in_degrees ? kPi / 180.0 : 1.0;
  std::vector<double> scale(labels.size(), 1.0);
  for (std::size_t c = 1; c < labels.size(); ++c)
    if (column_to_q[c] >= 0)
      scale[c] = skeleton.getCoordinates()[static_cast<std::size_t>(column_to_q[c])].motion ==
                         CoordinateMotion::kTranslational
                     ? kMetresToMm
                     : to_rad;
  const Eigen::VectorXd& rest = skeleton.getRestCoordinateValues();
  Motion m;
  m.path_ = path;
  m.times_s_.reserve(table.rows.size());
  m.q_rad_.reserve(table.rows.size());
  for (std::size_t r = 0; r < table.rows.size(); ++r) {
    const auto& row = table.rows[r];
    Eigen::VectorXd q = rest;
    for (std::size_t c = 0; c < row.size(); ++c) {
      if (!std::isfinite(row[c]))
        throw ModelError("motion " + path + ": frame " + std::to_string(r) + ", column '" +
                         labels[c] + "' holds a non-finite value (" + std::to_string(row[c]) + ")");
      if (column_to_q[c] >= 0) {
        q[column_to_q[c]] = scale[c] * row[c];
        if (std::abs(q[column_to_q[c]]) > kMaxCoordinate_rad) {
          std::ostringstream text;
          text << "motion " << path << ": line "
               << (r < table.row_lines.size() ? table.row_lines[r] : 0) << " (frame " << r << "), column '"
               << labels[c] << "': " << row[c] << (table.in_degrees ? " deg" : " rad") << " exceeds the "
               << kMaxCoordinate_rad << " rad a coordinate may take (inDegrees="
               << (table.in_degrees ? "yes" : "no") << "; wrong units?)";
          throw ModelError(text.str());
        }
      }
    }
    if (r > 0 && !(row[0] > m.times_s_.back()))
      throw ModelError("motion " + path + ": frame " + std::to_string(r) + " has time " +
                       std::to_string(row[0]) + " s, expected time to increase (previous " +
                       std::to_string(m.times_s_.back()) + " s)");
    m.times_s_.push_back(row[0]);
    m.q_rad_.push_back(std::move(q));
  }
  return m;
}

}  // namespace rbfmuscle
