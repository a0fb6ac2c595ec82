// SPDX-License-Identifier: Apache-2.0
#include "fibres/interior_grid.h"

#include "geometry/disjoint_sets.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <queue>
#include <stdexcept>
#include <string>

namespace rbfmuscle {
namespace {

/// Grid cell centres of `box` with spacing h: positions and dims.
Eigen::Matrix3Xd makeGridPoints(const Eigen::AlignedBox3d& box, double h, Eigen::Vector3i& dims) {
  const Eigen::Vector3d size = box.sizes();
  for (int a = 0; a < 3; ++a) dims(a) = std::max(1, static_cast<int>(std::ceil(size(a) / h)));
  Eigen::Matrix3Xd points(3, static_cast<Eigen::Index>(dims.prod()));
  Eigen::Index n = 0;
  for (int k = 0; k < dims.z(); ++k)
    for (int j = 0; j < dims.y(); ++j)
      for (int i = 0; i < dims.x(); ++i) points.col(n++) = box.min() + h * Eigen::Vector3d(i + 0.5, j + 0.5, k + 0.5);
  return points;
}

/// Whether a node on the border of the grid is inside.
bool touchesBorder(const Eigen::VectorXd& values, const Eigen::Vector3i& dims, double margin) {
  Eigen::Index n = 0;
  for (int k = 0; k < dims.z(); ++k)
    for (int j = 0; j < dims.y(); ++j)
      for (int i = 0; i < dims.x(); ++i, ++n) {
        const bool border = i == 0 || j == 0 || k == 0 || i == dims.x() - 1 || j == dims.y() - 1 || k == dims.z() - 1;
        if (border && values(n) >= margin) return true;
      }
  return false;
}

/// The node of `cell`, −1 when the cell is outside the grid or not inside the muscle.
int findNode(const InteriorGrid& grid, const Eigen::Vector3i& cell) {
  if ((cell.array() < 0).any() || (cell.array() >= grid.dims.array()).any()) return -1;
  return grid.node_of_cell[static_cast<size_t>(cell.x() + grid.dims.x() * (cell.y() + grid.dims.y() * cell.z()))];
}

}  // namespace

double InteriorGrid::calcVolume() const { return static_cast<double>(nodes_mm.cols()) * std::pow(spacing_mm, 3); }

InteriorGrid makeInteriorGrid(const GaussianField& field, double margin_mm, int target_nodes) {
  if (field.getNumCentres() == 0) throw std::invalid_argument("makeInteriorGrid: the field has no centre");
  if (target_nodes < 8)
    throw std::invalid_argument("makeInteriorGrid: target_nodes must be ≥ 8, got " + std::to_string(target_nodes));
  const Eigen::Matrix3Xd& centres = field.getCentres();
  double pad = 0;
  for (Eigen::Index k = 0; k < centres.cols(); ++k) pad = std::max(pad, 2.0 / std::sqrt(field.getShapes()(k)));
  Eigen::AlignedBox3d box(centres.rowwise().minCoeff(), centres.rowwise().maxCoeff());
  Eigen::Vector3i dims;
  Eigen::VectorXd values;
  Eigen::Matrix3Xd points;
  double h = 0;
  for (int pass = 0;; ++pass) {
    const Eigen::AlignedBox3d padded(box.min().array() - pad, box.max().array() + pad);
    // Coarse pass (~8 target_nodes cells in the box), then the spacing that gives ~target_nodes inside.
    h = std::cbrt(padded.volume() / (8.0 * target_nodes));
    points = makeGridPoints(padded, h, dims);
    field.calcValues(points, values);
    const Eigen::Index inside = (values.array() >= margin_mm).count();
    if (inside == 0) throw std::invalid_argument("makeInteriorGrid: no grid node has f ≥ margin " + std::to_string(margin_mm));
    if (touchesBorder(values, dims, margin_mm) && pass < 4) {
      pad *= 1.5;
      continue;
    }
    h *= std::cbrt(static_cast<double>(inside) / target_nodes);
    box = padded;
    break;
  }
  points = makeGridPoints(box, h, dims);
  field.calcValues(points, values);
  InteriorGrid grid;
  grid.corner_mm = box.min() + 0.5 * h * Eigen::Vector3d::Ones();
  grid.spacing_mm = h;
  grid.dims = dims;
  grid.node_of_cell.assign(static_cast<size_t>(points.cols()), -1);
  const Eigen::Index inside = (values.array() >= margin_mm).count();
  if (inside == 0) throw std::invalid_argument("makeInteriorGrid: no grid node has f ≥ margin " + std::to_string(margin_mm));
  grid.nodes_mm.resize(3, inside);
  grid.values.resize(inside);
  Eigen::Index n = 0, c = 0;
  for (int k = 0; k < dims.z(); ++k)
    for (int j = 0; j < dims.y(); ++j)
      for (int i = 0; i < dims.x(); ++i, ++c) {
        if (values(c) < margin_mm) continue;
        grid.node_of_cell[static_cast<size_t>(c)] = static_cast<int>(n);
        grid.nodes_mm.col(n) = points.col(c);
        grid.values(n) = values(c);
        grid.cells.emplace_back(i, j, k);
        ++n;
      }
  return grid;
}

std::vector<int> labelInteriorPieces(const InteriorGrid& grid, int& count) {
  const int n = static_cast<int>(grid.nodes_mm.cols());
  DisjointSets sets(static_cast<size_t>(n));
  // Each edge once: the 13 of the 26 neighbour offsets that come later in cell order.
  for (int a = 0; a < n; ++a) {
    const Eigen::Vector3i& cell = grid.cells[static_cast<size_t>(a)];
    for (int dz = 0; dz <= 1; ++dz)
      for (int dy = dz ? -1 : 0; dy <= 1; ++dy)
        for (int dx = (dz || dy) ? -1 : 1; dx <= 1; ++dx) {
          const int b = findNode(grid, cell + Eigen::Vector3i(dx, dy, dz));
          if (b >= 0) sets.join(a, b);
        }
  }
  std::vector<int> label(static_cast<size_t>(n)), label_of_root(static_cast<size_t>(n), -1);
  count = 0;
  for (int a = 0; a < n; ++a) {
    int& l = label_of_root[static_cast<size_t>(sets.find(a))];
    if (l < 0) l = count++;
    label[static_cast<size_t>(a)] = l;
  }
  return label;
}

std::vector<int> findShortestPath(const InteriorGrid& grid, int from, int to, double centre_preference) {
  const int n = static_cast<int>(grid.nodes_mm.cols());
  if (from < 0 || from >= n || to < 0 || to >= n)
    throw std::invalid_argument("findShortestPath: node " + std::to_string(from) + " or " + std::to_string(to) +
                                " outside [0, " + std::to_string(n) + ")");
  if (!(centre_preference >= 0))
    throw std::invalid_argument("findShortestPath: centre_preference must be ≥ 0, got " +
                                std::to_string(centre_preference));
  const double f_max = grid.values.maxCoeff();
  std::vector<double> cost(static_cast<size_t>(n), std::numeric_limits<double>::infinity());
  std::vector<int> previous(static_cast<size_t>(n), -1);
  using Entry = std::pair<double, int>;
  std::priority_queue<Entry, std::vector<Entry>, std::greater<Entry>> queue;
  cost[static_cast<size_t>(from)] = 0;
  queue.push({0.0, from});
  while (!queue.empty()) {
    const auto [c, a] = queue.top();
    queue.pop();
    if (a == to) break;
    if (c > cost[static_cast<size_t>(a)]) continue;
    const Eigen::Vector3i& cell = grid.cells[static_cast<size_t>(a)];
    for (int dz = -1; dz <= 1; ++dz)
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) {
          if (dx == 0 && dy == 0 && dz == 0) continue;
          const int b = findNode(grid, cell + Eigen::Vector3i(dx, dy, dz));
          if (b < 0) continue;
          const double f_mean = 0.5 * (grid.values(a) + grid.values(b));
          const double w = grid.spacing_mm * std::sqrt(static_cast<double>(dx * dx + dy * dy + dz * dz)) *
                           (1.0 + centre_preference * (1.0 - std::min(f_mean, f_max) / f_max));
          if (c + w < cost[static_cast<size_t>(b)]) {
            cost[static_cast<size_t>(b)] = c + w;
            previous[static_cast<size_t>(b)] = a;
            queue.push({c + w, b});
          }
        }
  }
  if (!std::isfinite(cost[static_cast<size_t>(to)]))
    throw std::runtime_error("findShortestPath: node " + std::to_string(to) + " is not connected to node " +
                             std::to_string(from) + " inside the muscle");
  std::vector<int> path;
  for (int a = to; a >= 0; a = previous[static_cast<size_t>(a)]) path.push_back(a);
  std::reverse(path.begin(), path.end());
  return path;
}

}  // namespace rbfmuscle
