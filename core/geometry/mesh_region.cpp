#include "geometry/mesh_region.h"

#include <vector>

namespace rbfmuscle {

TriangleMesh keepTrianglesNear(const TriangleMesh& mesh, const Eigen::Matrix3Xd& points_mm, double radius_mm) {
  const double r2 = radius_mm * radius_mm;
  std::vector<bool> near(static_cast<size_t>(mesh.countVertices()), false);
  if (points_mm.cols() > 0)
    for (int v = 0; v < mesh.countVertices(); ++v)
      near[static_cast<size_t>(v)] = (points_mm.colwise() - mesh.vertices_mm.col(v)).colwise().squaredNorm().minCoeff() <= r2;
  std::vector<int> new_index(static_cast<size_t>(mesh.countVertices()), -1);
  std::vector<int> kept_vertices, kept_triangles;
  for (int t = 0; t < mesh.countTriangles(); ++t) {
    bool all = true;
    for (int c = 0; c < 3; ++c) all = all && near[static_cast<size_t>(mesh.triangles(c, t))];
    if (!all) continue;
    kept_triangles.push_back(t);
    for (int c = 0; c < 3; ++c) new_index[static_cast<size_t>(mesh.triangles(c, t))] = 0;
  }
  for (int v = 0; v < mesh.countVertices(); ++v)
    if (new_index[static_cast<size_t>(v)] == 0) {
      new_index[static_cast<size_t>(v)] = static_cast<int>(kept_vertices.size());
      kept_vertices.push_back(v);
    }
  TriangleMesh out;
  out.vertices_mm.resize(3, static_cast<Eigen::Index>(kept_vertices.size()));
  for (size_t j = 0; j < kept_vertices.size(); ++j)
    out.vertices_mm.col(static_cast<Eigen::Index>(j)) = mesh.vertices_mm.col(kept_vertices[j]);
  out.triangles.resize(3, static_cast<Eigen::Index>(kept_triangles.size()));
  for (size_t j = 0; j < kept_triangles.size(); ++j)
    for (int c = 0; c < 3; ++c)
      out.triangles(c, static_cast<Eigen::Index>(j)) =
          new_index[static_cast<size_t>(mesh.triangles(c, kept_triangles[j]))];
  return out;
}

}  // namespace rbfmuscle
