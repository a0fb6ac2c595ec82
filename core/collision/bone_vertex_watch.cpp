#include "collision/bone_vertex_watch.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <stdexcept>
#include <string>
#include <tuple>

namespace rbfmuscle {

BoneVertexWatch::BoneVertexWatch(const std::vector<TriangleMesh>& meshes_B,
                                 const std::vector<Eigen::Isometry3d>& X_MB_rest, const GaussianField& rest_field,
                                 double spacing_mm) {
  if (meshes_B.size() != X_MB_rest.size())
    throw std::invalid_argument("BoneVertexWatch: " + std::to_string(meshes_B.size()) + " meshes and " +
                                std::to_string(X_MB_rest.size()) + " poses");
  if (!(spacing_mm > 0.0) || !std::isfinite(spacing_mm))
    throw std::invalid_argument("BoneVertexWatch: spacing " + std::to_string(spacing_mm) + " mm, expected > 0");
  size_t largest = 0;
  for (size_t b = 0; b < meshes_B.size(); ++b) {
    const TriangleMesh& mesh = meshes_B[b];
    Eigen::Matrix3Xd normal = Eigen::Matrix3Xd::Zero(3, mesh.countVertices());
    for (int t = 0; t < mesh.countTriangles(); ++t) {
      // (v1 − v0) × (v2 − v0): outward, twice the area, so the sum weights faces by area.
      const Eigen::Vector3d n = (mesh.getCorner(t, 1) - mesh.getCorner(t, 0)).cross(mesh.getCorner(t, 2) - mesh.getCorner(t, 0));
      for (int c = 0; c < 3; ++c) normal.col(mesh.triangles(c, t)) += n;
    }
    std::map<std::tuple<long long, long long, long long>, int> first_of_cell;  // ordered: deterministic
    for (int v = 0; v < mesh.countVertices(); ++v) {
      if (!(normal.col(v).squaredNorm() > 0.0)) continue;  // unused or degenerate: no direction
      const Eigen::Array3d cell = (mesh.vertices_mm.col(v) / spacing_mm).array().floor();
      first_of_cell.emplace(std::make_tuple(static_cast<long long>(cell.x()), static_cast<long long>(cell.y()),
                                            static_cast<long long>(cell.z())),
                            v);
    }
    std::vector<int> watched;
    for (const auto& [cell, v] : first_of_cell)
      if (!(rest_field.calcValue(X_MB_rest[b] * Eigen::Vector3d(mesh.vertices_mm.col(v))) > 0.0)) watched.push_back(v);
    std::sort(watched.begin(), watched.end());
    Eigen::Matrix3Xd vertices(3, static_cast<Eigen::Index>(watched.size())), inward(3, vertices.cols());
    for (size_t k = 0; k < watched.size(); ++k) {
      vertices.col(static_cast<Eigen::Index>(k)) = mesh.vertices_mm.col(watched[k]);
      inward.col(static_cast<Eigen::Index>(k)) = -normal.col(watched[k]).normalized();
    }
    grids_B_.emplace_back();
    if (vertices.cols() > 0) grids_B_.back().build(vertices, spacing_mm);
    largest = std::max(largest, watched.size());
    vertices_B_.push_back(std::move(vertices));
    inward_B_.push_back(std::move(inward));
  }
  stamp_.assign(largest, -1);
}

void BoneVertexWatch::findInside(int b, const Eigen::Isometry3d& X_MB, const GaussianField& field,
                                 const Eigen::Ref<const Eigen::Matrix3Xd>& near_B, double radius_mm, std::vector<BoneVertexInside>& out) {
  if (b < 0 || b >= countBones())
    throw std::invalid_argument("BoneVertexWatch::findInside: bone " + std::to_string(b) + " of " +
                                std::to_string(countBones()));
  const Eigen::Matrix3Xd& vertices = vertices_B_[static_cast<size_t>(b)];
  if (vertices.cols() == 0) return;
  ++calls_;
  std::vector<int> tested;
  for (Eigen::Index i = 0; i < near_B.cols(); ++i) {
    grids_B_[static_cast<size_t>(b)].findWithinRadius(near_B.col(i), radius_mm, found_);
    for (int v : found_) {
      if (stamp_[static_cast<size_t>(v)] == calls_) continue;
      stamp_[static_cast<size_t>(v)] = calls_;
      tested.push_back(v);
    }
  }
  std::sort(tested.begin(), tested.end());
  const int n = static_cast<int>(tested.size());
  values_.resize(n);
#pragma omp parallel for schedule(static)
  for (int t = 0; t < n; ++t)  // independent per vertex: the same values on any number of threads
    values_(t) = field.calcValue(X_MB * Eigen::Vector3d(vertices.col(tested[static_cast<size_t>(t)])));
  for (int t = 0; t < n; ++t) {
    if (!(values_(t) > 0.0)) continue;
    const int v = tested[static_cast<size_t>(t)];
    out.push_back({b, X_MB * Eigen::Vector3d(vertices.col(v)), X_MB.linear() * inward_B_[static_cast<size_t>(b)].col(v), values_(t)});
  }
}

}  // namespace rbfmuscle
