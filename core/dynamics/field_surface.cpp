#include "dynamics/field_surface.h"

#include "geometry/iso_surface.h"
#include "rbf/field_on_grid.h"

#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

namespace rbfmuscle {

TriangleMesh extractFieldSurface(const GaussianField& field, const Eigen::AlignedBox3d& box_mm, double cell_mm,
                                 std::vector<std::uint64_t>* vertex_edges) {
  if (!(cell_mm > 0.0)) throw std::invalid_argument("extractFieldSurface: cell " + std::to_string(cell_mm) + " mm, expected > 0");
  if (box_mm.isEmpty()) throw std::invalid_argument("extractFieldSurface: empty box");
  RegularGrid grid;
  grid.origin_mm = box_mm.min();
  grid.cell_mm = cell_mm;
  grid.counts = countIsoSurfaceNodes(box_mm, cell_mm);
  std::vector<double> node_values;
  calcValuesOnGrid(field, grid, node_values);
  const auto lookup = [&grid, &node_values](const Eigen::Matrix3Xd& p, Eigen::VectorXd& v) {
    v.resize(p.cols());
    for (Eigen::Index j = 0; j < p.cols(); ++j) {
      const Eigen::Vector3d ijk = ((p.col(j) - grid.origin_mm) / grid.cell_mm).array().round();
      v(j) = node_values[static_cast<size_t>(grid.index(static_cast<std::int64_t>(ijk.x()), static_cast<std::int64_t>(ijk.y()),
                                                      static_cast<std::int64_t>(ijk.z())))];
    }
  };
  return extractIsoSurface(lookup, box_mm, cell_mm, nullptr, vertex_edges);
}

}  // namespace rbfmuscle
