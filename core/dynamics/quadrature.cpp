// SPDX-License-Identifier: Apache-2.0
#include "dynamics/quadrature.h"


#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace rbfmuscle {

namespace {

/// Grid nodes box.min + h (i, j, k), i < n(0), …, in (z, y, x) order.
Eigen::Matrix3Xd makeGridNodes(const Eigen::AlignedBox3d& box, double h, const Eigen::Array3i& n) {
  Eigen::Matrix3Xd nodes(3, static_cast<Eigen::Index>(n.prod()));
  Eigen::Index c = 0;
  for (int k = 0; k < n(2); ++k)
    for (int j = 0; j < n(1); ++j)
      for (int i = 0; i < n(0); ++i) nodes.col(c++) = box.min() + h * Eigen::Vector3d(i, j, k);
  return nodes;
}

Eigen::Array3i countNodes(const Eigen::AlignedBox3d& box, double h) {
  const Eigen::Array3d s = box.sizes().array() / h;
  return (s.ceil() + 1.0).cast<int>();
}

}  // namespace

Eigen::AlignedBox3d findBandBox(const GaussianField& field, double band_value, int coarse_cells) {
  if (coarse_cells < 4) throw std::invalid_argument("findBandBox: coarse_cells " + std::to_string(coarse_cells) + " < 4");
  const double c = -field.getOffset() - band_value;
  if (!(c > 0.0)) {
    throw std::invalid_argument("findBandBox: offset b = " + std::to_string(field.getOffset()) + " and band " +
                                std::to_string(band_value) + " give −b − β ≤ 0: the far field lies inside the band");
  }
  const int N = field.getNumCentres();
  Eigen::AlignedBox3d bound;
  for (int k = 0; k < N; ++k) {
    const double lambda = field.getWeights()(k);
    if (!(lambda * N > c)) continue;
    const double alpha = field.getShapes()(k);
    const double r = std::min(std::sqrt(std::log(lambda * N / c) / alpha), field.getCutoffRadius(k));
    const Eigen::Vector3d xi = field.getCentres().col(k);
    bound.extend(xi - Eigen::Vector3d::Constant(r));
    bound.extend(xi + Eigen::Vector3d::Constant(r));
  }
  if (bound.isEmpty()) throw std::invalid_argument("findBandBox: no centre has a weight reaching the band f > −β");
  const double h = bound.sizes().maxCoeff() / coarse_cells;
  const Eigen::Array3i n = countNodes(bound, h);
  const Eigen::Matrix3Xd nodes = makeGridNodes(bound, h, n);
  Eigen::VectorXd f;
  field.calcValues(nodes, f);
  Eigen::AlignedBox3d tight;
  for (Eigen::Index j = 0; j < nodes.cols(); ++j)
    if (f(j) > -band_value) tight.extend(nodes.col(j));
  if (tight.isEmpty()) throw std::invalid_argument("findBandBox: no grid node has f > −β (band too thin for the scan)");
  tight.extend(tight.min() - Eigen::Vector3d::Constant(h));
  tight.extend(tight.max() + Eigen::Vector3d::Constant(h));
  return tight;
}

Quadrature makeQuadrature(const GaussianField& field, const QuadratureSettings& settings) {
  if (settings.target_count < 8) {
    throw std::invalid_argument("makeQuadrature: target_count " + std::to_string(settings.target_count) + " < 8");
  }
  if (!(settings.band_value >= 0.0) || !std::isfinite(settings.band_value)) {
    throw std::invalid_argument("makeQuadrature: band_value " + std::to_string(settings.band_value) +
                                " must be finite and >= 0");
  }
  const Eigen::AlignedBox3d box = findBandBox(field, settings.band_value, settings.coarse_cells);
  // Estimate the band volume by a scan at 24 cells on the longest side, then choose h.
  const double h_scan = box.sizes().maxCoeff() / 24.0;
  const Eigen::Matrix3Xd scan = makeGridNodes(box, h_scan, countNodes(box, h_scan));
  Eigen::VectorXd f;
  field.calcValues(scan, f);
  const Eigen::Index inside = (f.array() > -settings.band_value).count();
  const double band_volume = std::max<double>(1.0, static_cast<double>(inside)) * h_scan * h_scan * h_scan;
  const double h = std::cbrt(band_volume / settings.target_count);

  Quadrature q;
  q.cell_mm = h;
  q.box_mm = box;
  const Eigen::Matrix3Xd nodes = makeGridNodes(box, h, countNodes(box, h));
  field.calcValues(nodes, f);
  const Eigen::Index kept = (f.array() > -settings.band_value).count();
  q.points_mm.resize(3, kept);
  Eigen::Index c = 0;
  for (Eigen::Index j = 0; j < nodes.cols(); ++j)
    if (f(j) > -settings.band_value) q.points_mm.col(c++) = nodes.col(j);
  q.weights_mm3 = Eigen::VectorXd::Constant(kept, h * h * h);
  return q;
}

}  // namespace rbfmuscle
