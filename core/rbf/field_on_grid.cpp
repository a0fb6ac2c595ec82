#include "rbf/field_on_grid.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

namespace rbfmuscle {

namespace {

/// One axis of one centre: the node range within its cut-off radius, and per node
/// d² and e^{−α d²}.
struct AxisFactors {
  std::int64_t first = 0;  ///< first node index in range
  std::int64_t count = 0;  ///< nodes in range (0: the centre misses the grid)
  size_t offset = 0;       ///< start of this range in the shared buffers
};

}  // namespace

void addCentresOnGrid(const GaussianField& field, const RegularGrid& grid, const std::vector<int>& centres,
                      const Eigen::VectorXd& weight_change, std::vector<double>& values) {
  if (!(grid.cell_mm > 0.0) || !std::isfinite(grid.cell_mm)) {
    throw std::invalid_argument("field on grid: cell " + std::to_string(grid.cell_mm) + " mm, expected > 0");
  }
  for (int a = 0; a < 3; ++a) {
    if (grid.counts[static_cast<size_t>(a)] < 0) {
      throw std::invalid_argument("field on grid: negative node count on axis " + std::to_string(a));
    }
  }
  if (values.size() != static_cast<size_t>(grid.size())) {
    throw std::invalid_argument("field on grid: " + std::to_string(values.size()) + " values for " +
                                std::to_string(grid.size()) + " nodes");
  }
  const int n = static_cast<int>(centres.size());  // listed centres, in list order
  const double log_inv_cutoff = field.getCutoff() > 0.0 ? -std::log(field.getCutoff())
                                                          : std::numeric_limits<double>::infinity();
  const Eigen::Matrix3Xd& positions = field.getCentres();
  const Eigen::VectorXd& shapes = field.getShapes();
  // Per centre and axis: the node range and its factors (d², e^{−α d²}).
  std::vector<std::array<AxisFactors, 3>> ranges(static_cast<size_t>(n));
  std::vector<double> d2, factor;
  for (int m = 0; m < n; ++m) {
    const int c = centres[static_cast<size_t>(m)];
    const double alpha = shapes(c);
    const double radius = std::sqrt(log_inv_cutoff / alpha);  // +inf without cut-off
    for (int a = 0; a < 3; ++a) {
      const std::int64_t count = grid.counts[static_cast<size_t>(a)];
      const double u = (positions(a, c) - grid.origin_mm(a)) / grid.cell_mm;
      const double reach = radius / grid.cell_mm;
      const std::int64_t lo = std::isfinite(reach) ? std::max<std::int64_t>(0, std::int64_t(std::ceil(u - reach))) : 0;
      const std::int64_t hi =
          std::isfinite(reach) ? std::min<std::int64_t>(count - 1, std::int64_t(std::floor(u + reach))) : count - 1;
      AxisFactors& r = ranges[static_cast<size_t>(m)][static_cast<size_t>(a)];
      r.first = lo;
      r.count = std::max<std::int64_t>(0, hi - lo + 1);
      r.offset = d2.size();
      for (std::int64_t i = lo; i <= hi; ++i) {
        const double d = grid.origin_mm(a) + grid.cell_mm * double(i) - positions(a, c);
        d2.push_back(d * d);
        factor.push_back(std::exp(-alpha * d * d));
      }
    }
  }
  const std::int64_t nx = grid.counts[0], ny = grid.counts[1], nz = grid.counts[2];
#pragma omp parallel for schedule(dynamic, 1)
  for (std::int64_t k = 0; k < nz; ++k) {
    double* layer = values.data() + static_cast<size_t>(k * nx * ny);
    for (int m = 0; m < n; ++m) {
      const int c = centres[static_cast<size_t>(m)];
      const auto& r = ranges[static_cast<size_t>(m)];
      if (r[0].count == 0 || r[1].count == 0 || k < r[2].first || k >= r[2].first + r[2].count) continue;
      const size_t zk = r[2].offset + static_cast<size_t>(k - r[2].first);
      const double alpha = shapes(c);
      const double budget = log_inv_cutoff / alpha - d2[zk];  // room left for dx² + dy²
      if (budget < 0.0) continue;
      const double wz = weight_change(c) * factor[zk];
      for (std::int64_t j = 0; j < r[1].count; ++j) {
        const size_t yj = r[1].offset + static_cast<size_t>(j);
        if (d2[yj] > budget) continue;
        const double wyz = wz * factor[yj];
        const double budget_x = budget - d2[yj];
        double* row = layer + static_cast<size_t>((r[1].first + j) * nx + r[0].first);
        for (std::int64_t i = 0; i < r[0].count; ++i) {
          const size_t xi = r[0].offset + static_cast<size_t>(i);
          if (d2[xi] <= budget_x) row[i] += wyz * factor[xi];
        }
      }
    }
  }
}

void calcValuesOnGrid(const GaussianField& field, const RegularGrid& grid, std::vector<double>& values) {
  values.assign(static_cast<size_t>(std::max<std::int64_t>(0, grid.size())), field.getOffset());
  std::vector<int> all(static_cast<size_t>(field.getNumCentres()));
  for (size_t c = 0; c < all.size(); ++c) all[c] = static_cast<int>(c);
  addCentresOnGrid(field, grid, all, field.getWeights(), values);
}

}  // namespace rbfmuscle
