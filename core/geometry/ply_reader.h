// SPDX-License-Identifier: Apache-2.0
#pragma once
/// @file
/// Internal to rbfmuscle_geometry: a PLY reader of its own. assimp 5.2's binary PLY
/// parser misreads some valid files (faces with 0 or 1 index, then an abort in its
/// triangulation step; e.g. models/hip/meshes/pelvis_r_proxy.ply), so loadMesh reads PLY
/// here and every other format through assimp.
#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace rbfmuscle::detail {

/// Raw polygon soup as stored: vertex positions and faces (any number of corners).
struct PlyContent {
  std::vector<std::array<double, 3>> vertices;  ///< x, y, z as stored (mm).
  std::vector<std::vector<int>> faces;          ///< vertex indices per face, 0-based.
};

/// Largest PLY file read (bytes): 2 GiB. The whole file is read into memory; the largest
/// mesh of the project (the pelvis) is under 10 MB.
constexpr std::uintmax_t kMaxPlyFileBytes = 2ull << 30;

/// Largest element count a PLY header may declare: 2^31 − 1, since vertex indices are int.
/// Counts are also checked against the bytes left after the header before any allocation.
constexpr long long kMaxPlyElementCount = 2147483647LL;

/// Reads an ASCII or binary (little/big-endian) PLY file: element `vertex` with
/// properties x, y, z of any scalar type; element `face` with a list property
/// `vertex_indices` (or `vertex_index`); other elements and properties are skipped.
/// @throws MeshError naming `path` and the fault: not a regular file (a device, FIFO or
///         directory is refused before it is read), a file over kMaxPlyFileBytes, bad header,
///         an element count the file's size cannot hold (refused before allocation), no
///         vertex element or no x, y, z, truncated data, index out of range.
PlyContent readPly(const std::string& path);

/// Parses the bytes of a PLY file held in memory (what readPly does after reading the file);
/// `path` only names the file in errors.
PlyContent parsePly(const std::string& data, const std::string& path);

}  // namespace rbfmuscle::detail
