// SPDX-License-Identifier: Apache-2.0
#pragma once
/// @file
/// Per-frame geometry a component can expose for `rbfmuscle run --frames-mesh`
/// (deformed muscle surface, fibres), written as VTK XML polydata (.vtp) with
/// one ParaView `.pvd` time series per geometry name.
#include <Eigen/Core>

#include <string>
#include <vector>

namespace rbfmuscle {

/// Triangles and polylines in ground, in mm.
struct FrameGeometry {
  std::string name;                         ///< file stem: COMPONENT_NAME or COMPONENT_NAME_part
  Eigen::Matrix3Xd vertices_mm;             ///< 3×n vertex positions in ground (mm)
  Eigen::Matrix3Xi triangles;               ///< 3×m vertex indices, counter-clockwise outward
  std::vector<std::vector<int>> polylines;  ///< vertex index chains (e.g. fibres)
};

/// Writes one geometry as an ASCII VTK XML PolyData file (.vtp).
/// @throws FrameworkError naming the path when it cannot be written or an index is out of range.
void writeVtp(const std::string& path, const FrameGeometry& geometry);

/// Reads an ASCII .vtp file as writeVtp writes it (points, triangles, polylines); the name is
/// the file stem.
/// @throws FrameworkError naming the path and what is wrong (unreadable, not VTK PolyData, an
///   array of the wrong length, a non-number or an index out of range).
FrameGeometry readVtp(const std::string& path);

/// A ParaView `.pvd` collection: (time, file) entries written at the end.
class PvdSeries {
 public:
  /// @param file path relative to the .pvd file's directory
  void add(double time_s, const std::string& file) { entries_.push_back({time_s, file}); }
  /// @throws FrameworkError naming the path when it cannot be written.
  void write(const std::string& path) const;

 private:
  struct Entry {
    double time_s;
    std::string file;
  };
  std::vector<Entry> entries_;
};

}  // namespace rbfmuscle
