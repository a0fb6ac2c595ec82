// SPDX-License-Identifier: Apache-2.0
#pragma once
/// @file
/// VTK XML PolyData (.vtp) reader: the geometry files of OpenSim models (written by VTK
/// with zlib-compressed base64 arrays), ParaView exports, and the per-frame files of
/// `rbfmuscle run --frames-mesh` (ASCII).
///
/// Supported DataArray encodings: `format="ascii"`, `format="binary"` (base64, inline) and
/// `format="appended"` (AppendedData with `encoding="base64"` or `encoding="raw"`), each
/// uncompressed or compressed with `compressor="vtkZLibDataCompressor"`; `header_type`
/// UInt32 (the default) or UInt64; `byte_order` LittleEndian or BigEndian; element types
/// Int8 … UInt64, Float32 and Float64. Several Pieces are concatenated.
#include <Eigen/Core>

#include <string>
#include <vector>

#include "geometry/mesh_error.h"

namespace rbfmuscle {

/// The cells and points of a .vtp file, as stored (coordinates in the file's units; OpenSim
/// geometry is usually in metres, the LHDL model's in mm: the model says which).
struct VtpPolyData {
  Eigen::Matrix3Xd points;                 ///< 3×N point coordinates, all pieces
  std::vector<std::vector<int>> polys;     ///< Polys cells (polygons), indices into points
  std::vector<std::vector<int>> strips;    ///< Strips cells (triangle strips)
  std::vector<std::vector<int>> lines;     ///< Lines cells (polylines)
  long verts = 0;                          ///< number of Verts cells (read and checked, not kept)

  /// Triangles of the polygons (fan from each polygon's first corner, keeping its winding)
  /// and of the strips (alternate triangles flipped so all keep the strip's winding), as 3×T.
  Eigen::Matrix3Xi triangulate() const;
};

/// Reads a VTK XML PolyData file.
/// @throws MeshError naming `path`, the XML line and the array, and what is wrong: missing or
///   unreadable file, XML syntax error (a truncated file), not `VTKFile type="PolyData"`, an
///   unsupported compressor, header type, element type or encoding, a character that is not
///   base64, a compressed block zlib cannot inflate (corrupt compressed array), header sizes that
///   disagree with each other, with the data or with the piece's counts, counts beyond what the
///   file can hold, a non-finite coordinate, an offset that decreases or a vertex index out of range.
VtpPolyData readVtpPolyData(const std::string& path);

/// Parses the text of a .vtp file held in memory (what readVtpPolyData does after reading the
/// file); `path` only names the file in errors. @throws MeshError as readVtpPolyData.
VtpPolyData parseVtpPolyData(const std::string& text, const std::string& path);

}  // namespace rbfmuscle
