#pragma once
/// Small meshes and file helpers shared by the geometry tests.
#include <filesystem>
#include <fstream>
#include <string>

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

}  // namespace rbfmuscle::test
