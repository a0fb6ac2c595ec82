// SPDX-License-Identifier: Apache-2.0
#pragma once
/// @file
/// Fitting samples (dissertation Alg. 2, lines 3–7): mesh vertices, points ±d
/// along the vertex normals, Halton(2,3,5) points in the padded box, each with
/// its clamped signed-distance target.
#include <Eigen/Core>
#include <Eigen/Geometry>

#include <cstdint>
#include <vector>

#include "fit/fit_settings.h"
#include "geometry/triangle_mesh.h"

namespace rbfmuscle {

class MeshDistance;
class WindingNumber;

/// Where a sample came from.
enum class SampleKind : unsigned char { kSurface, kOffsetIn, kOffsetOut, kHalton, kCheck, kNearCrumb };

/// Samples in the muscle frame M (mm).
struct SampleSet {
  Eigen::Matrix3Xd points_mm;          ///< 3×S sample positions
  Eigen::VectorXd signed_distance_mm;  ///< s(x): negative inside, positive outside
  Eigen::VectorXd target;              ///< t(x) = clamp(−s(x), −τ, τ) (mm)
  std::vector<SampleKind> kinds;       ///< origin of each sample
  Eigen::AlignedBox3d box_mm;          ///< padded bounding box the samples fill
  /// Samples whose side (inside or outside) the winding number decided against the sign of
  /// the closest feature's pseudo-normal: > 0 when the mesh has folds or slivers.
  int resigned_samples = 0;
  int getNumSamples() const { return static_cast<int>(points_mm.cols()); }

  /// Check points: not fitted, but watched by the fit (see fitGreedy), which makes one a
  /// sample (kind kCheck) where the field puts it on the wrong side.
  Eigen::Matrix3Xd check_points_mm;
  Eigen::VectorXd check_signed_distance_mm;
  Eigen::VectorXd check_target;
  int getNumCheckPoints() const { return static_cast<int>(check_points_mm.cols()); }
};

/// Area-weighted unit vertex normals of a closed, outward-wound mesh (3×V).
Eigen::Matrix3Xd calcVertexNormals(const TriangleMesh& mesh);

/// The box of `mesh` padded by `padding_fraction` of its largest side on every side.
Eigen::AlignedBox3d calcPaddedBox(const TriangleMesh& mesh, double padding_fraction);

/// Signed distances s(p) of the columns of `points_mm` for fitting and measuring: |s| is the
/// distance to the closest point of the mesh (`distance`), the side is the winding number's
/// (`winding`, inside where w > ½). The sign of the closest feature's pseudo-normal, which
/// MeshDistance gives, is right for a clean closed mesh, but a fold or a sliver (two sheets
/// back to back) turns it over in a whole cone behind it: on the psoas major it called 0.6 %
/// of the padded box inside, up to 92 mm from the muscle, and the fit filled those cones.
/// `resigned`, if given, receives how many points the two signs disagree on.
Eigen::VectorXd calcSolidSignedDistances(const MeshDistance& distance, const WindingNumber& winding,
                                         const Eigen::Matrix3Xd& points_mm, int* resigned = nullptr);

/// Check points start at this index of the Halton sequence: apart from the fitting samples
/// (from 1) and the metric points (from 10⁷).
constexpr std::uint64_t kBandHaltonStart = 1'000'000;
/// makeBandPoints tries at most this many Halton points per point it is asked for.
constexpr long long kMaxBandPointsTried = 100;

/// Up to `count` points of the Halton sequence (from kBandHaltonStart) in `box_mm` that lie
/// within `band_mm` of the mesh, in sequence order: an even cover of the band. Fewer when
/// kMaxBandPointsTried·count points of the box hold fewer.
Eigen::Matrix3Xd makeBandPoints(const Eigen::AlignedBox3d& box_mm, const MeshDistance& distance,
                                double band_mm, int count);

/// At most this many layers of check points along the normals.
constexpr std::size_t kMaxCheckLayers = 16;

/// Offsets of the check layers along the vertex normals: 2d, 4d, 8d, … below τ (mm).
std::vector<double> calcCheckLayerOffsets(double normal_offset_mm, double clamp_mm);

/// The fit's targets t = clamp(−s, −τ, τ) of signed distances s (negative inside) for the clamp τ.
Eigen::VectorXd calcTargets(const Eigen::VectorXd& signed_distance_mm, double clamp_mm);

/// Builds the samples for `mesh_M` (already in the muscle frame), its sides from `winding`. Targets come
/// from the exact signed distance (so an inward offset that crosses a thin
/// part still gets its true value), signed by calcSolidSignedDistances. The check
/// points are settings.check_band_samples band points (makeBandPoints, band τ) followed,
/// when settings.check_normal_layers, by every vertex moved by −o and +o along its normal
/// for each o of calcCheckLayerOffsets.
SampleSet buildSamples(const TriangleMesh& mesh_M, const MeshDistance& distance, const WindingNumber& winding,
                       const FitSettings& settings);

}  // namespace rbfmuscle
