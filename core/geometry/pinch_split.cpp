// SPDX-License-Identifier: Apache-2.0
#include "geometry/pinch_split.h"

#include <algorithm>
#include <numeric>
#include <utility>

#include "geometry/disjoint_sets.h"
#include "geometry/mesh_edges.h"

namespace rbfmuscle::detail {
namespace {

/// Sides of the mesh: side s = 3t + c is edge c of triangle t, running from corner c to
/// corner (c + 1) mod 3. `mate[s]` is the side it is paired with, or −1.
class SidePairing {
 public:
  explicit SidePairing(const TriangleMesh& mesh)
      : mesh_(mesh), edges_(buildEdgeTable(mesh)), mate_(3 * std::size_t(mesh.countTriangles()), -1) {
    const std::size_t E = edges_.vertices.size();
    first_.assign(E + 1, 0);
    for (int t = 0; t < mesh.countTriangles(); ++t)
      for (int c = 0; c < 3; ++c) ++first_[std::size_t(edges_.of_triangle(c, t)) + 1];
    std::partial_sum(first_.begin(), first_.end(), first_.begin());
    sides_.resize(mate_.size());
    std::vector<int> fill(first_.begin(), first_.end() - 1);
    for (int t = 0; t < mesh.countTriangles(); ++t)
      for (int c = 0; c < 3; ++c) sides_[std::size_t(fill[std::size_t(edges_.of_triangle(c, t))]++)] = 3 * t + c;
  }

  const EdgeTable& edges() const { return edges_; }
  const std::vector<int>& mates() const { return mate_; }

  /// Pairs the two sides of every consistently wound two-sided edge.
  void pairManifoldEdges() {
    for (std::size_t e = 0; e < edges_.vertices.size(); ++e)
      if (edges_.isConsistentManifold(int(e))) link(sides_[first_[e]], sides_[first_[e] + 1]);
  }

  /// Pairs the sides of non-manifold edge e by walking round one of its end vertices, then
  /// the other. @return false when neither walk pairs every side.
  bool pairNonManifoldEdge(int e) {
    const auto [lo, hi] = edges_.vertices[std::size_t(e)];
    return pairByWalkingRound(e, lo, hi) || pairByWalkingRound(e, hi, lo);
  }

 private:
  int vertexAt(int t, int c) const { return mesh_.triangles(c % 3, t); }

  void link(int s, int m) {
    mate_[std::size_t(s)] = m;
    mate_[std::size_t(m)] = s;
  }

  /// From each side of e whose triangle runs v → w, walks round v (crossing paired edges)
  /// to the triangle running w → v that closes the fan; pairs the two when every side is
  /// reached exactly once.
  bool pairByWalkingRound(int e, int v, int w) {
    std::vector<std::pair<int, int>> pairs;
    std::vector<int> closing;
    for (int i = first_[std::size_t(e)]; i < first_[std::size_t(e) + 1]; ++i) {
      const int s = sides_[std::size_t(i)];
      if (vertexAt(s / 3, s % 3) != v) continue;  // this side runs w → v
      int t = s / 3, end = -1;
      for (int step = 0; step <= mesh_.countTriangles() && end < 0; ++step) {
        int i_v = 0;
        while (vertexAt(t, i_v) != v) ++i_v;
        const int back = 3 * t + (i_v + 2) % 3;  // the side n → v of t, n its corner before v
        if (vertexAt(t, i_v + 2) == w) {
          end = back;
        } else {
          const int m = mate_[std::size_t(back)];
          if (m < 0) return false;  // another unpaired edge round v: the walk cannot go on
          t = m / 3;
        }
      }
      if (end < 0) return false;
      pairs.emplace_back(s, end);
      closing.push_back(end);
    }
    if (2 * pairs.size() != std::size_t(edges_.use_count[std::size_t(e)])) return false;
    std::sort(closing.begin(), closing.end());
    if (std::adjacent_find(closing.begin(), closing.end()) != closing.end()) return false;
    for (const auto& [s, m] : pairs) link(s, m);
    return true;
  }

  const TriangleMesh& mesh_;
  EdgeTable edges_;
  std::vector<int> mate_;
  std::vector<int> first_;  ///< sides of edge e are sides_[first_[e] .. first_[e+1])
  std::vector<int> sides_;
};

}  // namespace

PinchSplit splitPinches(TriangleMesh& mesh) {
  PinchSplit result;
  const int T = mesh.countTriangles(), V = mesh.countVertices();
  SidePairing pairing(mesh);
  const EdgeTable& edges = pairing.edges();
  pairing.pairManifoldEdges();
  bool splittable = true;
  std::vector<char> on_non_manifold_edge(std::size_t(V), 0);
  for (std::size_t e = 0; e < edges.vertices.size(); ++e) {
    const int uses = edges.use_count[e];
    if (uses > 2) {
      ++result.non_manifold_edges;
      on_non_manifold_edge[std::size_t(edges.vertices[e][0])] = 1;
      on_non_manifold_edge[std::size_t(edges.vertices[e][1])] = 1;
    } else if (!edges.isConsistentManifold(int(e))) {
      splittable = false;  // open or inconsistently wound: not a pinch
    }
  }
  for (std::size_t e = 0; e < edges.vertices.size() && splittable; ++e)
    if (edges.use_count[e] > 2)
      splittable = 2 * edges.forward_count[e] == edges.use_count[e] && pairing.pairNonManifoldEdge(int(e));
  if (!splittable) {
    result.unsplit_edges = result.non_manifold_edges;
    return result;
  }

  // Corners 3t + c round one vertex are in one fan when joined across paired edges.
  DisjointSets corners(3 * std::size_t(T));
  const std::vector<int>& mate = pairing.mates();
  for (int s = 0; s < 3 * T; ++s) {
    const int m = mate[std::size_t(s)];
    if (m < s) continue;  // each pair once (every side is paired here)
    const int t = s / 3, c = s % 3, u = m / 3, d = m % 3;
    // Side s runs a → b over corners c, c+1 of t; side m runs b → a over corners d, d+1 of u.
    corners.join(3 * t + c, 3 * u + (d + 1) % 3);
    corners.join(3 * t + (c + 1) % 3, 3 * u + d);
  }
  std::vector<int> index_of_fan(corners.size(), -1), fans(std::size_t(V), 0);
  std::vector<int>& copy_of = result.copy_of;
  Eigen::Matrix3Xi triangles = mesh.triangles;
  for (int k = 0; k < 3 * T; ++k) {
    const int root = corners.find(k), v = mesh.triangles(k % 3, k / 3);
    int& index = index_of_fan[std::size_t(root)];
    if (index < 0) {
      index = fans[std::size_t(v)]++ == 0 ? v : V + int(copy_of.size());
      if (index >= V) copy_of.push_back(v);
    }
    triangles(k % 3, k / 3) = index;
  }
  for (int v = 0; v < V; ++v)
    result.pinched_vertices += (fans[std::size_t(v)] > 1 && !on_non_manifold_edge[std::size_t(v)]) ? 1 : 0;
  result.vertex_copies = int(copy_of.size());
  if (copy_of.empty()) return result;
  result.at_pinch.assign(std::size_t(V) + copy_of.size(), 1);
  for (int v = 0; v < V; ++v) result.at_pinch[std::size_t(v)] = fans[std::size_t(v)] > 1 ? 1 : 0;
  Eigen::Matrix3Xd vertices(3, V + result.vertex_copies);
  vertices.leftCols(V) = mesh.vertices_mm;
  for (std::size_t i = 0; i < copy_of.size(); ++i) vertices.col(V + Eigen::Index(i)) = mesh.vertices_mm.col(copy_of[i]);
  mesh.vertices_mm = std::move(vertices);
  mesh.triangles = std::move(triangles);
  return result;
}

}  // namespace rbfmuscle::detail
