// SPDX-License-Identifier: Apache-2.0
#include "geometry/mesh_check.h"

#include <algorithm>
#include <cmath>
#include <queue>
#include <sstream>

#include "geometry/mesh_edges.h"
#include "geometry/mesh_measures.h"

namespace rbfmuscle {
namespace {

bool isDegenerate(const TriangleMesh& mesh, int t) {
  const int i = mesh.triangles(0, t), j = mesh.triangles(1, t), k = mesh.triangles(2, t);
  if (i == j || j == k || k == i) return true;
  const Eigen::Vector3d a = mesh.vertices_mm.col(i), b = mesh.vertices_mm.col(j),
                        c = mesh.vertices_mm.col(k);
  const double longest_sq =
      std::max({(b - a).squaredNorm(), (c - b).squaredNorm(), (a - c).squaredNorm()});
  return !((b - a).cross(c - a).norm() > 1e-12 * longest_sq);
}

}  // namespace

std::vector<std::string> MeshReport::listProblems() const {
  std::vector<std::string> problems;
  const auto add = [&](int count, const std::string& what) {
    if (count > 0) problems.push_back(std::to_string(count) + " " + what);
  };
  add(non_finite_vertices, "vertices with non-finite coordinates (NaN or infinity)");
  add(degenerate_triangles,
      "degenerate triangles (zero area or a repeated vertex index) — remove or collapse them");
  add(boundary_edges, "boundary edges — the mesh is not watertight (open boundary)");
  add(non_manifold_edges,
      "non-manifold edges (shared by more than two triangles) — the mesh is not a single "
      "closed surface");
  add(inconsistent_edges,
      "inconsistently wound edges (neighbouring triangles face opposite ways) — wind them alike "
      "in a mesh tool (`rbfmuscle fit --fix-winding` does it for a fit)");
  if (problems.empty() && !(signed_volume_mm3 > 0.0)) {
    std::ostringstream s;
    s << "signed volume " << signed_volume_mm3
      << " mm³ is not positive — the triangles are wound inward; turn them outward in a mesh tool "
         "(`rbfmuscle fit --fix-winding` does it for a fit)";
    problems.push_back(s.str());
  }
  return problems;
}

std::string MeshReport::describe() const {
  std::ostringstream s;
  s << vertex_count << " vertices, " << triangle_count << " triangles, " << components
    << (components == 1 ? " component" : " components") << ", signed volume "
    << signed_volume_mm3 << " mm³";
  const std::vector<std::string> problems = listProblems();
  if (problems.empty()) {
    s << "; closed, manifold, consistently outward wound";
  } else {
    for (const std::string& p : problems) s << "; " << p;
  }
  return s.str();
}

MeshReport checkMesh(const TriangleMesh& mesh) {
  MeshReport r;
  r.vertex_count = mesh.countVertices();
  r.triangle_count = mesh.countTriangles();
  for (int v = 0; v < r.vertex_count; ++v)
    r.non_finite_vertices += mesh.vertices_mm.col(v).allFinite() ? 0 : 1;
  for (int t = 0; t < r.triangle_count; ++t) r.degenerate_triangles += isDegenerate(mesh, t) ? 1 : 0;
  const detail::EdgeTable edges = detail::buildEdgeTable(mesh);
  for (std::size_t e = 0; e < edges.vertices.size(); ++e) {
    if (edges.vertices[e][0] == edges.vertices[e][1]) continue;  // inside a degenerate triangle
    const int uses = edges.use_count[e];
    r.boundary_edges += uses == 1 ? 1 : 0;
    r.non_manifold_edges += uses > 2 ? 1 : 0;
    r.inconsistent_edges += (uses == 2 && edges.forward_count[e] != 1) ? 1 : 0;
  }
  r.components = countComponents(mesh);
  r.signed_volume_mm3 = calcVolume(mesh);
  return r;
}

void validateMesh(const TriangleMesh& mesh, const std::string& source_name) {
  const std::vector<std::string> problems = checkMesh(mesh).listProblems();
  if (problems.empty()) return;
  std::string message = source_name + ": ";
  for (std::size_t i = 0; i < problems.size(); ++i) message += (i ? "; " : "") + problems[i];
  throw MeshError(message);
}

int orientConsistently(TriangleMesh& mesh) {
  const int T = mesh.countTriangles();
  const detail::EdgeTable edges = detail::buildEdgeTable(mesh);
  // Triangles on each two-sided edge, to walk across it.
  std::vector<std::array<int, 2>> sides(edges.vertices.size(), {-1, -1});
  for (int t = 0; t < T; ++t)
    for (int c = 0; c < 3; ++c) {
      auto& s = sides[edges.of_triangle(c, t)];
      (s[0] < 0 ? s[0] : s[1]) = t;
    }
  const auto runsForward = [&](int t, int c) {
    return mesh.triangles(c, t) <= mesh.triangles((c + 1) % 3, t);
  };
  std::vector<char> flip(std::size_t(T), 0), seen(std::size_t(T), 0);
  const Eigen::Vector3d o = mesh.calcBoundingBox().center();
  for (int seed = 0; seed < T; ++seed) {
    if (seen[seed]) continue;
    std::vector<int> piece{seed};
    std::queue<int> queue;
    queue.push(seed);
    seen[seed] = 1;
    while (!queue.empty()) {
      const int t = queue.front();
      queue.pop();
      for (int c = 0; c < 3; ++c) {
        const int e = edges.of_triangle(c, t);
        if (edges.use_count[e] != 2 || edges.vertices[e][0] == edges.vertices[e][1]) continue;
        const int u = sides[e][0] == t ? sides[e][1] : sides[e][0];
        if (u < 0 || seen[u]) continue;
        int cu = 0;
        while (edges.of_triangle(cu, u) != e) ++cu;
        // Consistent when the shared edge runs opposite ways after flipping.
        const bool same_direction = runsForward(t, c) == runsForward(u, cu);
        flip[u] = char(flip[t] ^ (same_direction ? 1 : 0));
        seen[u] = 1;
        piece.push_back(u);
        queue.push(u);
      }
    }
    double six_volume = 0.0;
    for (int t : piece) {
      const Eigen::Vector3d a = mesh.getCorner(t, 0) - o, b = mesh.getCorner(t, 1) - o,
                            c = mesh.getCorner(t, 2) - o;
      six_volume += (flip[t] ? -1.0 : 1.0) * a.dot(b.cross(c));
    }
    if (six_volume < 0.0)
      for (int t : piece) flip[t] ^= 1;
  }
  int flipped = 0;
  for (int t = 0; t < T; ++t)
    if (flip[t]) {
      std::swap(mesh.triangles(1, t), mesh.triangles(2, t));
      ++flipped;
    }
  return flipped;
}

}  // namespace rbfmuscle
