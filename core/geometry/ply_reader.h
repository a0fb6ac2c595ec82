#pragma once
/// @file
/// Internal to rbfmuscle_geometry: a PLY reader of its own. assimp 5.2's binary PLY
/// parser misreads some valid files (faces with 0 or 1 index, then an abort in its
/// triangulation step; e.g. models/hip/meshes/pelvis_r_proxy.ply), so loadMesh reads PLY
/// here and every other format through assimp.
#include <array>
#include <string>
#include <vector>

namespace rbfmuscle::detail {

/// Raw polygon soup as stored: vertex positions and faces (any number of corners).
struct PlyContent {
  std::vector<std::array<double, 3>> vertices;  ///< x, y, z as stored (mm).
  std::vector<std::vector<int>> faces;          ///< vertex indices per face, 0-based.
};

/// Reads an ASCII or binary (little/big-endian) PLY file: element `vertex` with
/// properties x, y, z of any scalar type; element `face` with a list property
/// `vertex_indices` (or `vertex_index`); other elements and properties are skipped.
/// @throws MeshError naming `path` and the fault (bad header, truncated data,
///         index out of range).
PlyContent readPly(const std::string& path);

}  // namespace rbfmuscle::detail
