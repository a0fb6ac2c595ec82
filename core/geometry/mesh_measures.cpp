#include "geometry/mesh_measures.h"

#include <numeric>
#include <vector>

namespace rbfmuscle {

double calcVolume(const TriangleMesh& mesh) {
  const Eigen::AlignedBox3d box = mesh.calcBoundingBox();
  const Eigen::Vector3d o = box.isEmpty() ? Eigen::Vector3d::Zero().eval() : box.center().eval();
  double six_volume = 0.0;
  for (int t = 0; t < mesh.countTriangles(); ++t) {
    const Eigen::Vector3d a = mesh.getCorner(t, 0) - o, b = mesh.getCorner(t, 1) - o,
                          c = mesh.getCorner(t, 2) - o;
    six_volume += a.dot(b.cross(c));
  }
  return six_volume / 6.0;
}

double calcArea(const TriangleMesh& mesh) {
  double twice_area = 0.0;
  for (int t = 0; t < mesh.countTriangles(); ++t) {
    const Eigen::Vector3d a = mesh.getCorner(t, 0);
    twice_area += (mesh.getCorner(t, 1) - a).cross(mesh.getCorner(t, 2) - a).norm();
  }
  return twice_area / 2.0;
}

int countComponents(const TriangleMesh& mesh) {
  std::vector<int> parent(static_cast<std::size_t>(mesh.countVertices()));
  std::iota(parent.begin(), parent.end(), 0);
  const auto find = [&](int v) {
    while (parent[v] != v) v = parent[v] = parent[parent[v]];
    return v;
  };
  std::vector<char> used(parent.size(), 0);
  for (int t = 0; t < mesh.countTriangles(); ++t)
    for (int c = 0; c < 3; ++c) {
      used[mesh.triangles(c, t)] = 1;
      parent[find(mesh.triangles(c, t))] = find(mesh.triangles((c + 1) % 3, t));
    }
  int count = 0;
  for (int v = 0; v < int(parent.size()); ++v) count += (used[v] && find(v) == v) ? 1 : 0;
  return count;
}

}  // namespace rbfmuscle
