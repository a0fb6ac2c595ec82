// SPDX-License-Identifier: Apache-2.0
#include "geometry/mesh_measures.h"

#include "geometry/disjoint_sets.h"

#include <algorithm>
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

namespace {

/// Piece of every vertex (−1 for vertices no triangle uses), pieces numbered 0 … count − 1.
std::vector<int> labelComponents(const TriangleMesh& mesh, int& count) {
  DisjointSets sets(static_cast<std::size_t>(mesh.countVertices()));
  std::vector<char> used(sets.size(), 0);
  for (int t = 0; t < mesh.countTriangles(); ++t)
    for (int c = 0; c < 3; ++c) {
      used[mesh.triangles(c, t)] = 1;
      sets.join(mesh.triangles(c, t), mesh.triangles((c + 1) % 3, t));
    }
  std::vector<int> label(sets.size(), -1), root_label(sets.size(), -1);
  count = 0;
  for (int v = 0; v < int(sets.size()); ++v) {
    if (!used[v]) continue;
    const int r = sets.find(v);
    if (root_label[r] < 0) root_label[r] = count++;
    label[v] = root_label[r];
  }
  return label;
}

}  // namespace

int countComponents(const TriangleMesh& mesh) {
  int count = 0;
  labelComponents(mesh, count);
  return count;
}

std::vector<double> calcComponentVolumes(const TriangleMesh& mesh) {
  int count = 0;
  const std::vector<int> label = labelComponents(mesh, count);
  std::vector<double> volumes(static_cast<std::size_t>(count), 0.0);
  if (count == 0) return volumes;
  const Eigen::Vector3d o = 0.5 * (mesh.vertices_mm.rowwise().minCoeff() + mesh.vertices_mm.rowwise().maxCoeff());
  for (int t = 0; t < mesh.countTriangles(); ++t) {
    const Eigen::Vector3d a = mesh.vertices_mm.col(mesh.triangles(0, t)) - o;
    const Eigen::Vector3d b = mesh.vertices_mm.col(mesh.triangles(1, t)) - o;
    const Eigen::Vector3d c = mesh.vertices_mm.col(mesh.triangles(2, t)) - o;
    volumes[static_cast<std::size_t>(label[static_cast<std::size_t>(mesh.triangles(0, t))])] += a.dot(b.cross(c)) / 6.0;
  }
  std::sort(volumes.begin(), volumes.end(), [](double x, double y) { return x > y; });
  return volumes;
}

std::vector<double> calcComponentSizes(const TriangleMesh& mesh) {
  int count = 0;
  const std::vector<int> label = labelComponents(mesh, count);
  std::vector<Eigen::AlignedBox3d> boxes(static_cast<std::size_t>(count));
  for (int v = 0; v < mesh.countVertices(); ++v) {
    const int piece = label[static_cast<std::size_t>(v)];
    if (piece >= 0) boxes[static_cast<std::size_t>(piece)].extend(mesh.vertices_mm.col(v));
  }
  std::vector<double> sizes;
  for (const Eigen::AlignedBox3d& box : boxes) sizes.push_back(box.diagonal().norm());
  std::sort(sizes.begin(), sizes.end(), [](double x, double y) { return x > y; });
  return sizes;
}

void calcVertexNormals(const TriangleMesh& mesh, Eigen::Matrix3Xd& out) {
  out.setZero(3, mesh.vertices_mm.cols());
  for (int t = 0; t < mesh.countTriangles(); ++t) {
    const Eigen::Vector3d a = mesh.getCorner(t, 0);
    const Eigen::Vector3d area_normal = (mesh.getCorner(t, 1) - a).cross(mesh.getCorner(t, 2) - a);
    for (int c = 0; c < 3; ++c) out.col(mesh.triangles(c, t)) += area_normal;
  }
}

}  // namespace rbfmuscle
