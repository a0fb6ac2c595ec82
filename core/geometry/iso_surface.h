// SPDX-License-Identifier: Apache-2.0
#pragma once
/// @file
/// Triangle mesh of the zero level set of a scalar field sampled on a regular grid.
#include <array>
#include <cstdint>
#include <functional>
#include <vector>

#include "geometry/triangle_mesh.h"

namespace rbfmuscle {

/// Batch field evaluation: fills `values` (resized by the callee to N) with f at each
/// column of the 3×N `points_mm`.
using ScalarFieldFn = std::function<void(const Eigen::Matrix3Xd& points_mm, Eigen::VectorXd& values)>;

/// Nodes per axis of the grid extractIsoSurface samples over `box_mm` with spacing
/// `cell_mm`: max(2, ⌈size/cell⌉ + 1) (the last layer may pass box.max() by less than a
/// cell). Anything that must see the same nodes as the extraction uses this.
std::array<std::int64_t, 3> countIsoSurfaceNodes(const Eigen::AlignedBox3d& box_mm, double cell_mm);

/// Refuses a grid of more than 10⁹ nodes over `box_mm` with spacing `cell_mm`, the most
/// extractIsoSurface samples: callers that extract later check it before their long work.
/// @throws std::invalid_argument "a surface cell of C mm takes a grid of I×J×K nodes, …".
void checkIsoSurfaceGrid(const Eigen::AlignedBox3d& box_mm, double cell_mm);

/// Extracts the surface {f = 0} of `field`, with inside = {f > 0}, as a mesh wound outward
/// (normals point towards decreasing f).
///
/// Method: marching tetrahedra on a grid of nodes box.min() + cell_mm·(i, j, k),
/// i ≤ ⌈size/cell⌉ (the last layer may pass box.max() by less than a cell); each cube is
/// split into the 6 tetrahedra of the Kuhn/Freudenthal triangulation around its (0,0,0)–(1,1,1)
/// diagonal, identical in every cube, so neighbouring cubes agree on their shared face
/// diagonals. Each cut grid edge gets one vertex, keyed by (low node, direction), so the
/// mesh is indexed without duplicates, and the output is a closed 2-manifold whenever
/// f ≤ 0 on the whole grid boundary (a node with f = 0 counts as outside). It is always
/// closed: nodes on the box faces with f > 0 are taken as f = 0, so a surface that
/// leaves the box is cut flat there; their number goes to `clipped_nodes`. The vertex on an
/// edge is the linear root t = f₀/(f₀ − f₁), snapped into [10⁻³, 1 − 10⁻³] rather than onto
/// a node: no two vertices coincide and no triangle is degenerate, so nothing is dropped and
/// no hole opens (position error ≤ 10⁻³ edge lengths).
/// The field is evaluated one z layer of nodes at a time (two layers in memory).
/// @param field   batch evaluator.
/// @param box_mm  region to mesh (mm); non-empty.
/// @param cell_mm grid spacing (mm), > 0; at most 10⁹ nodes.
/// @param clipped_nodes if given, receives the number of box-face nodes with f > 0.
/// @param vertex_edges if given, receives per vertex the grid edge it lies on, as
///        id(lower node)·8 + d, id = i + nᵢ(j + nⱼk), d = the edge's direction as a mask (1 = +x,
///        2 = +y, 4 = +z; 3, 5, 6, 7 the diagonals): the same edge in two extractions on one
///        lattice carries both surfaces' crossings.
/// @throws std::invalid_argument for an empty box, cell_mm ≤ 0 or too many nodes;
///         std::runtime_error if the field returns a wrong count or a non-finite value.
TriangleMesh extractIsoSurface(const ScalarFieldFn& field, const Eigen::AlignedBox3d& box_mm,
                               double cell_mm, std::int64_t* clipped_nodes = nullptr,
                               std::vector<std::uint64_t>* vertex_edges = nullptr);

}  // namespace rbfmuscle
