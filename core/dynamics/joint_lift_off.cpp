// SPDX-License-Identifier: Apache-2.0
#include "dynamics/joint_lift_off.h"

#include "dynamics/smoothstep.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

namespace rbfmuscle {

namespace {

double cross(const Eigen::Vector2d& a, const Eigen::Vector2d& b) { return a.x() * b.y() - a.y() * b.x(); }

/// The convex hull's vertices, counter-clockwise (Andrew's monotone chain).
std::vector<Eigen::Vector2d> findHull(std::vector<Eigen::Vector2d> p) {
  std::sort(p.begin(), p.end(), [](const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
    return a.x() < b.x() || (a.x() == b.x() && a.y() < b.y());
  });
  std::vector<Eigen::Vector2d> hull(2 * p.size());
  size_t k = 0;
  for (size_t i = 0; i < p.size(); ++i) {  // lower chain
    while (k >= 2 && cross(hull[k - 1] - hull[k - 2], p[i] - hull[k - 2]) <= 0.0) --k;
    hull[k++] = p[i];
  }
  for (size_t i = p.size() - 1, lower = k + 1; i-- > 0;) {  // upper chain
    while (k >= lower && cross(hull[k - 1] - hull[k - 2], p[i] - hull[k - 2]) <= 0.0) --k;
    hull[k++] = p[i];
  }
  hull.resize(k > 1 ? k - 1 : k);
  return hull;
}

/// The convex hull of 2-D points (2×m) and the origin, the axis they are seen along.
/// @throws std::invalid_argument for non-finite points, naming `what`.
std::vector<Eigen::Vector2d> findHullWithAxis(const Eigen::Matrix2Xd& points, const char* what) {
  if (!points.allFinite()) throw std::invalid_argument(std::string(what) + ": the points must be finite");
  std::vector<Eigen::Vector2d> all(static_cast<size_t>(points.cols()) + 1, Eigen::Vector2d::Zero());
  for (Eigen::Index j = 0; j < points.cols(); ++j) all[static_cast<size_t>(j)] = points.col(j);
  return findHull(all);
}

Eigen::Matrix<double, 2, 3> planeBasis(const Eigen::Vector3d& axis) {
  const Eigen::Vector3d u = axis.unitOrthogonal(), v = axis.cross(u);
  Eigen::Matrix<double, 2, 3> basis;
  basis.row(0) = u.transpose();
  basis.row(1) = v.transpose();
  return basis;
}

}  // namespace

Eigen::VectorXd calcStringDistances(const Eigen::Matrix2Xd& points) {
  const std::vector<Eigen::Vector2d> hull = findHullWithAxis(points, "calcStringDistances");
  const Eigen::Index m = points.cols();
  Eigen::VectorXd s(m);
  for (Eigen::Index j = 0; j < m; ++j) {
    const double r = points.col(j).norm();
    s[j] = r;
    if (!(r > 0.0) || hull.size() < 3) continue;
    // The ray leaves the hull through the nearest edge it faces: edge e holds n·x ≤ c, the
    // origin inside (c ≥ 0), so the exit is at t = c / (n·d) over the edges with n·d > 0.
    const Eigen::Vector2d d = points.col(j) / r;
    double exit = std::numeric_limits<double>::infinity();
    for (size_t e = 0; e < hull.size(); ++e) {
      const Eigen::Vector2d a = hull[e], b = hull[(e + 1) % hull.size()];
      const Eigen::Vector2d n(b.y() - a.y(), a.x() - b.x());  // outward for a counter-clockwise hull
      const double facing = n.dot(d);
      if (facing > 0.0) exit = std::min(exit, std::max(n.dot(a), 0.0) / facing);
    }
    if (std::isfinite(exit)) s[j] = std::max(exit, r);
  }
  return s;
}

Eigen::VectorXd calcStringSags(const Eigen::Matrix2Xd& points) {
  const std::vector<Eigen::Vector2d> hull = findHullWithAxis(points, "calcStringSags");
  const Eigen::Index m = points.cols();
  Eigen::VectorXd sags = Eigen::VectorXd::Zero(m);
  if (hull.size() < 3) return sags;
  for (Eigen::Index j = 0; j < m; ++j) {
    double nearest = std::numeric_limits<double>::infinity();
    for (size_t e = 0; e < hull.size(); ++e) {
      const Eigen::Vector2d a = hull[e], b = hull[(e + 1) % hull.size()];
      if (a.isZero(0.0) || b.isZero(0.0)) continue;  // a side through the axis: not the string
      const Eigen::Vector2d ab = b - a;
      const double t = std::clamp((points.col(j) - a).dot(ab) / ab.squaredNorm(), 0.0, 1.0);
      nearest = std::min(nearest, (a + t * ab - points.col(j)).norm());
    }
    if (std::isfinite(nearest)) sags[j] = nearest;
  }
  return sags;
}

namespace {

/// A fibre now and at rest seen along the axis (2-D, about the centre), with the plane's basis.
struct AxisView {
  Eigen::Matrix<double, 2, 3> basis;
  Eigen::Matrix2Xd now, rest;
};

AxisView viewAlongAxis(const char* what, const Eigen::Matrix3Xd& now_mm, const Eigen::Matrix3Xd& rest_mm,
                       const Eigen::Vector3d& centre_mm, const Eigen::Vector3d& axis, double fade_mm) {
  if (now_mm.cols() != rest_mm.cols())
    throw std::invalid_argument(std::string(what) + ": the points now and at rest differ in number");
  if (!(std::abs(axis.norm() - 1.0) < 1e-9) || !(fade_mm > 0.0) || !centre_mm.allFinite())
    throw std::invalid_argument(std::string(what) + ": need a unit axis, a finite centre and fade_mm > 0");
  const Eigen::Matrix<double, 2, 3> basis = planeBasis(axis);
  return AxisView{basis, basis * (now_mm.colwise() - centre_mm), basis * (rest_mm.colwise() - centre_mm)};
}

}  // namespace

Eigen::Matrix3Xd calcSagRisesSinceRest(const Eigen::Matrix3Xd& now_mm, const Eigen::Matrix3Xd& rest_mm,
                                       const Eigen::Vector3d& centre_mm, const Eigen::Vector3d& axis, double fade_mm) {
  const AxisView view = viewAlongAxis("calcSagRisesSinceRest", now_mm, rest_mm, centre_mm, axis, fade_mm);
  const Eigen::VectorXd sags = calcStringSags(view.now), sags0 = calcStringSags(view.rest);
  Eigen::Matrix3Xd rises = Eigen::Matrix3Xd::Zero(3, now_mm.cols());
  for (Eigen::Index j = 0; j < now_mm.cols(); ++j) {
    const double r = view.now.col(j).norm();
    if (!(r > 0.0) || !(sags[j] > sags0[j])) continue;
    rises.col(j) = calcSmoothstep(r / fade_mm) * (sags[j] - sags0[j]) / r * (view.basis.transpose() * view.now.col(j));
  }
  return rises;
}

Eigen::Matrix3Xd calcLiftOffRisesSinceRest(const Eigen::Matrix3Xd& now_mm, const Eigen::Matrix3Xd& rest_mm,
                                           const Eigen::Vector3d& centre_mm, const Eigen::Vector3d& axis,
                                           double fade_mm) {
  const AxisView view = viewAlongAxis("calcLiftOffRisesSinceRest", now_mm, rest_mm, centre_mm, axis, fade_mm);
  const Eigen::VectorXd s = calcStringDistances(view.now), s0 = calcStringDistances(view.rest);
  Eigen::Matrix3Xd rises = Eigen::Matrix3Xd::Zero(3, now_mm.cols());
  for (Eigen::Index j = 0; j < now_mm.cols(); ++j) {
    const double r = view.now.col(j).norm();
    if (!(r > 0.0) || !(s0[j] > 0.0) || !(s[j] > s0[j])) continue;
    rises.col(j) = calcSmoothstep(s0[j] / fade_mm) * (s[j] - s0[j]) / r *
                   (view.basis.transpose() * view.now.col(j));  // s − s₀ along the ray
  }
  return rises;
}

}  // namespace rbfmuscle
