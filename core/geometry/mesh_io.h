// SPDX-License-Identifier: Apache-2.0
#pragma once
/// @file
/// Mesh files: reading (PLY and VTK XML PolyData by own readers; STL, OBJ and every other
/// format assimp knows),
/// writing binary PLY, and hashing a file to tie derived data to its source mesh.
#include <string>

#include "geometry/mesh_error.h"
#include "geometry/mesh_repair.h"
#include "geometry/mesh_warning.h"
#include "geometry/triangle_mesh.h"

namespace rbfmuscle {

/// Largest coordinate magnitude a mesh file may hold, in its own units: 1e6. The project's
/// meshes are in mm (a muscle or bone spans under 1e3 mm, CT frames sit within 1e3 mm of
/// their origin) or in metres (bones in a URDF); 1e6 leaves room for µm and for far origins,
/// and beyond it a file has wrong units or is corrupt. Squared distances stay exact enough
/// in double precision up to it.
constexpr double kMaxMeshCoordinate = 1e6;

/// Smallest extent (largest side of the bounding box) a mesh file may have, in its own
/// units: 1e-6, i.e. 1 nm in mm or 1 µm in metres. A smaller mesh is collapsed or in wrong
/// units; no fit or contact tolerance of the project could resolve it.
constexpr double kMinMeshExtent = 1e-6;

/// A mesh file as loadMesh returns it, with what was dropped and repaired on the way.
struct LoadedMesh {
  TriangleMesh mesh;         ///< welded and repaired (mm, as stored).
  int unused_vertices = 0;   ///< vertices of the file that no triangle uses, dropped.
  MeshRepairReport repair;   ///< what repairMesh found and did after welding.

  /// The warning for `path`: "<path>: 2 unused vertices dropped; 1 non-manifold edge
  /// repaired: ..."; empty when there was nothing to drop or repair.
  std::string describeDefects(const std::string& path) const;
};

/// Reads every triangle of every mesh in the file (node transforms applied, polygons
/// triangulated, points and lines ignored). PLY (ASCII or binary, by the `.ply` extension)
/// is read by the library's own reader, because assimp 5.2 misreads some binary PLY files;
/// VTK XML PolyData (`.vtp`, as OpenSim model geometry is stored) by readVtpPolyData
/// (vtp_reader.h), polygons and triangle strips triangulated; every other format (STL, OBJ, ...)
/// through assimp. Then it welds vertices with exactly equal
/// coordinates so unindexed formats (STL) become indexed, drops unreferenced vertices, and
/// repairs what repairMesh can repair safely (collapsed, back-to-back and duplicate triangles,
/// pinched edges and vertices, slivers left hanging at a pinch). An indexed file with none of
/// those defects and no unused vertices is returned exactly as stored. Coordinates are taken as millimetres as stored.
/// Open or otherwise unusable meshes are returned as they are: use loadSolidMesh for a mesh
/// that must bound a solid.
/// @throws MeshError naming `path` when the file is missing or unreadable or not a regular file
///         (devices, FIFOs and directories are refused before they are read), assimp or the VTP
///         reader fails (its message included), there are no triangles, a coordinate used by a
///         triangle is not finite or of magnitude above kMaxMeshCoordinate, or the mesh spans less
///         than kMinMeshExtent.
LoadedMesh readMesh(const std::string& path);

/// readMesh for the bytes of a .ply or .vtp file held in memory; `path` picks the reader by its
/// extension and names the file in errors. @throws MeshError as readMesh, and for any other
/// extension.
LoadedMesh parseMesh(const std::string& bytes, const std::string& path);

/// readMesh, passing the warning (LoadedMesh::describeDefects) to `warn` when the file had
/// unused vertices or defects the loader repaired.
/// @throws MeshError as readMesh.
TriangleMesh loadMesh(const std::string& path, const MeshWarningFn& warn = printMeshWarning);

/// Writes `mesh` as binary little-endian PLY (`property double x/y/z` in mm,
/// `property list uchar int vertex_indices`), so writePly → loadMesh is exact for a mesh without
/// the defects loadMesh repairs (a mesh whose pinches were split holds coincident vertices, which
/// loading welds and splits again). Written to a temporary file beside `path`
/// and renamed over it, so `path` is never left half-written.
/// @throws MeshError naming `path` when the file cannot be written.
void writePly(const std::string& path, const TriangleMesh& mesh);

/// 64-bit FNV-1a hash of the file's bytes as 16 lowercase hex digits
/// (offset basis 0xcbf29ce484222325, prime 0x100000001b3).
/// @throws MeshError naming `path` when the file cannot be read or is not a regular file.
std::string hashFile(const std::string& path);

}  // namespace rbfmuscle
