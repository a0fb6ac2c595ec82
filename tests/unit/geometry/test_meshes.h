// SPDX-License-Identifier: Apache-2.0
#pragma once
/// Small meshes and file helpers shared by the geometry tests.
#include <algorithm>
#include <array>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "geometry/triangle_mesh.h"

namespace rbfmuscle::test {

/// Path of a file in the source tree's models/ folder.
inline std::string modelPath(const std::string& relative) {
  return std::string(RBFMUSCLE_SOURCE_DIR) + "/models/" + relative;
}

/// A fresh empty directory under the build tree for one test's files.
inline std::filesystem::path makeTempDir(const std::string& name) {
  const auto dir = std::filesystem::path(RBFMUSCLE_BINARY_DIR) / "test_tmp" / "geometry" / name;
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir;
}

/// Writes `text` to `path` and returns the path as a string.
inline std::string writeText(const std::filesystem::path& path, const std::string& text) {
  std::ofstream(path, std::ios::binary) << text;
  return path.string();
}

/// Axis-aligned cube [lo, lo+size]³ (mm), 8 vertices and 12 outward-wound triangles.
inline TriangleMesh makeCube(double size_mm, double lo_mm = 0.0) {
  TriangleMesh m;
  m.vertices_mm.resize(3, 8);
  for (int v = 0; v < 8; ++v)
    m.vertices_mm.col(v) << lo_mm + size_mm * (v & 1), lo_mm + size_mm * ((v >> 1) & 1),
        lo_mm + size_mm * ((v >> 2) & 1);
  m.triangles.resize(3, 12);
  m.triangles << 0, 0, 4, 4, 0, 0, 2, 2, 0, 0, 1, 1,  //
      2, 3, 5, 7, 1, 5, 6, 7, 4, 6, 3, 7,             //
      3, 1, 7, 6, 5, 4, 7, 3, 6, 2, 7, 5;
  return m;
}

/// Icosphere of radius `radius_mm` centred at the origin: the icosahedron with each
/// triangle split in four `levels` times, vertices pushed onto the sphere; wound outward.
inline TriangleMesh makeIcosphere(double radius_mm, int levels) {
  const double g = (1.0 + std::sqrt(5.0)) / 2.0;
  std::vector<Eigen::Vector3d> v = {{-1, g, 0}, {1, g, 0},  {-1, -g, 0}, {1, -g, 0},
                                    {0, -1, g}, {0, 1, g},  {0, -1, -g}, {0, 1, -g},
                                    {g, 0, -1}, {g, 0, 1},  {-g, 0, -1}, {-g, 0, 1}};
  std::vector<std::array<int, 3>> f = {{0, 11, 5}, {0, 5, 1},  {0, 1, 7},   {0, 7, 10}, {0, 10, 11},
                                       {1, 5, 9},  {5, 11, 4}, {11, 10, 2}, {10, 7, 6}, {7, 1, 8},
                                       {3, 9, 4},  {3, 4, 2},  {3, 2, 6},   {3, 6, 8},  {3, 8, 9},
                                       {4, 9, 5},  {2, 4, 11}, {6, 2, 10},  {8, 6, 7},  {9, 8, 1}};
  for (int level = 0; level < levels; ++level) {
    std::map<std::pair<int, int>, int> mid;
    const auto midpoint = [&](int a, int b) {
      const auto key = std::minmax(a, b);
      auto it = mid.find(key);
      if (it != mid.end()) return it->second;
      v.push_back((v[std::size_t(a)] + v[std::size_t(b)]) / 2.0);
      return mid[key] = int(v.size()) - 1;
    };
    std::vector<std::array<int, 3>> next;
    for (const auto& t : f) {
      const int ab = midpoint(t[0], t[1]), bc = midpoint(t[1], t[2]), ca = midpoint(t[2], t[0]);
      next.push_back({t[0], ab, ca});
      next.push_back({t[1], bc, ab});
      next.push_back({t[2], ca, bc});
      next.push_back({ab, bc, ca});
    }
    f.swap(next);
  }
  TriangleMesh m;
  m.vertices_mm.resize(3, Eigen::Index(v.size()));
  for (std::size_t i = 0; i < v.size(); ++i) m.vertices_mm.col(Eigen::Index(i)) = radius_mm * v[i].normalized();
  m.triangles.resize(3, Eigen::Index(f.size()));
  for (std::size_t i = 0; i < f.size(); ++i) m.triangles.col(Eigen::Index(i)) << f[i][0], f[i][1], f[i][2];
  return m;
}

/// Closed, outward-wound surface of a union of grid cells: cell (i, j, k) is the cube
/// [i, i+1] × [j, j+1] × [k, k+1] times `size_mm` (mm). Each face between a cell and a missing
/// neighbour gives two triangles; vertices are shared by grid point, so cells that touch only
/// along an edge or at a corner give a pinched edge or vertex.
inline TriangleMesh makeCellUnion(const std::vector<std::array<int, 3>>& cells, double size_mm = 1.0) {
  const auto has = [&](std::array<int, 3> c) { return std::find(cells.begin(), cells.end(), c) != cells.end(); };
  std::map<std::array<int, 3>, int> index_of;
  std::vector<std::array<int, 3>> points, faces;
  const auto vertex = [&](std::array<int, 3> p) {
    const auto [it, added] = index_of.emplace(p, int(points.size()));
    if (added) points.push_back(p);
    return it->second;
  };
  for (const auto& cell : cells)
    for (int axis = 0; axis < 3; ++axis)
      for (int side : {-1, 1}) {
        std::array<int, 3> next = cell;
        next[std::size_t(axis)] += side;
        if (has(next)) continue;
        const std::size_t u = std::size_t(axis + 1) % 3, w = std::size_t(axis + 2) % 3;
        std::array<int, 3> p0 = cell;
        p0[std::size_t(axis)] += side > 0 ? 1 : 0;
        std::array<int, 3> p1 = p0, p2 = p0, p3 = p0;
        p1[u] += 1;
        p2[u] += 1;
        p2[w] += 1;
        p3[w] += 1;
        const int a = vertex(p0), b = vertex(p1), c = vertex(p2), d = vertex(p3);
        // (e_u × e_w) = e_axis: counter-clockwise seen from +axis.
        if (side > 0) {
          faces.push_back({a, b, c});
          faces.push_back({a, c, d});
        } else {
          faces.push_back({a, c, b});
          faces.push_back({a, d, c});
        }
      }
  TriangleMesh m;
  m.vertices_mm.resize(3, Eigen::Index(points.size()));
  for (std::size_t i = 0; i < points.size(); ++i)
    m.vertices_mm.col(Eigen::Index(i)) << size_mm * points[i][0], size_mm * points[i][1], size_mm * points[i][2];
  m.triangles.resize(3, Eigen::Index(faces.size()));
  for (std::size_t i = 0; i < faces.size(); ++i) m.triangles.col(Eigen::Index(i)) << faces[i][0], faces[i][1], faces[i][2];
  return m;
}

/// `mesh` with the vertices `extra_mm` (mm) and the triangles `extra` (indices into the
/// combined vertex list) appended.
inline TriangleMesh appendTriangles(const TriangleMesh& mesh, const std::vector<Eigen::Vector3d>& extra_mm,
                                    const std::vector<std::array<int, 3>>& extra) {
  TriangleMesh out = mesh;
  const Eigen::Index V = mesh.vertices_mm.cols(), T = mesh.triangles.cols();
  out.vertices_mm.conservativeResize(3, V + Eigen::Index(extra_mm.size()));
  for (std::size_t i = 0; i < extra_mm.size(); ++i) out.vertices_mm.col(V + Eigen::Index(i)) = extra_mm[i];
  out.triangles.conservativeResize(3, T + Eigen::Index(extra.size()));
  for (std::size_t i = 0; i < extra.size(); ++i) out.triangles.col(T + Eigen::Index(i)) << extra[i][0], extra[i][1], extra[i][2];
  return out;
}

/// Removes triangle `t` from `mesh`.
inline TriangleMesh removeTriangle(const TriangleMesh& mesh, int t) {
  TriangleMesh out = mesh;
  out.triangles.resize(3, mesh.countTriangles() - 1);
  out.triangles << mesh.triangles.leftCols(t), mesh.triangles.rightCols(mesh.countTriangles() - t - 1);
  return out;
}

}  // namespace rbfmuscle::test
