#pragma once
/// @file
/// The part of a triangle mesh near a set of points (e.g. a bone's surface near a muscle's
/// attachment landmarks).
#include <Eigen/Core>

#include "geometry/triangle_mesh.h"

namespace rbfmuscle {

/// The triangles of `mesh` whose three corners each lie within `radius_mm` of some point of
/// `points_mm` (3×K, the mesh's frame), in their order, with only the vertices they use
/// (in their order). Empty when none is that close (or K = 0).
TriangleMesh keepTrianglesNear(const TriangleMesh& mesh, const Eigen::Matrix3Xd& points_mm, double radius_mm);

}  // namespace rbfmuscle
