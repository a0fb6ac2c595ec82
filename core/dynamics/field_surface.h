#pragma once
/// @file
/// The zero set of a Gaussian field as a triangle mesh, from one separable grid evaluation.
#include "geometry/triangle_mesh.h"
#include "rbf/gaussian_field.h"

#include <Eigen/Geometry>

#include <cstdint>
#include <vector>

namespace rbfmuscle {

/// {f = 0} of `field` by extractIsoSurface over `box_mm` with spacing `cell_mm`. The field is
/// evaluated on every node by separable sums (field_on_grid.h), about 15× faster than node by
/// node; the extraction then reads its layers from them. Same mesh as extracting with the field.
/// `vertex_edges`: as extractIsoSurface's.
/// @throws std::invalid_argument if cell_mm ≤ 0 or the box is empty.
TriangleMesh extractFieldSurface(const GaussianField& field, const Eigen::AlignedBox3d& box_mm, double cell_mm,
                                 std::vector<std::uint64_t>* vertex_edges = nullptr);

}  // namespace rbfmuscle
