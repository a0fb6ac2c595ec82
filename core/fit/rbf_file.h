// SPDX-License-Identifier: Apache-2.0
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

/// Bounds readRbfFile puts on what a file may hold. A fitted muscle lies within 1e3 mm of its
/// frame origin, its weights are of the order of the clamp of the fit's target (τ = 10 mm by
/// default) and its shapes span 0.005–0.5 mm⁻²; the bounds sit far outside so that any real
/// fit passes, and close enough that sums and squares of every term stay finite (a weight of
/// 1e308 made every curvature cost NaN):
/// - coordinates (centres, frame offset): |x| ≤ 1e6 mm (1 km);
constexpr double kMaxRbfCoordinateMm = 1e6;
/// - weights and the offset b: |λ| ≤ 1e6 field units (1e5 times the default clamp);
constexpr double kMaxRbfWeight = 1e6;
/// - shapes: 1e-8 ≤ α ≤ 1e4 mm⁻², i.e. Gaussian widths σ = α^−½ from 10 m down to 10 µm;
constexpr double kMinRbfShape = 1e-8;
constexpr double kMaxRbfShape = 1e4;
/// - centres: 1 ≤ N ≤ 1e7 (fits use up to 1e5), and N lines of at least 10 bytes must fit in
///   the file, checked before anything is allocated.
constexpr int kMaxRbfCentres = 10000000;

/// Writes `surface` with full double precision, to a temporary file renamed
/// over `path` (never half-written). @throws RbfFileError when it cannot.
void writeRbfFile(const std::string& path, const RbfSurface& surface);

/// Reads a file written by writeRbfFile. @throws RbfFileError naming the file
/// and line: missing file or not a regular file (a device, FIFO or directory is refused
/// before it is read), wrong magic or version, missing record, bad number, a centre count
/// outside 1…kMaxRbfCentres or more than the file's size can hold, fewer centre lines than
/// declared ("file ends early") or more ("more centre lines than the N declared"), a value
/// beyond the bounds above.
RbfSurface readRbfFile(const std::string& path);

/// Parses the text of a .rbf file held in memory (what readRbfFile does after opening the
/// file); `path` only names the file in errors. @throws RbfFileError as readRbfFile.
RbfSurface parseRbfText(const std::string& text, const std::string& path);

}  // namespace rbfmuscle
