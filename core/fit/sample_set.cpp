// SPDX-License-Identifier: Apache-2.0
#include "fit/sample_set.h"

#include <algorithm>

#include "fit/halton.h"
#include "geometry/mesh_distance.h"
#include "geometry/winding_number.h"

namespace rbfmuscle {

Eigen::Matrix3Xd calcVertexNormals(const TriangleMesh& mesh) {
  Eigen::Matrix3Xd normals = Eigen::Matrix3Xd::Zero(3, mesh.vertices_mm.cols());
  for (Eigen::Index t = 0; t < mesh.triangles.cols(); ++t) {
    const Eigen::Vector3i tri = mesh.triangles.col(t);
    const Eigen::Vector3d a = mesh.vertices_mm.col(tri[0]);
    // Cross product length = 2 × area: area weighting comes for free.
    const Eigen::Vector3d n =
        (mesh.vertices_mm.col(tri[1]) - a).cross(mesh.vertices_mm.col(tri[2]) - a);
    for (int c = 0; c < 3; ++c) normals.col(tri[c]) += n;
  }
  for (Eigen::Index v = 0; v < normals.cols(); ++v) {
    const double length = normals.col(v).norm();
    if (length > 0) normals.col(v) /= length;
  }
  return normals;
}

Eigen::AlignedBox3d calcPaddedBox(const TriangleMesh& mesh, double padding_fraction) {
  Eigen::AlignedBox3d box(mesh.vertices_mm.rowwise().minCoeff(),
                          mesh.vertices_mm.rowwise().maxCoeff());
  const double pad = padding_fraction * box.sizes().maxCoeff();
  box.min().array() -= pad;
  box.max().array() += pad;
  return box;
}

Eigen::VectorXd calcSolidSignedDistances(const MeshDistance& distance, const WindingNumber& winding,
                                         const Eigen::Matrix3Xd& points_mm, int* resigned) {
  Eigen::VectorXd s = distance.calcSignedDistances(points_mm);
  const Eigen::Array<bool, Eigen::Dynamic, 1> inside = winding.calcInside(points_mm);
  int disagree = 0;
  for (Eigen::Index i = 0; i < s.size(); ++i) {
    if (s[i] == 0.0 || (s[i] < 0.0) == inside[i]) continue;
    s[i] = -s[i];
    ++disagree;
  }
  if (resigned) *resigned = disagree;
  return s;
}

Eigen::Matrix3Xd makeBandPoints(const Eigen::AlignedBox3d& box_mm, const MeshDistance& distance,
                                double band_mm, int count) {
  constexpr int kChunk = 1 << 15;
  const long long max_tried = kMaxBandPointsTried * static_cast<long long>(std::max(count, 0));
  std::vector<Eigen::Vector3d> kept;
  kept.reserve(static_cast<std::size_t>(std::max(count, 0)));
  std::vector<char> near(kChunk);
  for (long long first = 0; first < max_tried && static_cast<int>(kept.size()) < count; first += kChunk) {
    const Eigen::Matrix3Xd pool = makeHaltonPoints(box_mm, kChunk, kBandHaltonStart + static_cast<std::uint64_t>(first));
#pragma omp parallel for schedule(static)
    for (int i = 0; i < kChunk; ++i) near[i] = distance.calcUnsignedDistanceWithin(pool.col(i), band_mm) <= band_mm;
    for (int i = 0; i < kChunk && static_cast<int>(kept.size()) < count; ++i)
      if (near[i]) kept.push_back(pool.col(i));
  }
  Eigen::Matrix3Xd points(3, static_cast<Eigen::Index>(kept.size()));
  for (std::size_t i = 0; i < kept.size(); ++i) points.col(static_cast<Eigen::Index>(i)) = kept[i];
  return points;
}

std::vector<double> calcCheckLayerOffsets(double normal_offset_mm, double clamp_mm) {
  std::vector<double> offsets;
  for (double offset = 2.0 * normal_offset_mm; offset < clamp_mm && offsets.size() < kMaxCheckLayers; offset *= 2.0)
    offsets.push_back(offset);
  return offsets;
}

Eigen::VectorXd calcTargets(const Eigen::VectorXd& signed_distance_mm, double clamp_mm) {
  return (-signed_distance_mm).cwiseMax(-clamp_mm).cwiseMin(clamp_mm);
}

SampleSet buildSamples(const TriangleMesh& mesh_M, const MeshDistance& distance, const WindingNumber& winding,
                       const FitSettings& settings) {
  const Eigen::Index V = mesh_M.vertices_mm.cols();
  const Eigen::Matrix3Xd normals = calcVertexNormals(mesh_M);
  SampleSet samples;
  samples.box_mm = calcPaddedBox(mesh_M, settings.padding_fraction);
  const Eigen::Matrix3Xd halton = makeHaltonPoints(samples.box_mm, settings.halton_samples);

  const Eigen::Index S = 3 * V + halton.cols();
  samples.points_mm.resize(3, S);
  samples.points_mm.leftCols(V) = mesh_M.vertices_mm;
  samples.points_mm.middleCols(V, V) = mesh_M.vertices_mm - settings.normal_offset_mm * normals;
  samples.points_mm.middleCols(2 * V, V) = mesh_M.vertices_mm + settings.normal_offset_mm * normals;
  samples.points_mm.rightCols(halton.cols()) = halton;
  samples.kinds.assign(S, SampleKind::kHalton);
  std::fill_n(samples.kinds.begin(), V, SampleKind::kSurface);
  std::fill_n(samples.kinds.begin() + V, V, SampleKind::kOffsetIn);
  std::fill_n(samples.kinds.begin() + 2 * V, V, SampleKind::kOffsetOut);

  samples.signed_distance_mm =
      calcSolidSignedDistances(distance, winding, samples.points_mm, &samples.resigned_samples);
  // Vertices lie on the surface by definition; the query only adds round-off there.
  samples.signed_distance_mm.head(V).setZero();
  const double tau = settings.clamp_mm;
  samples.target = calcTargets(samples.signed_distance_mm, tau);

  const Eigen::Matrix3Xd band = makeBandPoints(samples.box_mm, distance, tau, settings.check_band_samples);
  const std::vector<double> layers =
      settings.check_normal_layers ? calcCheckLayerOffsets(settings.normal_offset_mm, tau) : std::vector<double>{};
  const Eigen::Index L = static_cast<Eigen::Index>(layers.size());
  samples.check_points_mm.resize(3, band.cols() + 2 * L * V);
  samples.check_points_mm.leftCols(band.cols()) = band;
  for (Eigen::Index l = 0; l < L; ++l) {
    samples.check_points_mm.middleCols(band.cols() + 2 * l * V, V) = mesh_M.vertices_mm - layers[l] * normals;
    samples.check_points_mm.middleCols(band.cols() + (2 * l + 1) * V, V) = mesh_M.vertices_mm + layers[l] * normals;
  }
  samples.check_signed_distance_mm = calcSolidSignedDistances(distance, winding, samples.check_points_mm);
  samples.check_target = calcTargets(samples.check_signed_distance_mm, tau);
  return samples;
}

}  // namespace rbfmuscle
