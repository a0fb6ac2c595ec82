#include "model/motion.h"

#include <cmath>
#include <sstream>

#include "model/skeleton.h"
#include "model/storage_file.h"

namespace rbfmuscle {
namespace {
constexpr double kPi = 3.141592653589793238462643383279502884;
}  // namespace

Motion Motion::fromFile(const std::string& path, const Skeleton& skeleton) {
  const StorageTable table = readStorage(path);
  const auto& labels = table.column_labels;
  const auto& names = skeleton.getCoordinateNames();

  // Column c of the file feeds coordinate column_to_q[c] (-1 for time).
  std::vector<int> column_to_q(labels.size(), -1);
  for (std::size_t c = 1; c < labels.size(); ++c) {
    const int q = skeleton.findCoordinateIndex(labels[c]);
    if (q < 0) {
      std::string list;
      for (const auto& n : names) list += (list.empty() ? "" : ", ") + n;
      throw ModelError("motion " + path + ": column '" + labels[c] +
                       "' is not a coordinate of skeleton " + skeleton.getName() +
                       " (coordinates: " + list + ")");
    }
    column_to_q[c] = q;
  }
  if (table.rows.empty()) throw ModelError("motion " + path + ": the file has no frames (no data rows)");

  const double to_rad = table.in_degrees ? kPi / 180.0 : 1.0;
  Motion m;
  m.path_ = path;
  m.times_s_.reserve(table.rows.size());
  m.q_rad_.reserve(table.rows.size());
  for (std::size_t r = 0; r < table.rows.size(); ++r) {
    const auto& row = table.rows[r];
    Eigen::VectorXd q = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(names.size()));
    for (std::size_t c = 0; c < row.size(); ++c) {
      if (!std::isfinite(row[c]))
        throw ModelError("motion " + path + ": frame " + std::to_string(r) + ", column '" +
                         labels[c] + "' holds a non-finite value (" + std::to_string(row[c]) + ")");
      if (column_to_q[c] >= 0) {
        q[column_to_q[c]] = to_rad * row[c];
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
