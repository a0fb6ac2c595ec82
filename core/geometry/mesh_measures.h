// SPDX-License-Identifier: Apache-2.0
#pragma once
/// @file
/// Global measures of a triangle mesh: enclosed volume, surface area, components, vertex normals.
#include "geometry/triangle_mesh.h"

#include <vector>

namespace rbfmuscle {

/// Signed enclosed volume (mm³) by the divergence theorem:
/// V = (1/6) Σₜ (a − o) · ((b − o) × (c − o)) over triangles (a, b, c), with o the bounding-box
/// centre (exact for a closed mesh whatever o; o only reduces round-off far from the origin).
/// Positive for a closed mesh wound outward, negative if wound inward.
double calcVolume(const TriangleMesh& mesh);

/// Total surface area (mm²): Σₜ ½ ‖(b − a) × (c − a)‖.
double calcArea(const TriangleMesh& mesh);

/// Number of connected pieces: triangles are connected when they share a vertex.
/// Vertices used by no triangle are not counted.
int countComponents(const TriangleMesh& mesh);

/// Signed enclosed volume (mm³) of each connected piece (as countComponents), largest first:
/// a surface that came apart shows its crumbs here, a cavity as a negative volume.
std::vector<double> calcComponentVolumes(const TriangleMesh& mesh);

/// Bounding-box diagonal (mm) of each connected piece (as countComponents), largest first: how
/// far across each piece is, so a check can leave out pieces below a mesh's resolution.
std::vector<double> calcComponentSizes(const TriangleMesh& mesh);

/// Area-weighted vertex normals: column v of `out` (3×V, resized) is Σ (b − a) × (c − a) over the
/// triangles (a, b, c) at vertex v, unnormalised (length twice their area; 0 at a vertex no
/// triangle uses), outward for a mesh wound outward.
void calcVertexNormals(const TriangleMesh& mesh, Eigen::Matrix3Xd& out);

}  // namespace rbfmuscle
