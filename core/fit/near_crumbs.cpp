// SPDX-License-Identifier: Apache-2.0
#include "fit/near_crumbs.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

#include "geometry/grid_pieces.h"
#include "geometry/iso_surface.h"

namespace rbfmuscle {

namespace {

/// f below which the outside far from the surface is found once (findNearCrumbs): any level
/// below 0 gives the same bubbles; this one keeps the band labelled at each level thin.
constexpr double kFarBelow = -1.0;

/// One axis of a kernel's cut-off box on the grid: its first node and exp(−α(xᵢ − ξ)²) there.
struct AxisFactors {
  std::int64_t first = 0;
  std::vector<double> factors;
};

AxisFactors calcAxisFactors(double centre, double alpha, double radius, double origin, double cell, std::int64_t count) {
  AxisFactors axis;
  axis.first = std::max<std::int64_t>(0, static_cast<std::int64_t>(std::ceil((centre - radius - origin) / cell)));
  const std::int64_t last = std::min<std::int64_t>(count - 1, static_cast<std::int64_t>(std::floor((centre + radius - origin) / cell)));
  for (std::int64_t i = axis.first; i <= last; ++i) {
    const double d = origin + cell * double(i) - centre;
    axis.factors.push_back(std::exp(-alpha * d * d));
  }
  return axis;
}

/// f at every node origin + cell·(i, j, k) of an n₀×n₁×n₂ grid (i fastest), kernel by kernel:
/// exp(−α|x − ξ|²) is the product of one factor per axis, so a kernel costs one product per
/// node of its cut-off box (φ ≥ ε, as the field's own sums), 20× fewer operations than a sum
/// per node over the kernels near it.
std::vector<double> calcGridValues(const GaussianField& field, const Eigen::Vector3d& origin, double cell,
                                   const std::array<std::int64_t, 3>& n) {
  const int K = field.getNumCentres();
  const double cutoff = field.getCutoff();
  std::vector<std::array<AxisFactors, 3>> boxes(static_cast<std::size_t>(K));
  for (int k = 0; k < K; ++k) {
    const double alpha = field.getShapes()[k], radius = field.getCutoffRadius(k);
    for (int a = 0; a < 3; ++a)
      boxes[std::size_t(k)][std::size_t(a)] =
          calcAxisFactors(field.getCentres()(a, k), alpha, radius, origin[a], cell, n[std::size_t(a)]);
  }
  std::vector<double> values(static_cast<std::size_t>(n[0] * n[1] * n[2]), field.getOffset());
  // Layers in parallel: each writes its own nodes, adding the kernels in index order.
#pragma omp parallel for schedule(dynamic, 4)
  for (std::int64_t z = 0; z < n[2]; ++z)
    for (int k = 0; k < K; ++k) {
      const auto& [bx, by, bz] = boxes[std::size_t(k)];
      if (z < bz.first || z >= bz.first + static_cast<std::int64_t>(bz.factors.size())) continue;
      const double lambda = field.getWeights()[k], fz = bz.factors[std::size_t(z - bz.first)];
      for (std::size_t j = 0; j < by.factors.size(); ++j) {
        const double fyz = fz * by.factors[j];
        if (fyz < cutoff) continue;
        double* row = values.data() + (z * n[1] + by.first + std::int64_t(j)) * n[0] + bx.first;
        for (std::size_t i = 0; i < bx.factors.size(); ++i) {
          const double phi = fyz * bx.factors[i];
          if (phi >= cutoff) row[i] += lambda * phi;
        }
      }
    }
  return values;
}

}  // namespace

Eigen::Matrix3Xd findNearCrumbs(const GaussianField& field, const Eigen::AlignedBox3d& box_mm, double cell_mm,
                                double margin) {
  if (!(margin >= 0.0)) throw std::invalid_argument("findNearCrumbs: margin " + std::to_string(margin) + "; expected ≥ 0");
  if (!(cell_mm > 0.0)) throw std::invalid_argument("findNearCrumbs: cell " + std::to_string(cell_mm) + " mm; expected > 0");
  checkIsoSurfaceGrid(box_mm, cell_mm);
  const std::array<std::int64_t, 3> n = countIsoSurfaceNodes(box_mm, cell_mm);
  const auto node = [&](std::int64_t v) {
    const std::array<std::int64_t, 3> ijk = splitNodeIndex(v, n);
    return Eigen::Vector3d(box_mm.min() + cell_mm * Eigen::Vector3d(double(ijk[0]), double(ijk[1]), double(ijk[2])));
  };
  const std::vector<double> values = calcGridValues(field, box_mm.min(), cell_mm, n);
  // Each stray piece's node nearest f = 0, with its distance below (a crumb) or above it (a bubble).
  std::vector<std::pair<double, std::int64_t>> found;
  std::vector<char> in_set(values.size());
  const auto addStrayPieces = [&](double level, double side, const std::vector<char>* outside) {
    // side +1: the pieces of {f > level} but the largest; side −1: those of {f < level} but the
    // `outside` nodes and what touches them (with no `outside`, the largest).
    for (std::size_t v = 0; v < values.size(); ++v)
      in_set[v] = side * (values[v] - level) > 0.0 && !(outside && (*outside)[v]);
    const GridPieces pieces = labelGridPieces(in_set, n);
    std::vector<char> stray(pieces.nodes_of_piece.size(), 1);
    if (!outside && !stray.empty()) stray[std::size_t(pieces.findLargest())] = 0;
    std::vector<std::int64_t> nearest(pieces.nodes_of_piece.size(), -1);
    for (std::size_t v = 0; v < values.size(); ++v) {
      const int p = pieces.piece_of_node[v];
      if (p < 0 || !stray[std::size_t(p)]) continue;
      if (outside && visitJoinedNodes(static_cast<std::int64_t>(v), n, [&](std::int64_t u) { return (*outside)[std::size_t(u)] != 0; })) {
        stray[std::size_t(p)] = 0;
        continue;
      }
      std::int64_t& best = nearest[std::size_t(p)];
      if (best < 0 || side * values[v] > side * values[std::size_t(best)]) best = static_cast<std::int64_t>(v);
    }
    for (std::size_t p = 0; p < nearest.size(); ++p)
      if (stray[p] && nearest[p] >= 0) found.emplace_back(-side * values[std::size_t(nearest[p])], nearest[p]);
  };
  // The outside far from the surface, {f < kFarBelow} where it reaches the grid's boundary, is
  // found once: a level's bubbles are then the pieces of the rest of {f < ε} (a band about the
  // surface, and any deep bubble) that do not touch it, and the outside's millions of nodes are
  // not labelled at every level.
  std::vector<char> far(values.size());
  for (std::size_t v = 0; v < values.size(); ++v) far[v] = values[v] < kFarBelow;
  const std::vector<char> far_outside = findReachedFromBoundary(far, n);
  const bool has_far_outside = std::find(far_outside.begin(), far_outside.end(), 1) != far_outside.end();
  const int levels = margin > 0.0 ? kNearCrumbLevels : 0;  // margin 0: islands and bubbles only
  for (int level = 0; level <= levels; ++level) {
    const double below = level < levels ? std::ldexp(margin, -level) : 0.0;
    addStrayPieces(-below, 1.0, nullptr);
    addStrayPieces(below, -1.0, has_far_outside ? &far_outside : nullptr);
  }
  std::sort(found.begin(), found.end());  // nearest f = 0 first; a node found at several levels once
  std::vector<std::int64_t> nodes;
  for (const auto& [distance, v] : found)
    if (std::find(nodes.begin(), nodes.end(), v) == nodes.end()) nodes.push_back(v);
  Eigen::Matrix3Xd result(3, static_cast<Eigen::Index>(nodes.size()));
  for (std::size_t p = 0; p < nodes.size(); ++p) result.col(static_cast<Eigen::Index>(p)) = node(nodes[p]);
  return result;
}

}  // namespace rbfmuscle
