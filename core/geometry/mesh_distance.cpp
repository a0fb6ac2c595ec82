// SPDX-License-Identifier: Apache-2.0
#include "geometry/mesh_distance.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

#include "geometry/mesh_edges.h"

namespace rbfmuscle {
namespace {

constexpr int kLeafSize = 4;

/// Closest point to p on segment [a, b]; t ∈ [0, 1] returned through `t`.
Eigen::Vector3d closestOnSegment(const Eigen::Vector3d& p, const Eigen::Vector3d& a,
                                 const Eigen::Vector3d& b, double& t) {
  const Eigen::Vector3d ab = b - a;
  const double len_sq = ab.squaredNorm();
  t = len_sq > 0.0 ? std::clamp((p - a).dot(ab) / len_sq, 0.0, 1.0) : 0.0;
  return a + t * ab;
}

}  // namespace

MeshDistance::MeshDistance(TriangleMesh mesh, bool signs) : mesh_(std::move(mesh)), signs_(signs) {
  const int T = mesh_.countTriangles(), V = mesh_.countVertices();
  if (T == 0) throw MeshError("MeshDistance: mesh has no triangles");
  if (!mesh_.vertices_mm.allFinite()) throw MeshError("MeshDistance: mesh has non-finite vertices");
  if (mesh_.triangles.minCoeff() < 0 || mesh_.triangles.maxCoeff() >= V)
    throw MeshError("MeshDistance: triangle index out of range 0.." + std::to_string(V - 1));

  // Pseudo-normals.
  face_normals_.setZero(3, T);
  vertex_normals_.setZero(3, V);
  detail::EdgeTable edges;
  if (signs_) edges = detail::buildEdgeTable(mesh_);
  triangle_edges_ = edges.of_triangle;
  edge_normals_.assign(edges.vertices.size(), Eigen::Vector3d::Zero());
  for (int t = 0; t < T; ++t) {
    const Eigen::Vector3d n =
        (mesh_.getCorner(t, 1) - mesh_.getCorner(t, 0)).cross(mesh_.getCorner(t, 2) - mesh_.getCorner(t, 0));
    const double norm = n.norm();
    if (!(norm > 0.0)) continue;
    face_normals_.col(t) = n / norm;  // also marks degenerate triangles for the queries
    if (!signs_) continue;
    for (int c = 0; c < 3; ++c) {
      edge_normals_[std::size_t(triangle_edges_(c, t))] += face_normals_.col(t);
      const Eigen::Vector3d u = mesh_.getCorner(t, (c + 1) % 3) - mesh_.getCorner(t, c);
      const Eigen::Vector3d w = mesh_.getCorner(t, (c + 2) % 3) - mesh_.getCorner(t, c);
      const double angle = std::atan2(u.cross(w).norm(), u.dot(w));
      vertex_normals_.col(mesh_.triangles(c, t)) += angle * face_normals_.col(t);
    }
  }

  // Tree.
  std::vector<Eigen::Vector3d> centroids(std::size_t(T), Eigen::Vector3d::Zero());
  for (int t = 0; t < T; ++t)
    centroids[std::size_t(t)] = (mesh_.getCorner(t, 0) + mesh_.getCorner(t, 1) + mesh_.getCorner(t, 2)) / 3.0;
  order_.resize(std::size_t(T));
  for (int t = 0; t < T; ++t) order_[std::size_t(t)] = t;
  nodes_.reserve(std::size_t(2 * (T / kLeafSize + 1)));
  buildNode(0, T, centroids);
  corners_.resize(std::size_t(T));
  for (int s = 0; s < T; ++s)
    for (int c = 0; c < 3; ++c) corners_[std::size_t(s)][std::size_t(c)] = mesh_.getCorner(order_[std::size_t(s)], c);
}

int MeshDistance::buildNode(int begin, int end, std::vector<Eigen::Vector3d>& centroids) {
  const int id = int(nodes_.size());
  nodes_.emplace_back();
  Eigen::AlignedBox3d box, centre_box;
  for (int s = begin; s < end; ++s) {
    const int t = order_[std::size_t(s)];
    for (int c = 0; c < 3; ++c) box.extend(mesh_.getCorner(t, c));
    centre_box.extend(centroids[std::size_t(t)]);
  }
  nodes_[std::size_t(id)].box = box;
  if (end - begin <= kLeafSize) {
    nodes_[std::size_t(id)].first = begin;
    nodes_[std::size_t(id)].count = end - begin;
    return id;
  }
  int axis = 0;
  centre_box.sizes().maxCoeff(&axis);
  const int mid = (begin + end) / 2;
  std::nth_element(order_.begin() + begin, order_.begin() + mid, order_.begin() + end,
                   [&](int a, int b) {
                     const double ca = centroids[std::size_t(a)][axis], cb = centroids[std::size_t(b)][axis];
                     return ca < cb || (ca == cb && a < b);
                   });
  const int left = buildNode(begin, mid, centroids);
  const int right = buildNode(mid, end, centroids);
  nodes_[std::size_t(id)].left = left;
  nodes_[std::size_t(id)].right = right;
  return id;
}

MeshDistance::Hit MeshDistance::findHit(const Eigen::Vector3d& p, double max_distance_sq) const {
  Hit best{Eigen::Vector3d::Zero(), max_distance_sq, -1, 0};
  // Depth-first, nearer child first; each entry carries its box's squared distance.
  std::pair<int, double> stack[128];
  int top = 0;
  stack[top++] = {0, nodes_[0].box.squaredExteriorDistance(p)};
  while (top > 0) {
    const auto [id, box_sq] = stack[--top];
    if (box_sq >= best.distance_sq) continue;
    const Node& node = nodes_[std::size_t(id)];
    if (node.count == 0) {
      const double dl = nodes_[std::size_t(node.left)].box.squaredExteriorDistance(p);
      const double dr = nodes_[std::size_t(node.right)].box.squaredExteriorDistance(p);
      if (dl <= dr) {
        stack[top++] = {node.right, dr};
        stack[top++] = {node.left, dl};
      } else {
        stack[top++] = {node.left, dl};
        stack[top++] = {node.right, dr};
      }
      continue;
    }
    for (int s = node.first; s < node.first + node.count; ++s) {
      const int t = order_[std::size_t(s)];
      const auto& corners = corners_[std::size_t(s)];
      const Eigen::Vector3d& a = corners[0];
      const Eigen::Vector3d& b = corners[1];
      const Eigen::Vector3d& c = corners[2];
      Eigen::Vector3d q = a;
      int feature = 0;
      if (face_normals_.col(t).isZero(0.0)) {
        // Degenerate triangle: nearest of its three sides.
        double best_sq = std::numeric_limits<double>::infinity();
        for (int e = 0; e < 3; ++e) {
          double u = 0.0;
          const Eigen::Vector3d x = closestOnSegment(p, corners[std::size_t(e)], corners[std::size_t((e + 1) % 3)], u);
          if ((p - x).squaredNorm() < best_sq) {
            best_sq = (p - x).squaredNorm();
            q = x;
            feature = u <= 0.0 ? 4 + e : u >= 1.0 ? 4 + (e + 1) % 3 : 1 + e;
          }
        }
      } else {
        // Ericson, Real-Time Collision Detection §5.1.5, with the Voronoi region kept.
        const Eigen::Vector3d ab = b - a, ac = c - a, ap = p - a;
        const double d1 = ab.dot(ap), d2 = ac.dot(ap);
        const Eigen::Vector3d bp = p - b;
        const double d3 = ab.dot(bp), d4 = ac.dot(bp);
        const Eigen::Vector3d cp = p - c;
        const double d5 = ab.dot(cp), d6 = ac.dot(cp);
        const double vc = d1 * d4 - d3 * d2, vb = d5 * d2 - d1 * d6, va = d3 * d6 - d5 * d4;
        if (d1 <= 0.0 && d2 <= 0.0) {
          q = a, feature = 4;
        } else if (d3 >= 0.0 && d4 <= d3) {
          q = b, feature = 5;
        } else if (d6 >= 0.0 && d5 <= d6) {
          q = c, feature = 6;
        } else if (vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0) {
          q = a + (d1 / (d1 - d3)) * ab, feature = 1;
        } else if (vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0) {
          q = a + (d2 / (d2 - d6)) * ac, feature = 3;
        } else if (va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0) {
          q = b + ((d4 - d3) / ((d4 - d3) + (d5 - d6))) * (c - b), feature = 2;
        } else {
          const double denom = 1.0 / (va + vb + vc);
          q = a + ab * (vb * denom) + ac * (vc * denom), feature = 0;
        }
      }
      const double d_sq = (p - q).squaredNorm();
      if (d_sq < best.distance_sq || (d_sq == best.distance_sq && t < best.triangle))
        best = Hit{q, d_sq, t, feature};
    }
  }
  return best;
}

double MeshDistance::signOf(const Eigen::Vector3d& p, const Hit& hit) const {
  Eigen::Vector3d n;
  if (hit.feature == 0) {
    n = face_normals_.col(hit.triangle);
  } else if (hit.feature <= 3) {
    n = edge_normals_[std::size_t(triangle_edges_(hit.feature - 1, hit.triangle))];
  } else {
    n = vertex_normals_.col(mesh_.triangles(hit.feature - 4, hit.triangle));
  }
  const double side = (p - hit.point).dot(n);
  return side < 0.0 ? -1.0 : side > 0.0 ? 1.0 : 0.0;
}

ClosestPoint MeshDistance::findClosestPoint(const Eigen::Vector3d& p_mm) const {
  const Hit hit = findHit(p_mm);
  return ClosestPoint{hit.point, hit.triangle, std::sqrt(hit.distance_sq)};
}

SignedClosestPoint MeshDistance::findSignedClosestPoint(const Eigen::Vector3d& p_mm, double max_distance_mm) const {
  requireSigns();
  const Hit hit = findHit(p_mm, max_distance_mm * max_distance_mm);
  SignedClosestPoint c;
  if (hit.triangle < 0) {
    c.distance_mm = c.signed_distance_mm = std::numeric_limits<double>::infinity();
    return c;
  }
  c.point_mm = hit.point;
  c.triangle = hit.triangle;
  c.distance_mm = std::sqrt(hit.distance_sq);
  c.signed_distance_mm = signOf(p_mm, hit) * c.distance_mm;
  return c;
}

double MeshDistance::calcUnsignedDistance(const Eigen::Vector3d& p_mm) const {
  return std::sqrt(findHit(p_mm).distance_sq);
}

double MeshDistance::calcUnsignedDistanceWithin(const Eigen::Vector3d& p_mm, double max_distance_mm) const {
  const Hit hit = findHit(p_mm, max_distance_mm * max_distance_mm);
  return hit.triangle < 0 ? std::numeric_limits<double>::infinity() : std::sqrt(hit.distance_sq);
}

void MeshDistance::requireSigns() const {
  if (!signs_) throw MeshError("MeshDistance: a signed query on a tree built without signs");
}

double MeshDistance::calcSignedDistance(const Eigen::Vector3d& p_mm) const {
  requireSigns();
  const Hit hit = findHit(p_mm);
  return signOf(p_mm, hit) * std::sqrt(hit.distance_sq);
}

bool MeshDistance::isInside(const Eigen::Vector3d& p_mm) const {
  return calcSignedDistance(p_mm) < 0.0;
}

Eigen::VectorXd MeshDistance::calcUnsignedDistances(const Eigen::Matrix3Xd& points_mm) const {
  Eigen::VectorXd out(points_mm.cols());
  const long n = long(points_mm.cols());
#pragma omp parallel for schedule(dynamic, 256)
  for (long i = 0; i < n; ++i) out[i] = calcUnsignedDistance(points_mm.col(i));
  return out;
}

Eigen::VectorXd MeshDistance::calcSignedDistances(const Eigen::Matrix3Xd& points_mm) const {
  Eigen::VectorXd out(points_mm.cols());
  const long n = long(points_mm.cols());
#pragma omp parallel for schedule(dynamic, 256)
  for (long i = 0; i < n; ++i) out[i] = calcSignedDistance(points_mm.col(i));
  return out;
}

Eigen::Array<bool, Eigen::Dynamic, 1> MeshDistance::calcInside(const Eigen::Matrix3Xd& points_mm) const {
  const Eigen::VectorXd s = calcSignedDistances(points_mm);
  return s.array() < 0.0;
}

}  // namespace rbfmuscle
