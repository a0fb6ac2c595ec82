// SPDX-License-Identifier: Apache-2.0
#include "geometry/winding_number.h"

#include <algorithm>
#include <cmath>
#include <numeric>

#include "geometry/mesh_error.h"

namespace rbfmuscle {
namespace {

constexpr int kLeafSize = 8;
/// The query stack: a depth-first descent holds at most one pending sibling per level. The
/// median split halves every node, so the depth is ⌈log₂ T⌉ and 64 levels hold any mesh.
constexpr int kMaxDepth = 64;
constexpr double kFourPi = 4.0 * 3.14159265358979323846;

}  // namespace

WindingNumber::WindingNumber(TriangleMesh mesh, double accuracy_beta) : mesh_(std::move(mesh)), beta_(accuracy_beta) {
  const int T = mesh_.countTriangles(), V = mesh_.countVertices();
  if (T == 0) throw MeshError("WindingNumber: mesh has no triangles");
  if (!mesh_.vertices_mm.allFinite()) throw MeshError("WindingNumber: mesh has non-finite vertices");
  if (mesh_.triangles.minCoeff() < 0 || mesh_.triangles.maxCoeff() >= V)
    throw MeshError("WindingNumber: triangle index out of range 0.." + std::to_string(V - 1));
  if (!(beta_ > 1.0)) throw MeshError("WindingNumber: accuracy beta must be > 1");
  std::vector<Eigen::Vector3d> centroids(static_cast<std::size_t>(T));
  for (int t = 0; t < T; ++t)
    centroids[std::size_t(t)] = (mesh_.getCorner(t, 0) + mesh_.getCorner(t, 1) + mesh_.getCorner(t, 2)) / 3.0;
  order_.resize(std::size_t(T));
  std::iota(order_.begin(), order_.end(), 0);
  nodes_.reserve(std::size_t(2 * (T / kLeafSize + 1)));
  buildNode(0, T, 0, centroids);
}

int WindingNumber::buildNode(int begin, int end, int depth, const std::vector<Eigen::Vector3d>& centroids) {
  if (depth >= kMaxDepth) throw MeshError("WindingNumber: tree deeper than 64 levels");
  depth_ = std::max(depth_, depth);
  const int id = static_cast<int>(nodes_.size());
  nodes_.emplace_back();
  Node node;
  double area_sum = 0.0;
  Eigen::Vector3d weighted = Eigen::Vector3d::Zero(), plain = Eigen::Vector3d::Zero();
  Eigen::AlignedBox3d centroid_box;
  for (int s = begin; s < end; ++s) {
    const int t = order_[std::size_t(s)];
    const Eigen::Vector3d a = mesh_.getCorner(t, 0);
    const Eigen::Vector3d area_vector = 0.5 * (mesh_.getCorner(t, 1) - a).cross(mesh_.getCorner(t, 2) - a);
    const double area = area_vector.norm();
    node.area_vector += area_vector;
    area_sum += area;
    weighted += area * centroids[std::size_t(t)];
    plain += centroids[std::size_t(t)];
    centroid_box.extend(centroids[std::size_t(t)]);
  }
  node.centre = area_sum > 0.0 ? (weighted / area_sum).eval() : (plain / double(end - begin)).eval();
  for (int s = begin; s < end; ++s)
    for (int c = 0; c < 3; ++c)
      node.radius = std::max(node.radius, (mesh_.getCorner(order_[std::size_t(s)], c) - node.centre).norm());
  if (end - begin <= kLeafSize) {
    node.first = begin;
    node.count = end - begin;
  } else {
    int axis = 0;
    centroid_box.sizes().maxCoeff(&axis);
    const int mid = begin + (end - begin) / 2;
    std::nth_element(order_.begin() + begin, order_.begin() + mid, order_.begin() + end, [&](int x, int y) {
      const double cx = centroids[std::size_t(x)][axis], cy = centroids[std::size_t(y)][axis];
      return cx != cy ? cx < cy : x < y;
    });
    node.left = buildNode(begin, mid, depth + 1, centroids);
    node.right = buildNode(mid, end, depth + 1, centroids);
  }
  nodes_[std::size_t(id)] = node;
  return id;
}

double WindingNumber::calcTriangleSolidAngle(int t, const Eigen::Vector3d& p) const {
  const Eigen::Vector3d a = mesh_.getCorner(t, 0) - p, b = mesh_.getCorner(t, 1) - p, c = mesh_.getCorner(t, 2) - p;
  const double la = a.norm(), lb = b.norm(), lc = c.norm();
  const double numerator = a.dot(b.cross(c));
  const double denominator = la * lb * lc + a.dot(b) * lc + b.dot(c) * la + c.dot(a) * lb;
  if (numerator == 0.0 && denominator == 0.0) return 0.0;  // p on the triangle's plane, on it or a corner
  return 2.0 * std::atan2(numerator, denominator);
}

double WindingNumber::calcExactWindingNumber(const Eigen::Vector3d& p_mm) const {
  double sum = 0.0;
  for (int t = 0; t < mesh_.countTriangles(); ++t) sum += calcTriangleSolidAngle(t, p_mm);
  return sum / kFourPi;
}

double WindingNumber::calcWindingNumber(const Eigen::Vector3d& p_mm) const {
  int stack[kMaxDepth + 2];
  int top = 0;
  stack[top++] = 0;
  double sum = 0.0;
  // Each node is pushed at most once, so the loop ends after at most nodes_.size() turns.
  while (top > 0) {
    const Node& node = nodes_[std::size_t(stack[--top])];
    const Eigen::Vector3d d = node.centre - p_mm;
    const double distance = d.norm();
    if (distance > beta_ * node.radius) {
      sum += node.area_vector.dot(d) / (distance * distance * distance);
    } else if (node.count > 0) {
      for (int s = node.first; s < node.first + node.count; ++s) sum += calcTriangleSolidAngle(order_[std::size_t(s)], p_mm);
    } else {
      stack[top++] = node.right;
      stack[top++] = node.left;
    }
  }
  return sum / kFourPi;
}

bool WindingNumber::isInside(const Eigen::Vector3d& p_mm) const {
  const double w = calcWindingNumber(p_mm);
  if (std::abs(w - 0.5) >= kAmbiguousWinding) return w > 0.5;
  return calcExactWindingNumber(p_mm) > 0.5;
}

Eigen::Array<bool, Eigen::Dynamic, 1> WindingNumber::calcInside(const Eigen::Matrix3Xd& points_mm) const {
  const long n = static_cast<long>(points_mm.cols());
  Eigen::Array<bool, Eigen::Dynamic, 1> out(n);
#pragma omp parallel for schedule(dynamic, 256)
  for (long i = 0; i < n; ++i) out[i] = isInside(points_mm.col(i));
  return out;
}

Eigen::VectorXd WindingNumber::calcWindingNumbers(const Eigen::Matrix3Xd& points_mm) const {
  const long n = static_cast<long>(points_mm.cols());
  Eigen::VectorXd out(n);
#pragma omp parallel for schedule(static)
  for (long i = 0; i < n; ++i) out[i] = calcWindingNumber(points_mm.col(i));
  return out;
}

}  // namespace rbfmuscle
