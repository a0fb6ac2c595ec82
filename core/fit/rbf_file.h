#pragma once
/// @file
/// The .rbf file: a fitted Gaussian surface with everything needed to trust
/// and reuse it (version, units, frame, source mesh hash, fit settings).
///
/// Format (text, version 1, one record per line, `#` starts a comment line):
///   rbfmuscle_rbf 1
///   units mm
///   source_mesh <file name of the fitted mesh>
///   source_hash <16 hex digits: FNV-1a-64 of the mesh file bytes>
///   frame_offset_mm <x> <y> <z>      muscle frame M = source frame shifted by this (p_src = p_M + offset)
///   offset <b>                       field constant b (mm)
///   cutoff <ε>                       φ below ε is ignored
///   settings <key=value …>           the fit settings used
///   metrics <JSON object>            the fit's measured quality
///   centres <N>
///   then N lines: <ξx> <ξy> <ξz> <λ> <α>  (ξ in M, mm; λ in mm; α in mm⁻²)
#include <Eigen/Core>

#include <stdexcept>
#include <string>

#include "rbf/gaussian_field.h"

namespace rbfmuscle {

/// Thrown for an unreadable or malformed .rbf file; names the file and line.
class RbfFileError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// A fitted surface and its provenance.
struct RbfSurface {
  GaussianField field;                                       ///< in the muscle frame M
  Eigen::Vector3d frame_offset_mm = Eigen::Vector3d::Zero(); ///< origin of M in the source frame
  std::string source_mesh;
  std::string source_hash;
  std::string settings;
  std::string metrics_json;
};

/// Current format version.
constexpr int kRbfFileVersion = 1;

/// Writes `surface` with full double precision, to a temporary file renamed
/// over `path` (never half-written). @throws RbfFileError when it cannot.
void writeRbfFile(const std::string& path, const RbfSurface& surface);

/// Reads a file written by writeRbfFile. @throws RbfFileError naming the file
/// and line: missing file, wrong magic or version, missing record, bad number,
/// wrong centre count, non-positive shape.
RbfSurface readRbfFile(const std::string& path);

}  // namespace rbfmuscle
