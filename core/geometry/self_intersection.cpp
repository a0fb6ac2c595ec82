// SPDX-License-Identifier: Apache-2.0
#include "geometry/self_intersection.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <unordered_map>

namespace rbfmuscle {
namespace {

/// Projects the three points on `axis`: [lo, hi].
void project(const Eigen::Vector3d& axis, const Eigen::Vector3d& p0, const Eigen::Vector3d& p1,
             const Eigen::Vector3d& p2, double& lo, double& hi) {
  const double a = axis.dot(p0), b = axis.dot(p1), c = axis.dot(p2);
  lo = std::min({a, b, c});
  hi = std::max({a, b, c});
}

}  // namespace

bool trianglesIntersect(const Eigen::Vector3d& a0, const Eigen::Vector3d& a1, const Eigen::Vector3d& a2,
                        const Eigen::Vector3d& b0, const Eigen::Vector3d& b1, const Eigen::Vector3d& b2,
                        double gap) {
  const std::array<Eigen::Vector3d, 3> ea = {a1 - a0, a2 - a1, a0 - a2};
  const std::array<Eigen::Vector3d, 3> eb = {b1 - b0, b2 - b1, b0 - b2};
  const Eigen::Vector3d na = ea[0].cross(ea[1]), nb = eb[0].cross(eb[1]);
  std::array<Eigen::Vector3d, 17> axes;
  int count = 0;
  axes[count++] = na;
  axes[count++] = nb;
  for (const Eigen::Vector3d& u : ea)
    for (const Eigen::Vector3d& v : eb) axes[count++] = u.cross(v);
  for (const Eigen::Vector3d& u : ea) axes[count++] = na.cross(u);
  for (const Eigen::Vector3d& v : eb) axes[count++] = nb.cross(v);
  for (int k = 0; k < count; ++k) {
    const double length = axes[static_cast<std::size_t>(k)].norm();
    if (!(length > 1e-300)) continue;  // parallel edges or a degenerate triangle: no axis
    const Eigen::Vector3d axis = axes[static_cast<std::size_t>(k)] / length;
    double alo, ahi, blo, bhi;
    project(axis, a0, a1, a2, alo, ahi);
    project(axis, b0, b1, b2, blo, bhi);
    if (ahi < blo - gap || bhi < alo - gap) return false;
  }
  return true;
}

SelfIntersections findSelfIntersections(const TriangleMesh& mesh, int max_pairs) {
  SelfIntersections found;
  const int T = mesh.countTriangles();
  if (T < 2) return found;
  const Eigen::AlignedBox3d box = mesh.calcBoundingBox();
  const double extent = box.sizes().maxCoeff();
  if (!(extent > 0) || !std::isfinite(extent)) return found;
  const double gap = 1e-9 * extent;
  // About one triangle per cell, at most 128 cells a side.
  const double volume = std::max(box.sizes().prod(), extent * extent * extent * 1e-9);
  const double cell = std::max(std::cbrt(volume / T), extent / 128.0);
  const Eigen::Vector3d origin = box.min();
  const auto cellOf = [&](double x, int axis) {
    return std::clamp(static_cast<long long>(std::floor((x - origin[axis]) / cell)), 0LL, 1LL << 20);
  };
  const auto key = [](long long i, long long j, long long k) { return (i << 42) | (j << 21) | k; };
  std::unordered_map<long long, std::vector<int>> grid;
  std::vector<Eigen::AlignedBox3d> boxes(static_cast<std::size_t>(T));
  for (int t = 0; t < T; ++t) {
    Eigen::AlignedBox3d& b = boxes[static_cast<std::size_t>(t)];
    for (int c = 0; c < 3; ++c) b.extend(mesh.getCorner(t, c));
    for (long long i = cellOf(b.min().x(), 0); i <= cellOf(b.max().x(), 0); ++i)
      for (long long j = cellOf(b.min().y(), 1); j <= cellOf(b.max().y(), 1); ++j)
        for (long long k = cellOf(b.min().z(), 2); k <= cellOf(b.max().z(), 2); ++k) grid[key(i, j, k)].push_back(t);
  }
  // Each pair is tested once, in the cell of the lower corner of the overlap of its boxes.
  for (const auto& [cell_key, members] : grid) {
    for (std::size_t x = 0; x < members.size(); ++x) {
      const int s = members[x];
      for (std::size_t y = x + 1; y < members.size(); ++y) {
        const int t = members[y];
        const Eigen::AlignedBox3d& bs = boxes[static_cast<std::size_t>(s)];
        const Eigen::AlignedBox3d& bt = boxes[static_cast<std::size_t>(t)];
        if ((bs.min().array() > bt.max().array() + gap).any() || (bt.min().array() > bs.max().array() + gap).any())
          continue;
        const Eigen::Vector3d low = bs.min().cwiseMax(bt.min());
        if (key(cellOf(low.x(), 0), cellOf(low.y(), 1), cellOf(low.z(), 2)) != cell_key) continue;
        bool shared = false;
        for (int a = 0; a < 3 && !shared; ++a)
          for (int b = 0; b < 3; ++b) shared = shared || mesh.triangles(a, s) == mesh.triangles(b, t);
        if (shared) continue;
        if (!trianglesIntersect(mesh.getCorner(s, 0), mesh.getCorner(s, 1), mesh.getCorner(s, 2), mesh.getCorner(t, 0),
                                mesh.getCorner(t, 1), mesh.getCorner(t, 2), gap))
          continue;
        ++found.pairs;
        if (found.examples.size() < 3) found.examples.emplace_back(std::min(s, t), std::max(s, t));
        if (found.pairs >= max_pairs) {
          found.capped = true;
          return found;
        }
      }
    }
  }
  std::sort(found.examples.begin(), found.examples.end());
  return found;
}

}  // namespace rbfmuscle
